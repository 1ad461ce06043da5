"""Command line: `gfmd run | plot | scene | verify | study run | study plot | study report` (also `python -m gfmd`).

Units: SI everywhere (see gfmd_contact.core.conventions); scenes are TOML files (gfmd_contact.core.scene).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

from gfmd_contact.core.scene import SceneError, default_scene, example_scene_text, load_scene

from .cli_common import count, interrupt_signals, note, wait_option
from .cli_study import add_study_commands


def _checks(scene):
    """Every check `gfmd run` makes before compute (gfmd_contact.check); (warnings, notes)."""
    from gfmd_contact import check

    return check(scene)


def _gfmd_description(scene):
    """GFMD's algorithms for the scene in words ("GFMD ncg (then fire where it stalls)"), as gfmd.chains picks them."""
    from gfmd.loading import describe_scene

    return describe_scene(scene)


def _method_overrides(args):
    """--method as scene keys (gfmd_contact.scenes.METHOD_CHOICES): fe → method.name; fire/verlet → GFMD
    with solver.method (the law's production chain / damped Verlet)."""
    from gfmd_contact.scenes import method_changes

    return method_changes(args.method)


def _resume_command(args, out):
    method = f" --method {args.method}" if args.method else ""
    scene = f" {args.scene}" if args.scene else ""
    return f"gfmd run{scene} --out {out}{method} --resume"


def _on_disk(scene, out):
    """One line: what an interrupted run left in `out`."""
    from .app import io

    parts = [io.load_part(out, scene, i) for i in range(scene.surface.realizations)]
    done = sum(1 for p in parts if p is not None and p[2])
    partial = [p for p in parts if p is not None and not p[2]]
    steps = sum(len(p[0].curve["step"]) for p in partial)
    return (f"{done} of {scene.surface.realizations} realization(s) complete, {len(partial)} partial "
            f"({steps} load steps) saved in {out}")


def _scene_from_args(args):
    if args.scene:
        if Path(args.scene).is_dir():
            raise SceneError(f"scene {args.scene!r} is a directory, not a TOML scene file "
                             "(to continue a run in it: gfmd run --out DIR --resume)")
        return load_scene(args.scene)
    if args.resume and args.out and (Path(args.out) / "scene.toml").is_file():
        return load_scene(Path(args.out) / "scene.toml")  # resume the scene of the run directory
    return default_scene()


def _cmd_run(args):
    import dataclasses
    import json

    from .app import io

    scene = _scene_from_args(args)
    overrides = _method_overrides(args)
    if args.realizations is not None:
        overrides["surface.realizations"] = args.realizations
    if overrides:
        scene = scene.replace(**overrides)
    if args.resume and not args.scene and args.out and (Path(args.out) / "meta.json").is_file():
        name = json.loads((Path(args.out) / "meta.json").read_text()).get("scene_name", scene.name)
        scene = dataclasses.replace(scene, name=name)
    warnings, notes = _checks(scene)  # refusals happen here, before any file is touched
    from gfmd_contact.core.cost import check_memory

    check_memory(scene, args.workers)  # the worker processes this run starts
    out = Path(args.out or f"results/{scene.name}")
    if out.exists() and not out.is_dir():
        raise io.RunDirError(f"--out {str(out)!r} is an existing file, not a directory: choose another --out")
    from .app import safe_files

    advice = ("wait for it to end (or add --wait to wait for it), or stop it first; to run beside it, choose "
              "another --out")
    try:
        with safe_files.locked(out, wait=getattr(args, "wait", 0), what="run directory", advice=advice, note=note):
            return _run_locked(args, scene, out, warnings, notes)
    except safe_files.WriteFailed as exc:
        print(f"gfmd: error: {exc}; the files written before are intact: free space or fix the permissions, then "
              f"continue with: {_resume_command(args, out)}", file=sys.stderr)
        return 2


