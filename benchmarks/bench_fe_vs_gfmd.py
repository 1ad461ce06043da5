"""FE reference vs GFMD: cost per load step, setup, unknowns and peak memory vs N (issue #4).

Usage: python benchmarks/bench_fe_vs_gfmd.py [--quick] [--out DIR] [--steps S] [--timeout T] [--sizes N ...]

Full: N = 256, 1024, 2048, 4096 (about 15 min on 2 shared cores); --quick: N = 256,
1024 (about 1 min). Output: benchmarks/results/bench_fe_vs_gfmd[_quick].md and .json
(with --sizes: a _N<sizes> suffix).

Scene: the cohesive sinusoid `verification.scenes.cohesive_sinusoid` (a = 50 nm,
L = 1 µm, layer D = L, E = 70 GPa, ν = 0.3, normal CZ φn* = 0.01, δn = 1 nm,
δ0 = 2 nm) with the verification's increment ΔU = 62 nm / 20 = 3.1 nm, cut to
S load steps (default 5: U = 0 … 15.5 nm). Steps 0 and 1 are not timed (no
extrapolated guess yet); "s/step" is the median wall time of the warm steps
k ≥ 2 (both codes warm-start with 2u_k − u_{k−1}).

Methods (each (N, method) runs in its own process, so "peak MB" is that
process's maximum resident set size, imports included, about 150 MB):

* fe-p2 / fe-p1 dense:  `reference.fem.run_realization(linear="dense")`
  (dense Schur complement onto the surface, dense LU per Newton iteration);
* fe-p2 / fe-p1 sparse: linear="sparse" (SuperLU of the full reduced system per
  Newton iteration, `reference.fem.sparse`);
* fe-p2 sparse-lagged:  linear="sparse-lagged" (last factorization reused as
  GMRES preconditioner);
* gfmd-fire: `gfmd.loading.run_realization` (FIRE, layer kernel for D = L) at
  the FE residual tolerance 1e-10 (same criterion: max |R/W| / p_ref) and at
  the verification's 1e-8.

ratio = FE s/step / GFMD (FIRE, 1e-10) s/step at the same N, same run.
Δp/p vs dense: |p_last − p_last(dense, same order)| / |p_last(dense)| at the last
step, a check that the sparse paths solve the same problem.
setup = total run time − sum of step times (mesh, assembly, condensation or
interior factorization; GFMD: kernel and model). "system" is the size of the
Newton system: dense = surface unknowns (S is system²), sparse = reduced DOFs.

The machine is shared (2 cores, other jobs): only ratios measured in one run
are meant to be compared; the table records `os.getloadavg()` before and after.
BLAS is pinned to one thread (as in CI).
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

INCREMENT = 62e-9 / 20  # m, ΔU of verification.scenes.cohesive_sinusoid
FE_METHODS = (("fe-p2", "dense"), ("fe-p2", "sparse"), ("fe-p2", "sparse-lagged"), ("fe-p1", "dense"),
              ("fe-p1", "sparse"))
GFMD_METHODS = (("gfmd-fire", "1e-10"), ("gfmd-fire", "1e-8"))
SIZES_FULL = (256, 1024, 2048, 4096)
SIZES_QUICK = (256, 1024)


def bench_scene(nodes, steps):
    """The verification scene with `steps` increments of INCREMENT."""
    from verification.scenes import cohesive_sinusoid as scene

    sc = scene(nodes)
    return sc.replace(**{"loading.steps": steps,
                         "loading.final_penetration": steps * INCREMENT - sc.loading.initial_separation,
                         "output.field_steps": 0})


def run_one(nodes, method, variant, steps):
    """Run one (N, method) in this process; returns a dict of measurements."""
    import resource

    import numpy as np

    from gfmd_contact.app.methods import run_realization  # the one registry: the scene's [method] says which

    sc = bench_scene(nodes, steps)
    t0 = time.perf_counter()
    if method.startswith("fe"):
        result = run_realization(sc.replace(**{"method.name": "fe", "method.order": int(method[-1]),
                                               "method.linear": variant}))
        prob = result.diagnostics["problem"]
        system = prob.reduced.shape[0] if hasattr(prob, "reduced") else prob.S.shape[0]
        dofs = prob.cell.basis.N
        extra = dict(getattr(prob, "stats", {}))
    else:
        result = run_realization(sc.replace(**{"solver.tolerance": float(variant)}))
        system = dofs = nodes
        extra = {}
    total = time.perf_counter() - t0
    walls = np.asarray(result.curve["wall_s"], float)
    iterations = np.asarray(result.curve["iterations"], float)
    return {"N": nodes, "method": method, "variant": variant, "dofs": int(dofs), "system": int(system),
            "setup_s": float(total - walls.sum()), "step_s": float(np.median(walls[2:])),
            "iterations": float(np.median(iterations[2:])), "steps_timed": int(walls[2:].size),
            "converged": bool(result.all_converged), "fallback_steps": list(result.diagnostics.get("fallback_steps", [])),
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, "total_s": total,
            "p_last": float(result.curve["p"][-1]), **extra}


def run_child(nodes, method, variant, steps, timeout):
    cmd = [sys.executable, __file__, "--one", str(nodes), method, variant, "--steps", str(steps)]
    start = time.perf_counter()
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=ROOT)
    except subprocess.TimeoutExpired:
        return {"N": nodes, "method": method, "variant": variant, "error": f"timeout after {timeout} s"}
    lines = [line for line in out.stdout.splitlines() if line.startswith("{")]
    if out.returncode != 0 or not lines:
        tail = (out.stderr or out.stdout).strip().splitlines()[-1:] or ["no output"]
        return {"N": nodes, "method": method, "variant": variant, "error": f"rc {out.returncode}: {tail[0][:120]}",
                "total_s": time.perf_counter() - start}
    return json.loads(lines[-1])


def _sha1(path):
    """First 10 hex digits of the file's git blob hash (identifies the timed FE code when the tree is dirty)."""
    try:
        return subprocess.run(["git", "hash-object", path], capture_output=True, text=True, cwd=ROOT,
                              timeout=30).stdout.strip()[:10] or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def _fmt(x, spec=".3g"):
    return format(x, spec) if isinstance(x, (int, float)) else str(x)


