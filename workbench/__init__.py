"""The application layer: command line, run directories, ensembles and plots.

It sits above the methods (`gfmd`, `reference.fem`) and the core (`contact`),
and nothing below imports it. `gfmd ...` and `python -m gfmd ...` run
`workbench.cli.main`.
"""