def _draw(out):
    """The run's figures; a failure to write them (the results are complete) is exit 2 with what to do."""
    from .app.plots import plot_run
    from .app.safe_files import WriteFailed

    try:
        for path in plot_run(out):
            print(f"wrote {path}", file=sys.stderr)
    except WriteFailed as exc:
        print(f"gfmd: error: {exc}; the results in {out}/ are complete: make {out / 'plots'} writable (or free "
              f"space), then draw the figures with: gfmd plot {out}", file=sys.stderr)
        return 2
    return 0


def _run_locked(args, scene, out, warnings, notes):
    """`gfmd run` in the locked run directory `out`."""
    from .app import io

    out = io.prepare_run_dir(out, scene, resume=args.resume, overwrite=args.overwrite)
    if args.resume and io.run_complete(out):  # its figures may be missing (a kill, a full disk): drawn again
        print(f"{out}: this run is complete; nothing to resume"
              + ("" if args.no_plot else "; drawing its figures again (--no-plot skips them)"), file=sys.stderr)
        return 0 if args.no_plot else _draw(out)
    for w in warnings:
        print(f"WARNING: {w}", file=sys.stderr)
    for n in notes:
        print(f"note: {n}", file=sys.stderr)
    method = "FE" if scene.method.name == "fe" else _gfmd_description(scene)
    from gfmd_contact.core.cost import describe, estimate_peak_memory, estimate_seconds

    estimates = describe(estimate_peak_memory(scene, args.workers), estimate_seconds(scene, args.workers))
    print(f"scene {scene.name!r}: {scene.surface.realizations} realization(s), {scene.loading.steps} load steps, "
          f"method {method}, {estimates}; results go to {out}/ as they "
          "are computed", file=sys.stderr)
    try:
        from gfmd_contact.runs import compute  # the one path of gfmd run and gfmd_contact.run

        with interrupt_signals():
            results, resume, elapsed = compute(scene, out, workers=args.workers, progress=not args.quiet,
                                               note=note)
    except KeyboardInterrupt:
        print(f"\ngfmd: interrupted: {_on_disk(scene, out)}; continue with: {_resume_command(args, out)}",
              file=sys.stderr)
        return 130
    if resume["realizations_reused"] or resume["steps_reused"]:
        print(f"resumed: {resume['realizations_reused']} realization(s) and {resume['steps_reused']} load steps "
              "reused from the interrupted run", file=sys.stderr)
    print(f"model solved: {results[0].model}", file=sys.stderr)
    for reason in _shown(results[0].reasons, getattr(args, "verbose", False)):
        print(f"  - {reason}", file=sys.stderr)
    bad = [m for r in results for m in r.messages]
    for m in bad:
        print(f"WARNING: {m}", file=sys.stderr)
    if not args.no_plot and _draw(out):
        return 2
    print(f"results in {out}/ (curve.csv, mean_curve.csv, fields.npz, scene.toml, meta.json) after {elapsed:.1f} s",
          file=sys.stderr)
    return 1 if any(not r.all_converged for r in results) else 0  # a fallback that converged is no failure


def _shown(reasons, verbose):
    """The reason lines `gfmd run` prints: the model's and the algorithms'; the process's internals (FFT backends,
    heap, BLAS threads: `gfmd.loading.INTERNALS`, kept in meta.json) only with --verbose."""
    from gfmd.loading import internal

    return [r for r in reasons if verbose or not internal(r)]


def _cmd_plot(args):
    from .app.plots import plot_run

    for path in plot_run(args.dir, snapshot_delta=args.delta, fmt=args.format, realization=args.realization,
                         wait=getattr(args, "wait", 0)):
        print(f"wrote {path}")
    return 0


