"""The cohesive NCG's nodal law work, numpy against the fused numba passes (`gfmd.ncg_nodes`, issue 24).

Usage: python benchmarks/bench_ncg_nodes.py [--sizes 12 14 17 20] [--ramp-size 17] [--phi 0.001 0.15]
                                            [--repeats 2] [--out FILE]

1. One line-search trial (`Eq3Nodes.trial`: Δn − α d, s, e^{−s}, Σ T_n d, and Σ k_loc d², which numpy computes
   only where the line search needs it: both counted) per N, against one FFT pair (rfft + irfft, `gfmd.fft.Fft`),
   and against "numba, libm exp": the fused trial as it was before session 37, one pass calling libm's exp per node
   (defined here, `_trial_libm`), which LLVM cannot vectorize; today's is two passes, the state with
   `gfmd.vector_exp.exp` (vectorized) and the sums. And the line search's start along a new direction (fused):
   Σ T_n d and Σ k_loc d² in one pass (`Eq3Nodes.direction_sums`, since session 41) against a dot with T_n and
   `curvature_sum` (before).
2. Whole ramps: the seed base scene (realization 1, 201 steps, δn = 1 nm, the Fig. 3 task) at N = 2^ramp-size per
   φn*, relaxed with the nodal work on numpy, fused, and fused with libm's exp, in the same process, alternating
   `--repeats` times (the same load on each): CPU s per ramp (time.process_time), NCG iterations, and the largest
   difference of p̄ and a_rel from the numpy ramp.
The spectral algebra is the fused one in both (GFMD_JIT's default); only the nodal backend differs.
Writes benchmarks/results/bench_ncg_nodes.md (or --out).
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import time
from pathlib import Path
from unittest import mock

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_adhesion_scaling import ramp  # noqa: E402
from benchmarks.report import header, ramp_differences, write  # noqa: E402
from gfmd import kernels, ncg_nodes  # noqa: E402
from gfmd.algorithms import ncg  # noqa: E402
from gfmd.fft import Fft, dot  # noqa: E402


if kernels.numba is not None:
    @kernels.numba.njit(cache=True, fastmath={"reassoc", "contract", "nsz", "arcp"})
    def _trial_libm(gap, d, alpha, inv_dn, max_compression, gap_a, s, e):
        """The fused trial before session 37: one pass, libm's exp per node (a scalar call: not vectorized)."""
        work = curv = 0.0
        for i in range(gap.size):
            g = gap[i] - alpha * d[i]
            si = g * inv_dn
            if si < -max_compression:
                si = -max_compression
            ei = np.exp(-si)
            gap_a[i], s[i], e[i] = g, si, ei
            x = ei * d[i]
            work += si * x
            curv += (1.0 - si) * x * d[i]
        return work, curv


#: the nodal variants: (label, Eq3Nodes backend, context: ncg_nodes' fused trial as it is or as `_trial_libm`)
VARIANTS = (("numpy", "numpy", contextlib.nullcontext), ("numba", "numba", contextlib.nullcontext),
            ("numba, libm exp", "numba", lambda: mock.patch.object(ncg_nodes, "_trial_fused", _trial_libm)))


def per_call(fn, seconds=0.3):
    """Mean wall time of fn() (s) over as many calls as fit in about `seconds`, after one warm-up call."""
    fn()
    calls, t0 = 0, time.perf_counter()
    while True:
        fn()
        calls += 1
        elapsed = time.perf_counter() - t0
        if elapsed > seconds and calls >= 3:
            return elapsed / calls


