"""Study throughput: load steps per CPU-second at N = 2^15 and 2^17, and the projected cost of
the seed paper's whole study (issue 11).

Usage: python benchmarks/bench_study.py [--sizes 15 17] [--classes hard-wall cohesive coupled]
                                        [--cores K] [--out DIR]

What is timed: one whole study task per (N, task class), run in this process by the same code a
study worker runs (`gfmd_contact.app.study_task.run_task`: the full ramp of 200 steps from δ0 = 12 nm out of
contact to δ = 20 nm, every step checkpointed to disk, fields saved), on the full-scale base
scene `studies/seed/seed_base.toml` (seed Sec. 2.1: L = 10.24 µm, H = 0.8, h_rms = 10 nm,
ν = 0.45, realization seed 1) with `surface.nodes` = N (λs,H = 2.5 nm fixed, so N = 2^15
resolves it with 8 nodes, 2^17 with 32 as in the paper). CPU seconds = time.process_time().

Task classes (what decides the cost of a step):
  hard-wall  interface.law = "hard-wall" (projected CG)
  cohesive   interface.law = "cohesive", φn* = 0.15, c = 0 (normal-only law: the NCG of issue 13, Settings.cohesive)
  coupled    interface.law = "cohesive", φn* = 0.15, c = 0.5, δt = 1 nm (u_x and u_z, FIRE/Verlet)

Projection: every full-scale study file in studies/seed/ (fig2, fig3, fig6a, fig6b, fig7, fig8)
is expanded with `gfmd_contact.app.study_file.load_study`; each task is counted under its class and costs
steps / (steps per CPU-second of its class at N = 2^17). Wall time on K cores assumes ideal
process-level scaling (independent single-threaded tasks); the roughness parameters of a task
(H, h_rms, ε_f) change its cost, which the class rate does not capture: the projection is an
estimate, the measured full-scale runs (README "Studies") are the check.

Dask path (section 3; ``--no-dask-path`` skips it): the same hard-wall task at the largest N run (a) in this
process, (b) in a child process started with the environment Dask's nanny gives its workers
(MALLOC_TRIM_THRESHOLD_=65536) without `gfmd_contact.app.study_task.reuse_freed_arrays` (the study engine
before that fix), (c) the same child with it (what a worker does now), (d) through
`gfmd study run` on a 1-worker local Dask cluster (cluster start included); wall seconds and, for
the children, minor page faults.

The machine is shared (2 cores): the load average at start and end is printed.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # run as a script from anywhere

from bench_gfmd import machine_info  # noqa: E402

from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd_contact.app.study import load_study, run_task, task_scene  # noqa: E402

SEED = ROOT / "studies" / "seed"
FULL_STUDIES = ("fig2", "fig3", "fig6a", "fig6b", "fig7", "fig8")
CLASSES = {
    "hard-wall": {"interface.law": "hard-wall"},
    "cohesive": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.0},
    "coupled": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.5,
                "interface.length_tangential": 1e-9},
}


def task_class(scene):
    """The cost class of a task scene (module docstring)."""
    if scene.interface.law == "hard-wall":
        return "hard-wall"
    return "coupled" if scene.interface.tangential_ratio > 0 else "cohesive"


def measure(n, cls, workdir):
    """One whole task at N = n of class `cls`: dict of steps, CPU s, wall s, iterations, converged."""
    base = load_scene(SEED / "seed_base.toml")
    scene = task_scene(base.replace(**{"surface.nodes": n, **CLASSES[cls]}), 0)
    out = Path(workdir) / f"{cls}_{n}"
    cpu, wall = time.process_time(), time.perf_counter()
    run_task(scene, out, command="bench_study", progress=lambda step, steps: None)
    cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
    import csv

    with open(out / "curve.csv") as f:
        rows = list(csv.DictReader(f))
    iterations = [int(r["iterations"]) for r in rows]
    return {"N": n, "class": cls, "steps": len(rows), "cpu_s": cpu, "wall_s": wall,
            "steps_per_cpu_s": len(rows) / cpu, "median_iterations": sorted(iterations)[len(iterations) // 2],
            "converged": sum(int(r["converged"]) for r in rows)}


_CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, sys.argv[1])
from gfmd_contact.core.scene import load_scene
from gfmd_contact.app import study_task
if sys.argv[4] == "before":
    study_task.reuse_freed_arrays = lambda: False
t = time.perf_counter()
study_task.run_task(load_scene(sys.argv[2]), sys.argv[3], progress=lambda step, steps: None)
print(json.dumps({"wall_s": time.perf_counter() - t, "faults": resource.getrusage(resource.RUSAGE_SELF).ru_minflt}))
"""