def _check_topography(scene, scene_file):
    """Print the prepared topography's statistics and write its figure next to the scene file."""
    from gfmd_contact.app.topography_plots import write_check_figure
    from gfmd_contact.core.topography_stats import check_lines, prepared_file

    prepared = prepared_file(scene)
    for line in check_lines(scene, prepared):
        print(f"topography: {line}")
    try:
        print(f"topography: wrote {write_check_figure(scene, prepared, scene_file)} (the prepared topography and its "
              "PSD)")
    except OSError as exc:
        print(f"note: the topography figure was not written ({exc.strerror or exc})", file=sys.stderr)


def _cmd_scene(args):
    if args.example:
        print(example_scene_text(), end="")
        return 0
    if args.check:
        if Path(args.check).is_dir():
            raise SceneError(f"scene {args.check!r} is a directory, not a TOML scene file")
        scene = load_scene(args.check)
        scene = scene.replace(**_method_overrides(args)) if args.method else scene
        warnings, notes = _checks(scene)  # the same checks as `gfmd run`
        for w in warnings:
            print(f"WARNING: {w}", file=sys.stderr)
        for n in notes:
            print(f"note: {n}", file=sys.stderr)
        from gfmd_contact.core.stickiness import lines as stickiness_lines

        for line in stickiness_lines(scene):  # the diagnostics of gfmd_contact.core.stickiness (n/a: with the reason)
            print(f"stickiness: {line}")
        if scene.surface.kind == "file":  # a measured file: what was read and prepared, and its figure
            _check_topography(scene, args.check)
        size = (f"Nx × Ny = {scene.surface.nodes} × {scene.surface.nodes_y} (2+1-D)" if scene.surface.two_d
                else f"N = {scene.surface.nodes}")
        from gfmd_contact.core.cost import describe, estimate_peak_memory, estimate_seconds

        print(f"{args.check}: valid scene; surface {scene.surface.kind}, {size}, "
              f"law {scene.interface.law}, {describe(estimate_peak_memory(scene), estimate_seconds(scene))}"
              + (f"; {len(warnings)} warning(s)" if warnings else "")
              + (f"; {len(notes)} realization(s) stop early" if notes else ""))
        return 0
    print("use `gfmd scene --example` or `gfmd scene --check FILE`", file=sys.stderr)
    return 2


def _source_root():
    """The source checkout the package runs from, if it holds the verification suite, else None."""
    root = Path(__file__).resolve().parent.parent
    needed = (root / "conftest.py", root / "pyproject.toml", root / "verification" / "conftest.py")
    return root if all(p.is_file() for p in needed) else None


def _cmd_verify(args):
    """pytest on the verification suite: `pytest verification` in a source checkout, else the installed
    package's `pytest --pyargs verification` in this directory; then where the report is and its file:// URL."""
    import os

    from .app.safe_files import locked

    root = _source_root()
    reports = Path(args.report_dir or os.environ.get("GFMD_REPORT_DIR") or (root or Path.cwd()) / "reports").absolute()
    options = ["--report-dir", str(reports)] + (["--full"] if args.full else []) + ["--solver", args.solver]
    if root is not None:
        cmd, where = [sys.executable, "-m", "pytest", *options, "verification"], root
    else:  # the installed suite; -p: its options even where pytest's plugin autoload is off
        cmd, where = [sys.executable, "-m", "pytest", "-p", "verification.plugin", *options, "--pyargs",
                      "verification"], Path.cwd()
    cmd += args.pytest_args
    print(f"running {' '.join(cmd[2:])} in {where}; the report goes to {reports / 'index.html'}", file=sys.stderr)
    with locked(reports, wait=getattr(args, "wait", 0), what="report folder", command="gfmd verify",
                advice="wait for that `gfmd verify` to end (or add --wait to wait for it)"):
        index = reports / "index.html"
        before = index.stat().st_mtime_ns if index.is_file() else None
        code = subprocess.call(cmd, cwd=where)
    if index.is_file() and index.stat().st_mtime_ns != before:  # written by this run
        print(f"verification report: {index}; open it in a browser: {index.as_uri()}", file=sys.stderr)
    return code


