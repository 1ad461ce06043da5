"""The study subcommands: `gfmd study run` (one study or a suite of them), `gfmd study plot`, `gfmd study report`.

Units: SI everywhere (see gfmd_contact.core.conventions); studies are TOML files (gfmd_contact.app.study_file).
"""

from __future__ import annotations

import sys
from pathlib import Path

from .cli_common import count, interrupt_signals, note, wait_option


def _cmd_study_run(args):
    from .app.study import failure_summary, load_study, run_study

    if len(args.study) > 1:
        return _cmd_study_suite(args)
    args.study = args.study[0]
    # its size first (refused above the limit unless --yes), then every parameter set validated, before any compute
    study = load_study(args.study, yes=args.yes, note=None if args.quiet else note)
    out = Path(args.out or f"results/{study.name}")
    n_tasks = len(study.tasks)
    where = _where(args)
    print(f"study {study.name!r}: {len(study.sets)} parameter set(s), {n_tasks} task(s) on {where}; "
          f"results go to {out}/", file=sys.stderr)
    command = _rerun_command(args.study, out, args)
    from .app.study import done_tasks

    record, code = _interruptible(
        lambda: run_study(study, out, workers=args.workers, scheduler=args.scheduler, progress=not args.quiet,
                          command=command, wait=getattr(args, "wait", 0)),
        command, lambda: f"{done_tasks(study, out)} of {n_tasks} task(s) complete in {out}/tasks")
    if code is not None:
        return code
    unconverged = [t for t in record["tasks"] if t["all_converged"] is False]
    print(f"study {study.name!r}: {record['tasks_total']} task(s): {record['tasks_reused']} reused, "
          f"{record['tasks_run']} run ({record['steps_reused']} saved load steps continued), "
          f"{record['tasks_failed']} failed; {out}/study.csv, summary.csv, summary.nc, study.json",
          file=sys.stderr)
    for t in unconverged:
        print(f"WARNING: set {t['set']}, realization {t['realization']} (task {t['key']}): non-converged steps: "
              f"{'; '.join(t['messages'][:3])}", file=sys.stderr)
    if record["tasks_failed"]:
        print(f"{record['tasks_failed']} task(s) failed (tracebacks in {out}/study.json):", file=sys.stderr)
        for line in failure_summary(record):
            print(f"  - {line}", file=sys.stderr)
    return 1 if record["tasks_failed"] or unconverged else 0


def _interruptible(run, command, done):
    """(run(), None) under Ctrl-C and SIGTERM; (None, exit code) after a disk error (2) or an interrupt (130),
    saying what is on disk (`done()`: the tasks complete) and the `command` that continues."""
    from .app.safe_files import WriteFailed

    try:
        with interrupt_signals():
            return run(), None
    except WriteFailed as exc:
        print(f"gfmd: error: {exc}; the files written before are intact: free space or fix the permissions, then "
              f"continue with: {command}", file=sys.stderr)
        return None, 2
    except KeyboardInterrupt:
        print(f"\ngfmd: interrupted: {done()}, the others keep their saved load steps; continue with: {command}",
              file=sys.stderr)
        return None, 130


def _where(args):
    """Where a study's tasks run, in words (the --scheduler or the local cluster)."""
    return f"the Dask scheduler at {args.scheduler}" if args.scheduler else \
        f"a local Dask cluster of {args.workers or 'all'} worker process(es)"


def _rerun_command(files, out, args):
    """The `gfmd study run` command line that continues this run (printed after an interrupt or a disk error)."""
    return f"gfmd study run {files} --out {out}" + (f" --workers {args.workers}" if args.workers else "") \
        + (f" --scheduler {args.scheduler}" if args.scheduler else "")