def table(rows):
    """Markdown table; ratio = FE s/step ÷ GFMD (1e-10) s/step at the same N; Δp vs the dense run of that order."""
    gfmd = {r["N"]: r["step_s"] for r in rows if r["method"] == "gfmd-fire" and r.get("variant") == "1e-10"
            and "step_s" in r}
    dense_p = {(r["N"], r["method"]): r["p_last"] for r in rows if r.get("variant") == "dense" and "p_last" in r}
    head = ("| N | method | linear / tol | DOFs | system | setup s | s/step | FE/GFMD | it/step | factorizations "
            "| peak MB | converged | Δp/p vs dense |")
    lines = [head, "|---" * (head.count("|") - 1) + "|"]
    for r in rows:
        if "error" in r:
            lines.append(f"| {r['N']} | {r['method']} | {r['variant']} | | | | {r['error']} | | | | | | |")
            continue
        ratio = r["step_s"] / gfmd[r["N"]] if r["method"].startswith("fe") and r["N"] in gfmd else ""
        fact = r.get("factorizations", "")
        ref = dense_p.get((r["N"], r["method"]))
        dp = abs(r["p_last"] - ref) / abs(ref) if ref is not None and r["variant"] != "dense" else ""
        lines.append(f"| {r['N']} | {r['method']} | {r['variant']} | {r['dofs']} | {r['system']} | "
                     f"{_fmt(r['setup_s'])} | {_fmt(r['step_s'])} | {_fmt(ratio)} | {_fmt(r['iterations'])} | "
                     f"{fact} | {r['peak_mb']:.0f} | {'yes' if r['converged'] else 'NO'} | {_fmt(dp, '.1e')} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 256, 1024 only")
    ap.add_argument("--steps", type=int, default=5, help="load steps (k = 0 … S; k ≥ 2 timed)")
    ap.add_argument("--timeout", type=float, default=1200.0, help="seconds per (N, method) process")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    ap.add_argument("--sizes", type=int, nargs="*", help="override the N list")
    ap.add_argument("--one", nargs=3, metavar=("N", "METHOD", "VARIANT"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        print(json.dumps(run_one(int(args.one[0]), args.one[1], args.one[2], args.steps)), flush=True)
        return
    sizes = args.sizes or (SIZES_QUICK if args.quick else SIZES_FULL)
    from gfmd_contact.app.io import code_version

    code = code_version()  # before the runs: the version that is timed
    load_start = os.getloadavg()
    started = time.perf_counter()
    rows = []
    for n in sizes:
        for method, variant in GFMD_METHODS + FE_METHODS:
            row = run_child(n, method, variant, args.steps, args.timeout)
            rows.append(row)
            print(json.dumps(row), flush=True)
    load_end = os.getloadavg()
    import numpy
    import scipy

    header = (f"# FE reference vs GFMD, cost per load step ({'quick' if args.quick else 'full'})\n\n"
              f"Machine: date = {datetime.datetime.now().isoformat(timespec='seconds')}; host = {platform.node()}; "
              f"cpu = {platform.processor() or platform.machine()}; cores = {os.cpu_count()}; "
              f"python = {platform.python_version()}; numpy = {numpy.__version__}; scipy = {scipy.__version__}; "
              f"OPENBLAS_NUM_THREADS = {os.environ.get('OPENBLAS_NUM_THREADS')}; code = {code} "
              f"(reference/fem/sparse.py {_sha1('reference/fem/sparse.py')}, solver.py {_sha1('reference/fem/solver.py')}); "
              f"loadavg_start = {' '.join(f'{x:.2f}' for x in load_start)}; "
              f"loadavg_end = {' '.join(f'{x:.2f}' for x in load_end)}; "
              f"total_s = {time.perf_counter() - started:.0f}\n\n"
              f"Scene: verification.scenes.cohesive_sinusoid (D = L, φn* = 0.01, ν = 0.3), "
              f"{args.steps} steps of ΔU = {INCREMENT * 1e9:.2f} nm; s/step = median of the warm steps k ≥ 2; "
              f"FE tolerance 1e-10; FE/GFMD = FE s/step ÷ GFMD (FIRE, tolerance 1e-10) s/step at the same N. "
              f"system = Newton system size (dense: surface unknowns, matrix system²; sparse: reduced DOFs). "
              f"See the script's docstring.\n\n")
    text = header + table(rows) + "\n"
    print("\n" + text)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    name = "bench_fe_vs_gfmd_quick" if args.quick else "bench_fe_vs_gfmd"
    if args.sizes:
        name += "_N" + "-".join(map(str, sizes))
    (out / f"{name}.md").write_text(text)
    (out / f"{name}.json").write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    main()