def build_parser():
    parser = argparse.ArgumentParser(prog="gfmd", description="GFMD for rough adhesive contacts: line contacts "
                                     "(profiles) and 2+1-D surfaces, under displacement or force control, with "
                                     "finite-element and analytic references (SI units).")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a scene (default: the built-in default scene) and write results + plots")
    run.add_argument("scene", nargs="?", help="scene TOML file (omit for the built-in default scene)")
    run.add_argument("--out", help="output directory (default results/<scene name>)")
    run.add_argument("--method", choices=("fire", "verlet", "fe"),
                     help="fire: GFMD with the production algorithms for the scene's law (solver.method = \"fire\": "
                          "NCG, CG, Newton or FIRE); verlet: GFMD with damped Verlet throughout; fe: the FE "
                          "reference (method.name)")
    run.add_argument("--realizations", type=count(1), help="override surface.realizations (≥ 1)")
    run.add_argument("--workers", type=count(0), default=None,
                     help="processes (default output.workers; 0 = all cores)")
    run.add_argument("--resume", action="store_true",
                     help="continue an interrupted run in --out: finished realizations are reused, an interrupted one "
                          "continues from its last saved step (the scene file may be omitted: taken from --out)")
    run.add_argument("--overwrite", action="store_true", help="replace the results of an earlier run in --out")
    run.add_argument("--no-plot", action="store_true", help="skip the figures")
    wait_option(run, "run directory")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.add_argument("--verbose", action="store_true",
                     help="also print the process's internals (FFT backends and plans, heap, BLAS threads)")
    run.set_defaults(func=_cmd_run)
    plot = sub.add_parser("plot", help="seed-style figures of a run directory (into DIR/plots/)")
    plot.add_argument("dir")
    plot.add_argument("--delta", type=float, help="δ (m) of the interface snapshot (default: last saved step)")
    plot.add_argument("--format", choices=("png", "svg", "pdf"), default="png", help="file format (default png)")
    plot.add_argument("--realization", type=int, metavar="I",
                      help="realization of the interface snapshot, as in curve.csv's `realization` column "
                           "(default: the first one with saved fields)")
    wait_option(plot, "plot folder")
    plot.set_defaults(func=_cmd_plot)
    scene = sub.add_parser("scene", help="print a commented example scene or check a scene file")
    scene.add_argument("--example", action="store_true")
    scene.add_argument("--check", metavar="FILE", help="validate FILE with every check `gfmd run` makes")
    scene.add_argument("--method", choices=("fire", "verlet", "fe"), help="with --check: also the method's checks")
    scene.set_defaults(func=_cmd_scene)
    verify = sub.add_parser("verify", help="run the verification suite (pytest verification; installed: pytest "
                            "--pyargs verification) and write its report (reports/index.html)")
    verify.add_argument("--full", action="store_true", help="include the expensive studies")
    verify.add_argument("--report-dir", metavar="DIR", help="where the report goes (default: $GFMD_REPORT_DIR, else "
                        "reports/ in the source checkout or, for an installed package, in this directory)")
    verify.add_argument("--solver", default="gfmd", metavar="NAME",
                        help="the contact code the cross-code cases run against (gfmd, fe, tamaas, contactmechanics, "
                             "or one registered in the entry-point group gfmd_contact.solvers; default gfmd)")
    verify.add_argument("pytest_args", nargs="*",
                        help="passed to pytest (after --, e.g. gfmd verify -- -x -k westergaard)")
    wait_option(verify, "report folder")
    verify.set_defaults(func=_cmd_verify)
    add_study_commands(sub)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        from .app.checkpoints import checkpoint_seconds

        checkpoint_seconds()  # a bad $GFMD_CHECKPOINT_SECONDS is refused before any compute
        return args.func(args)
    except (SceneError, ValueError, OSError) as exc:
        print(f"gfmd: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("\ngfmd: interrupted before any result was computed", file=sys.stderr)
        return 130
