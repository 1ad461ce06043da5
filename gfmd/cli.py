"""Command line: `gfmd run | plot | scene | verify` (also `python -m gfmd`).

Units: SI everywhere (see gfmd.conventions); scenes are TOML files (gfmd.scene).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

from .scene import SceneError, default_scene, example_scene_text, load_scene


def _run_fe(scene, out, quiet=False):
    """FE reference on every realization (serial, progress bar per load step); VTU + PVD per realization
    under out/vtu/realization<i>/ (reference.fem.export_vtu)."""
    from tqdm import tqdm

    from reference.fem import export_vtu, run_realization as run_fe  # optional reference method

    results = []
    for i in range(scene.surface.realizations):
        with tqdm(total=scene.loading.steps + 1, desc=f"FE realization {i}", unit="step", disable=quiet) as bar:
            result = run_fe(scene, i, progress=lambda k, steps: bar.update(1))
        files = export_vtu(result, out / "vtu" / f"realization{i}")
        print(f"wrote {len(files)} VTU/PVD files to {out / 'vtu' / f'realization{i}'}", file=sys.stderr)
        results.append(result)
    return results


def _cmd_run(args):
    scene = load_scene(args.scene) if args.scene else default_scene()
    overrides = {}
    if args.realizations is not None:
        overrides["surface.realizations"] = args.realizations
    if args.method in ("fire", "verlet"):
        overrides["solver.method"] = args.method
    if overrides:
        scene = scene.replace(**overrides)
    out = Path(args.out or f"results/{scene.name}")
    start = time.perf_counter()
    if args.method == "fe":
        results = _run_fe(scene, out, quiet=args.quiet)
    else:
        from .ensemble import run_ensemble

        print(f"scene {scene.name!r}: {scene.surface.realizations} realization(s), "
              f"{scene.loading.steps} load steps, solver {scene.solver.method}", file=sys.stderr)
        results = run_ensemble(scene, workers=args.workers, progress=not args.quiet)
    elapsed = time.perf_counter() - start
    from .io import write_run

    write_run(out, scene, results, timings={"total_s": elapsed, "workers": args.workers})
    print(f"model solved: {results[0].model}", file=sys.stderr)
    for reason in results[0].reasons:
        print(f"  - {reason}", file=sys.stderr)
    bad = [m for r in results for m in r.messages]
    for m in bad:
        print(f"WARNING: {m}", file=sys.stderr)
    if not args.no_plot:
        from .plots import plot_run

        for path in plot_run(out):
            print(f"wrote {path}", file=sys.stderr)
    print(f"results in {out}/ (curve.csv, fields.npz, scene.toml, meta.json) after {elapsed:.1f} s", file=sys.stderr)
    return 1 if bad else 0


def _cmd_plot(args):
    from .plots import plot_run

    for path in plot_run(args.dir, snapshot_delta=args.delta, fmt=args.format, realization=args.realization):
        print(f"wrote {path}")
    return 0


def _cmd_scene(args):
    if args.example:
        print(example_scene_text(), end="")
        return 0
    if args.check:
        scene = load_scene(args.check)
        print(f"{args.check}: valid scene; surface {scene.surface.kind}, N = {scene.surface.nodes}, "
              f"law {scene.interface.law}")
        return 0
    print("use `gfmd scene --example` or `gfmd scene --check FILE`", file=sys.stderr)
    return 2


def _cmd_verify(args):
    cmd = [sys.executable, "-m", "pytest", "verification"] + (["--full"] if args.full else []) + args.pytest_args
    return subprocess.call(cmd)


def build_parser():
    parser = argparse.ArgumentParser(prog="gfmd", description="GFMD for rough adhesive line contacts (SI units).")
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a scene (default: the built-in default scene) and write results + plots")
    run.add_argument("scene", nargs="?", help="scene TOML file (omit for the built-in default scene)")
    run.add_argument("--out", help="output directory (default results/<scene name>)")
    run.add_argument("--method", choices=("fire", "verlet", "fe"), help="override solver.method; fe = FE reference")
    run.add_argument("--realizations", type=int, help="override surface.realizations")
    run.add_argument("--workers", type=int, default=None, help="processes (default output.workers; 0 = all cores)")
    run.add_argument("--no-plot", action="store_true", help="skip the figures")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.set_defaults(func=_cmd_run)
    plot = sub.add_parser("plot", help="seed-style figures of a run directory (into DIR/plots/)")
    plot.add_argument("dir")
    plot.add_argument("--delta", type=float, help="δ (m) of the interface snapshot (default: last saved step)")
    plot.add_argument("--format", choices=("png", "svg", "pdf"), default="png", help="file format (default png)")
    plot.add_argument("--realization", type=int, metavar="I",
                      help="realization of the interface snapshot, as in curve.csv's `realization` column "
                           "(default: the first one with saved fields)")
    plot.set_defaults(func=_cmd_plot)
    scene = sub.add_parser("scene", help="print a commented example scene or check a scene file")
    scene.add_argument("--example", action="store_true")
    scene.add_argument("--check", metavar="FILE")
    scene.set_defaults(func=_cmd_scene)
    verify = sub.add_parser("verify", help="run the verification suite (pytest verification) and write reports/")
    verify.add_argument("--full", action="store_true", help="include the expensive studies")
    verify.add_argument("pytest_args", nargs="*")
    verify.set_defaults(func=_cmd_verify)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (SceneError, ValueError, FileNotFoundError) as exc:
        print(f"gfmd: error: {exc}", file=sys.stderr)
        return 2
