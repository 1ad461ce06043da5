"""Two versions of the code on the same whole ramp, side by side (issue 24): what a change did to CPU time.

Usage: python benchmarks/bench_versions.py --old DIR --new DIR [--label-old A] [--label-new B]
       [--classes normal hard-wall] [--size 17] [--realization 2] [--nu 0.45] [--phi 0.15] [--set KEY=VALUE ...]
       [--task] [--rounds 1] [--out FILE]

DIR: a source tree of the project (a git worktree of the version, e.g. ``git worktree add /tmp/old <commit>``); each
ramp runs in a process that imports the code (and `benchmarks.bench_adhesion_scaling.ramp`) from its tree alone.
Per class (bench_adhesion_scaling's seed base scene, φn* = 0.15: "cohesive" (c = 0), "hard-wall" (the hard wall on it),
"coupled" (c = 0.5, δt = 1 nm); --nu sets material.poisson_ratio, --phi interface.phi_n_star, --set any scene key) one
whole 201-step ramp per version (--task: the whole study task, `gfmd_contact.app.study_task.run_task`, with its per-step
observables, checkpoints and files), as two simultaneous processes pinned to one core each, then again with the cores
swapped (CPU time on this 2-core machine moves by up to 25 % with what runs on the other core, and the cores
differ): the CPU ratio new / old is the geometric mean of the two placements' ratios (the core's factor cancels), half
their difference the noise left; --rounds repeats the pair of placements. Per ramp: CPU s, iterations, FFT pairs, and
the states against the old version's (max |Δp̄| / max |p̄|).
Writes benchmarks/results/bench_versions_<label-new>.md (or --out).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before numpy: one thread

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
#: the classes: scene keys over bench_adhesion_scaling's "cohesive" class (as benchmarks/bench_fft.py's ramps)
CLASSES = {"cohesive": {}, "hard-wall": {"interface.law": "hard-wall"},
           "coupled": {"interface.tangential_ratio": 0.5, "interface.length_tangential": 1e-9}}


def run_one(args):
    """The worker: one ramp of the tree `args.root` on core `args.cpu`, its rows as JSON to `args.dump`."""
    os.sched_setaffinity(0, {args.cpu})
    root = str(Path(args.root).resolve())
    sys.path[:0] = [root, str(Path(root) / "benchmarks")]
    from benchmarks.bench_adhesion_scaling import ramp  # noqa: PLC0415  (the tree's own, once it is on sys.path)
    import gfmd  # noqa: PLC0415  (to check where it came from)

    if not Path(gfmd.__file__).resolve().is_relative_to(root):  # an installed copy or the driver's tree would hide it
        raise SystemExit(f"bench_versions: the worker for {root} imported gfmd from {gfmd.__file__}")
    from gfmd_contact.app.study_task import reuse_freed_arrays  # noqa: PLC0415  (the tree's own, as above)

    reuse_freed_arrays()
    keys = {**CLASSES[args.cls], "material.poisson_ratio": args.nu, "interface.phi_n_star": args.phi,
            **scene_keys(args.set)}
    ramp(2**12, "cohesive", max_steps=3, scene_keys=keys)  # numba's compilation and the plans outside the timed ramp
    if args.task:
        rows, cpu = whole_task(args, keys)
    else:
        t0 = time.process_time()
        rows = ramp(2**args.size, "cohesive", realization=args.realization, a_rel_stop=2.0, scene_keys=keys)
        cpu = time.process_time() - t0
    Path(args.dump).write_text(json.dumps({"cpu": cpu, "rows": [{k: r[k] for k in ("it", "pairs", "p", "converged")}
                                                                 for r in rows]}))


def scene_keys(pairs):
    """--set KEY=VALUE pairs as scene keys: a whole number, else a number, where the value reads as one (surface.nodes
    must stay an integer), else the text."""
    keys = {}
    for item in pairs or ():
        key, _, value = item.partition("=")
        for kind in (int, float, str):
            try:
                keys[key] = kind(value)
                break
            except ValueError:
                continue
    return keys


def whole_task(args, keys):
    """--task: the class's scene run as one study task (`gfmd_contact.app.study_task.run_task`: the ramp with its observables,
    checkpoints and files) into a temporary directory: (rows of its curve.csv, CPU s). FFT pairs are not in a task's
    files (0 here)."""
    from benchmarks.bench_adhesion_scaling import task_of  # noqa: PLC0415  (the tree's own, as in run_one)
    from gfmd_contact.app.study_task import run_task  # noqa: PLC0415

    scene, _ = task_of(2**args.size, "cohesive", args.realization, keys)
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.process_time()
        run_task(scene, Path(tmp) / "task", progress=lambda *a: None)
        cpu = time.process_time() - t0
        with open(Path(tmp) / "task" / "curve.csv") as f:
            rows = [{"it": int(r["iterations"]), "pairs": 0, "p": float(r["p"]), "converged": int(r["converged"])}
                    for r in csv.DictReader(f)]
    return rows, cpu


def pair(args, cls, trees):
    """The ramps of `trees` (two source roots) as simultaneous processes, the i-th pinned to core i: their dumps."""
    # imported here, in the driver only: a worker must import the `benchmarks` package from its own tree (run_one)
    sys.path.insert(0, str(ROOT))
    from benchmarks import report  # noqa: PLC0415

    return report.simultaneous([[sys.executable, __file__, "--worker", "--root", tree, "--cls", cls, "--size",
                                 str(args.size), "--realization", str(args.realization), "--nu", repr(args.nu),
                                 "--phi", repr(args.phi), *(["--task"] if args.task else []),
                                 *(["--set", *args.set] if args.set else [])]
                                for tree in trees])


def totals(run, reference):
    rows, ref = run["rows"], reference["rows"]
    p_max = max(abs(r["p"]) for r in ref)
    dp = max(abs(a["p"] - b["p"]) for a, b in zip(rows, ref)) / p_max if len(rows) == len(ref) else float("nan")
    return (run["cpu"], sum(r["it"] for r in rows), sum(r["pairs"] for r in rows),
            f"{sum(r['converged'] for r in rows)}/{len(rows)}", dp)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old")
    ap.add_argument("--new")
    ap.add_argument("--label-old", default="old")
    ap.add_argument("--label-new", default="new")
    ap.add_argument("--classes", nargs="+", default=["cohesive", "hard-wall"], choices=list(CLASSES))
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.45, help="material.poisson_ratio")
    ap.add_argument("--phi", type=float, default=0.15, help="interface.phi_n_star")
    ap.add_argument("--set", nargs="+", metavar="KEY=VALUE", help="more scene keys, e.g. surface.hurst=0.2")
    ap.add_argument("--task", action="store_true",
                    help="time the whole study task (observables, checkpoints, files), not the ramp alone")
    ap.add_argument("--rounds", type=int, default=1)
    ap.add_argument("--out")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--root", help=argparse.SUPPRESS)
    ap.add_argument("--cls", help=argparse.SUPPRESS)
    ap.add_argument("--dump", help=argparse.SUPPRESS)
    ap.add_argument("--cpu", type=int, default=0, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        return run_one(args)
    if not (args.old and args.new):
        ap.error("--old and --new (two source trees) are needed")
    for tree in (args.old, args.new):
        if not (Path(tree) / "gfmd" / "__init__.py").exists():
            ap.error(f"{tree} is not a source tree of this project (no gfmd/__init__.py)")
    versions = {}
    for name, tree in (("old", args.old), ("new", args.new)):
        head = subprocess.run(["git", "-C", tree, "log", "-1", "--format=%h %s"], capture_output=True, text=True)
        dirty = subprocess.run(["git", "-C", tree, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True).stdout.strip()
        versions[name] = (head.stdout.strip() or "not a git tree") + (" (+ working tree)" if dirty else "")
    extra = "".join(f", {k} = {v:g}" if isinstance(v, (int, float)) else f", {k} = {v}"
                    for k, v in scene_keys(args.set).items())
    lines = [f"# Two versions on whole {'study tasks' if args.task else 'ramps'}: {args.label_new} against "
             f"{args.label_old}, N = 2^{args.size}, realization {args.realization}, ν = {args.nu:g}, φn* = {args.phi:g}"
             f"{extra}", "",
             f"`python benchmarks/bench_versions.py {' '.join(argv if argv is not None else sys.argv[1:])}`; "
             f"old ({args.label_old}): {versions['old']}; new ({args.label_new}): {versions['new']}; load average at "
             f"start {os.getloadavg()[0]:.2f} (2-core machine, two simultaneous processes per pair)", "",
             f"| class | run | {'task' if args.task else 'ramp'} CPU s | iterations | FFT pairs | converged | "
             "max Δp̄ / max p̄ |", "|---|---|---|---|---|---|---|"]
    summary = []
    for cls in args.classes:
        ratios = []
        for _ in range(args.rounds):
            old0, new1 = pair(args, cls, [args.old, args.new])
            new0, old1 = pair(args, cls, [args.new, args.old])
            for label, run in ((f"{args.label_old}, core 0", old0), (f"{args.label_new}, core 1", new1),
                               (f"{args.label_new}, core 0", new0), (f"{args.label_old}, core 1", old1)):
                cpu, it, pairs, conv, dp = totals(run, old0)
                lines.append(f"| {cls} | {label} | {cpu:.1f} | {it} | {pairs:.0f} | {conv} | {dp:.1e} |")
            ratios += [new1["cpu"] / old0["cpu"], new0["cpu"] / old1["cpu"]]
        r = [ratios[i] * ratios[i + 1] for i in range(0, len(ratios), 2)]
        mean = float(sum(x ** 0.5 for x in r) / len(r))
        noise = max(abs(ratios[i] - ratios[i + 1]) / 2 for i in range(0, len(ratios), 2))
        summary.append(f"{cls}: CPU {args.label_new} / {args.label_old} × {mean:.3f} (geometric mean over the core "
                       f"placements, mean of {len(r)} round(s); noise ± {noise:.3f})")
    lines += [""] + [f"- {s}" for s in summary]
    text = "\n".join([*lines, "", f"Load average at end: {os.getloadavg()[0]:.2f}."]) + "\n"
    out = Path(args.out) if args.out else RESULTS / f"bench_versions_{args.label_new}.md"
    out.write_text(text)
    print(text)


if __name__ == "__main__":
    main()