def trial_table(sizes):
    rows = ["| N | numpy trial (ms) | fused trial (ms) | fused, libm exp (ms) | numpy / fused | libm exp / fused | "
            "FFT pair (ms) | fused / FFT pair | start: one pass (ms) | start: dot + curvature (ms) |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    dn = 1e-9
    for e in sizes:
        n = 2**e
        rng = np.random.default_rng(e)
        gap = dn * rng.uniform(-2.0, 40.0, n)
        d = dn * rng.standard_normal(n)
        times = {}
        for label, backend, swap in VARIANTS:
            nodes = ncg_nodes.Eq3Nodes(dn, 0.01 / dn, 0.01 / dn**2, backend)

            def trial():
                _, s, e_, _, curv = nodes.trial(gap, d, 0.3)
                if curv is None:
                    nodes.curvature_sum(s, e_, d)

            with swap():
                times[label] = per_call(trial)
        fft = Fft(n)
        x = rng.standard_normal(n)
        pair = per_call(lambda: fft.irfft(fft.rfft(x)))
        fused = times["numba"]
        nodes = ncg_nodes.Eq3Nodes(dn, 0.01 / dn, 0.01 / dn**2, "numba")
        s0, e0 = nodes.state(gap)
        t0 = nodes.traction(s0, e0)
        start_one = per_call(lambda: nodes.direction_sums(s0, e0, d))
        start_two = per_call(lambda: (dot(d, t0), nodes.curvature_sum(s0, e0, d)))
        rows.append(f"| 2^{e} | {times['numpy'] * 1e3:.3f} | {fused * 1e3:.3f} | {times['numba, libm exp'] * 1e3:.3f} | "
                    f"{times['numpy'] / fused:.2f} | {times['numba, libm exp'] / fused:.2f} | {pair * 1e3:.3f} | "
                    f"{fused / pair:.2f} | {start_one * 1e3:.3f} | {start_two * 1e3:.3f} |")
    return rows


def ramp_table(size, phis, repeats):
    rows = ["| φn* | nodal backend | CPU s per ramp (each repeat) | median | NCG iterations | max |Δp̄|/max|p̄| | "
            "max |Δa_rel| |", "|---|---|---|---|---|---|---|"]
    inner = ncg.Eq3Nodes
    for phi in phis:
        runs = {label: [] for label, _, _ in VARIANTS}
        for _ in range(repeats):
            for label, backend, swap in VARIANTS:
                ncg.Eq3Nodes = lambda *a, b=backend: inner(*a, backend=b)
                with swap():
                    t0 = time.process_time()
                    r = ramp(2**size, "cohesive", realization=1, scene_keys={"interface.phi_n_star": phi},
                             a_rel_stop=2.0)
                    runs[label].append((time.process_time() - t0, r))
        ncg.Eq3Nodes = inner
        for label, got in runs.items():
            r = got[0][1]
            dp, da, _ = ramp_differences(r, runs["numpy"][0][1])
            cpu = " / ".join(f"{c:.2f}" for c, _ in got)
            median = float(np.median([c for c, _ in got]))
            rows.append(f"| {phi:g} | {label} | {cpu} | {median:.2f} | {sum(x['it'] for x in r)} | {dp:.2g} | "
                        f"{da:.2g} |")
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[12, 14, 17, 20])
    ap.add_argument("--ramp-size", type=int, default=17)
    ap.add_argument("--phi", type=float, nargs="+", default=[0.001, 0.15])
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_ncg_nodes.md"))
    args = ap.parse_args(argv)
    if kernels.numba is None:
        sys.exit("bench_ncg_nodes: numba is not installed (pip install 'gfmd-contact[fast]')")
    lines = header("The cohesive NCG's nodal law work: numpy against the fused passes (`gfmd.ncg_nodes`)", "bench_ncg_nodes.py",
                   argv)
    lines += ["## 1. One line-search trial (wall time per call)", ""]
    lines += trial_table(args.sizes)
    lines += ["", f"## 2. Whole ramps at N = 2^{args.ramp_size} (seed base scene, realization 1, δn = 1 nm)", ""]
    lines += ramp_table(args.ramp_size, args.phi, args.repeats)
    write(lines, args.out)


if __name__ == "__main__":
    main()