def dask_path(n, workdir):
    """Section 3 (module docstring): [(label, wall s, minor page faults or None)]."""
    import json
    import subprocess

    from gfmd_contact.core.scene import scene_to_toml

    base = load_scene(SEED / "seed_base.toml")
    scene = task_scene(base.replace(**{"surface.nodes": n, **CLASSES["hard-wall"]}), 0)
    work = Path(workdir) / f"dask_{n}"
    work.mkdir()
    (work / "scene.toml").write_text(scene_to_toml(scene))
    rows = []
    t = time.perf_counter()
    run_task(scene, work / "in_process", command="bench_study", progress=lambda step, steps: None)
    rows.append(("in this process (`run_task`)", time.perf_counter() - t, None))
    env = dict(os.environ, MALLOC_TRIM_THRESHOLD_="65536")
    for mode, label in (("before", "child, Dask worker environment, without reuse_freed_arrays (before)"),
                        ("after", "child, Dask worker environment, with reuse_freed_arrays (now)")):
        out = subprocess.run([sys.executable, "-c", _CHILD, str(ROOT), str(work / "scene.toml"), str(work / mode), mode],
                             env=env, capture_output=True, text=True, check=True)
        r = json.loads(out.stdout.strip().splitlines()[-1])
        rows.append((label, r["wall_s"], r["faults"]))
    (work / "study.toml").write_text('name = "dask_path"\nbase = "scene.toml"\n[axes]\n"interface.law" = ["hard-wall"]\n')
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "gfmd", "study", "run", str(work / "study.toml"), "--out", str(work / "study"),
                    "--workers", "1"], check=True, capture_output=True, cwd=ROOT)  # `python -m gfmd` from the tree
    rows.append(("`gfmd study run`, 1-worker local Dask cluster (cluster start included)", time.perf_counter() - t, None))
    return rows


def study_counts():
    """{study: {class: (tasks, steps)}} of the full-scale study files."""
    counts = {}
    for name in FULL_STUDIES:
        study = load_study(SEED / f"{name}.toml")
        per = {}
        for t in study.tasks:
            cls = task_class(t.scene)
            tasks, steps = per.get(cls, (0, 0))
            per[cls] = (tasks + 1, steps + t.scene.loading.steps + 1)
        counts[name] = per
    return counts


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[15, 17], help="log2 N (default 15 17)")
    parser.add_argument("--classes", nargs="+", default=list(CLASSES), choices=list(CLASSES))
    parser.add_argument("--cores", type=int, default=os.cpu_count(), help="cores of the projection (default: this machine's)")
    parser.add_argument("--out", default=str(ROOT / "benchmarks" / "results"), help="where bench_study.md goes")
    parser.add_argument("--no-dask-path", action="store_true", help="skip section 3 (the Dask study path)")
    args = parser.parse_args(argv)

    info = machine_info()
    lines = ["# Study throughput and the projected cost of the seed's whole study", "",
             "Machine: " + "; ".join(f"{k} = {v}" for k, v in info.items()), "",
             "Generated by `python benchmarks/bench_study.py` (module docstring: what is timed, the classes, the "
             "projection).", "", "## 1. Throughput: one whole study task (200 load steps, δ0 = 12 nm → δ = 20 nm)", "",
             "| N | class | steps | converged | median it/step | CPU s | wall s | steps per CPU-s |",
             "|---|---|---|---|---|---|---|---|"]
    rates = {}
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        for k in args.sizes:
            for cls in args.classes:
                r = measure(2**k, cls, tmp)
                rates[(k, cls)] = r["steps_per_cpu_s"]
                line = (f"| 2^{k} | {cls} | {r['steps']} | {r['converged']}/{r['steps']} | {r['median_iterations']} | "
                        f"{r['cpu_s']:.1f} | {r['wall_s']:.1f} | {r['steps_per_cpu_s']:.3g} |")
                lines.append(line)
                print(line, flush=True)
    top = max(args.sizes)
    lines += ["", f"## 2. Projection of the paper's study at N = 2^{top} (full-scale files in studies/seed/)", "",
              f"Each task costs its steps / (steps per CPU-s of its class at N = 2^{top}); wall = CPU / {args.cores} "
              "cores (ideal scaling).", "",
              "| study | tasks (hard wall / cohesive / coupled) | steps | CPU-hours | wall hours on "
              f"{args.cores} cores |", "|---|---|---|---|---|"]
    total_cpu = 0.0
    for name, per in study_counts().items():
        missing = [c for c in per if (top, c) not in rates]
        if missing:
            lines.append(f"| {name} | | | not measured: class {', '.join(missing)} | |")
            continue
        cpu = sum(steps / rates[(top, c)] for c, (_, steps) in per.items())
        total_cpu += cpu
        tasks = " / ".join(str(per.get(c, (0, 0))[0]) for c in CLASSES)
        steps = sum(s for _, s in per.values())
        lines.append(f"| {name} | {tasks} | {steps} | {cpu / 3600:.2f} | {cpu / 3600 / args.cores:.2f} |")
    lines += [f"| **all** | | | **{total_cpu / 3600:.2f}** | **{total_cpu / 3600 / args.cores:.2f}** |", ""]
    if not args.no_dask_path:
        lines += [f"## 3. The Dask study path: one hard-wall task at N = 2^{top}", "",
                  "Same scene as section 1; module docstring for (a)–(d).", "",
                  "| run | wall s | minor page faults |", "|---|---|---|"]
        with tempfile.TemporaryDirectory() as tmp:
            for label, wall, faults in dask_path(2**top, tmp):
                lines.append(f"| {label} | {wall:.1f} | {faults if faults is not None else ''} |")
                print(lines[-1], flush=True)
        lines.append("")
    lines += [f"Benchmark time {time.perf_counter() - started:.0f} s; load average at end "
              + " ".join(f"{v:.2f}" for v in os.getloadavg()) + "."]
    text = "\n".join(lines) + "\n"
    print(text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "bench_study.md").write_text(text)


if __name__ == "__main__":
    main()
