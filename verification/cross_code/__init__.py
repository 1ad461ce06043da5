"""Cross-code verification: the same cases, references and tolerances for every contact code behind the
solver-adapter protocol (`verification.solvers`).

`cases` defines each case (its problems, its independent reference, its errors, its tolerances derived from the
stored convergence data); `outcomes` runs a case against one solver and keeps the records, one file per solver
in the report directory, so that runs of several solvers combine on one page (`verification.report_cross_code`).
"""
