"""The application layer: command line, run directories, ensembles and plots.

It sits above the methods (`gfmd`, `reference.fem`) and the core (`gfmd_contact.core`),
and nothing below imports it. `gfmd ...` and `python -m gfmd ...` run
`gfmd_contact.cli.main`.
"""