def _cmd_study_suite(args):
    """`gfmd study run A.toml B.toml ... --out DIR`: the studies as one suite (gfmd_contact.app.study_suite)."""
    import json

    from .app.study import failure_summary, load_study
    from .app.study_suite import check_names, run_suite, suite_done

    if not args.out:
        raise ValueError("several study files need --out DIR (each study goes to DIR/<study name>/)")
    studies = [load_study(path, yes=args.yes, note=None if args.quiet else note)  # validated before any compute
               for path in args.study]
    check_names(studies)
    out = Path(args.out)
    distinct = len({t.key for s in studies for t in s.tasks})
    where = _where(args)
    print(f"suite of {len(studies)} studies ({', '.join(s.name for s in studies)}): "
          f"{sum(len(s.tasks) for s in studies)} task(s), {distinct} distinct, on {where}; results go to "
          f"{out}/<study name>/", file=sys.stderr)
    command = _rerun_command(' '.join(args.study), out, args)
    suite, code = _interruptible(
        lambda: run_suite(studies, out, workers=args.workers, scheduler=args.scheduler, progress=not args.quiet,
                          command=command, wait=getattr(args, "wait", 0)),
        command, lambda: f"{suite_done(studies, out)} of {distinct} distinct task(s) complete under {out}")
    if code is not None:
        return code
    bad = 0
    for row in suite["studies"]:
        record = json.loads((out / row["dir"] / "study.json").read_text())
        print(f"study {row['name']!r}: {row['tasks']} task(s): {row['tasks_reused']} reused, {row['tasks_run']} run, "
              f"{row['tasks_linked']} linked from a sibling study, {row['tasks_failed']} failed; {out / row['dir']}/",
              file=sys.stderr)
        for t in record["tasks"]:
            if t["all_converged"] is False and t["status"] != "linked":  # named once, where it ran
                bad += 1
                print(f"WARNING: {row['name']} set {t['set']}, realization {t['realization']} (task {t['key']}): "
                      f"non-converged steps: {'; '.join(t['messages'][:3])}", file=sys.stderr)
        for line in failure_summary(record):
            print(f"  - {row['name']}: {line}", file=sys.stderr)
    print(f"suite: {suite['distinct_tasks']} distinct task(s), {suite['tasks_run']} run, {suite['tasks_linked']} "
          f"linked, {suite['tasks_failed']} failed, {suite['timings']['wall_s']:.1f} s; {out}/suite.json",
          file=sys.stderr)
    return 1 if suite["tasks_failed"] or bad else 0


def _cmd_study_plot(args):
    from .app.study_plots import plot_study

    for path in plot_study(args.dir, fmt=args.format, over=args.over):
        print(f"wrote {path}")
    return 0


def _cmd_study_report(args):
    from .app.study_report import claims_text, write_report

    path = write_report(args.dirs, out=args.out)
    for line in claims_text(args.dirs):
        print(line)
    print(f"wrote {path}")
    return 0


def add_study_commands(sub):
    """`gfmd study run | plot | report` on the command line's subparsers `sub`."""
    study = sub.add_parser("study", help="parameter studies: a grid of scenes × realizations on Dask")
    study_sub = study.add_subparsers(dest="study_command", required=True)
    srun = study_sub.add_parser("run", help="run (or continue) a study file's tasks and write study.csv, "
                                "summary.csv, summary.nc, study.json")
    srun.add_argument("study", nargs="+", help="study TOML file (base scene + [axes], optional [zip]); several: "
                      "one suite, each study in DIR/<study name>/, each distinct task computed once")
    srun.add_argument("--out", help="study directory (default results/<study name>); with several files the "
                      "suite's directory (required); rerun to resume")
    srun.add_argument("--workers", type=count(1), default=None,
                      help="worker processes of the local Dask cluster (default: all cores)")
    srun.add_argument("--scheduler", metavar="ADDRESS",
                      help="send the tasks to an existing Dask cluster (e.g. tcp://HOST:8786) instead; --out must "
                           "be on a file system every worker sees")
    srun.add_argument("--quiet", action="store_true", help="no progress bar")
    srun.add_argument("--yes", action="store_true", help="run a study of more tasks than the limit "
                      "(gfmd_contact.app.study_file.MAX_TASKS) without being refused")
    wait_option(srun, "study directory")
    srun.set_defaults(func=_cmd_study_run)
    splot = study_sub.add_parser("plot", help="seed-style figures of a study directory (into DIR/figures/): "
                                 "overlays of the parameter sets, hard-wall reference, κ fit, snapshot")
    splot.add_argument("dir", help="study directory (gfmd study run --out DIR)")
    splot.add_argument("--format", choices=("png", "svg"), default="png", help="file format (default png)")
    splot.add_argument("--over", metavar="AXIS",
                       help="one panel per combination of the other varied keys, one curve per value of AXIS "
                            "(a dotted key of the study, e.g. surface.h_rms); default: every set in one panel")
    splot.set_defaults(func=_cmd_study_plot)
    sreport = study_sub.add_parser("report", help="the seed's claims measured on study directories: "
                                   "DIR/report.html (self-contained) and the claims table on stdout")
    sreport.add_argument("dirs", nargs="+", metavar="DIR", help="study directories (several: one merged page)")
    sreport.add_argument("--out", help="the HTML page (default: the first DIR's report.html)")
    sreport.set_defaults(func=_cmd_study_report)
