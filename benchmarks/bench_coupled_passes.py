"""The coupled law's nodal passes fused (`gfmd.coupled_kernels`): the Newton's preconditioned product and Eq. 2's
tractions, per call, against numpy's passes and the law's formula.

Usage: python benchmarks/bench_coupled_passes.py [--sizes 12 15 17] [--contact 0.3] [--out FILE]

On the coupled class of benchmarks/bench_adhesion_scaling.py (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm,
realization 2) at N = 2^size: a law tangent made up on the profile's contact patches (the nodes whose height is in the
top `--contact` fraction: D_nn, D_tt of the order of the law's initial stiffness, non-symmetric D_nt, D_tn; soft
elsewhere), its coarse space as the Newton builds it (`gfmd.coupled_preconditioner.coarse_space`, the scene's block
width), and per call (best of 5 × a loop, ms): one FFT pair of shape (2, N), a preconditioned product A M⁻¹ y
(`operators(…)[1]`, one FFT pair plus the nodal passes) with numpy's passes and with the fused ones
(`coupled_kernels.coarse_passes`), the nodal passes' saving in FFT pairs, and the tractions (numba with
`gfmd.vector_exp`) against `gfmd_contact.core.law_equations.traction_coupled` (numpy); the largest relative difference of the
two products (round-off). One process, the variants alternating. Writes benchmarks/results/bench_coupled_passes.md.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from benchmarks.bench_adhesion_scaling import task_of  # noqa: E402
from benchmarks.report import header, write  # noqa: E402
from gfmd_contact.core.law_equations import traction_coupled  # noqa: E402
from gfmd import kernels  # noqa: E402
from gfmd.coupled_kernels import coupled_kernels  # noqa: E402
from gfmd.coupled_preconditioner import coarse_space, operators  # noqa: E402
from gfmd.fft import Fft  # noqa: E402
from gfmd.loading import prepare  # noqa: E402
from gfmd.problem import Elastic  # noqa: E402


def best(call, seconds=0.3):
    """ms per call: the best of 5 timed loops, each about `seconds` long."""
    call()
    t0 = time.perf_counter()
    call()
    reps = max(1, int(seconds / max(time.perf_counter() - t0, 1e-6)))
    times = []
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(reps):
            call()
        times.append((time.perf_counter() - t0) / reps)
    return 1e3 * min(times)


def cell_and_tangent(n, contact):
    """(model, law, coupled tangent made up on the contact patches, profile) at N = n."""
    scene, h = task_of(n, "coupled", realization=2)
    cell = prepare(scene, h)
    k_t, k_n = cell.law.law.initial_stiffness
    rng = np.random.default_rng(1)
    patch = h >= np.quantile(h, 1.0 - contact)
    d_nn = np.where(patch, k_n * (1 + rng.random(n)), -0.05 * k_n * rng.random(n))
    d_tt = np.where(patch, k_t * (1 + rng.random(n)), 0.001 * k_t * rng.random(n))
    d_nt = np.where(patch, 0.3 * k_n * rng.standard_normal(n), 0.0)
    d_tn = np.where(patch, -0.2 * k_n * rng.standard_normal(n), 0.0)
    return cell.physics, cell.law, (d_nn, d_nt, d_tn, d_tt), h


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[12, 15, 17])
    ap.add_argument("--contact", type=float, default=0.3)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_coupled_passes.md"))
    args = ap.parse_args(argv)
    if kernels.numba is None:
        raise SystemExit("bench_coupled_passes needs numba (the fused passes)")
    lines = header("The coupled law's nodal passes fused: the Newton's product and Eq. 2's tractions, per call",
                   "bench_coupled_passes.py", argv, f"2-core machine; contact patches on the top {args.contact:g} "
                   "of the profile")
    lines += ["| N | coarse blocks | FFT pair (2, N) ms | product, numpy passes ms | product, fused ms | saved, FFT "
              "pairs per product | max rel. Δ product | tractions numpy ms | tractions fused ms |",
              "|---|---|---|---|---|---|---|---|---|"]
    for size in args.sizes:
        n = 2**size
        model, law, tangent, h = cell_and_tangent(n, args.contact)
        fft, stiff = Fft(n), Elastic(model, 0.0, 0.0)
        coarse = coarse_space(stiff, fft, tangent, law.law.initial_stiffness)
        y = np.random.default_rng(2).standard_normal((2, n))
        y -= y.mean(axis=1, keepdims=True)
        products = {b: operators(coarse, stiff, fft, tangent, b)[1] for b in ("numpy", "numba")}
        diff = float(np.max(np.abs(products["numba"](y) - products["numpy"](y))) / np.max(np.abs(products["numpy"](y))))
        pair_ms = best(lambda: fft.irfft(fft.rfft(y)))
        ms = {b: best(lambda p=p: p(y)) for b, p in products.items()}
        u = np.stack([np.random.default_rng(3).normal(0.0, 0.3e-9, n), np.zeros(n)])
        z_ind = h - h.max() + 2e-9  # gaps 2 nm … 2 nm + peak-to-valley
        params = law._params
        fused = coupled_kernels("numba")[2]
        out = np.empty_like(u)
        t_numpy = best(lambda: traction_coupled(z_ind - u[1], -u[0], *params))
        t_fused = best(lambda: fused(u, z_ind, params, out))
        lines.append(f"| 2^{size} | {coarse.m} | {pair_ms:.3f} | {ms['numpy']:.3f} | {ms['numba']:.3f} | "
                     f"{(ms['numpy'] - ms['numba']) / pair_ms:.2f} | {diff:.1e} | {t_numpy:.3f} | {t_fused:.3f} |")
        print(lines[-1], flush=True)
    lines += ["", "The product's nodal passes per call: Zᵀ y (block sums), g = y − D Π Z c (the coarse correction's "
              "spread, its mean from the block sums, and D's 2×2 product in one pass), Π (D s + g) with its row sums; "
              "numpy: reduceat, zeros, repeat, mean, subtract, the tangent product and a subtraction, then the tangent "
              "product, an addition and a mean removal."]
    write(lines, args.out)


if __name__ == "__main__":
    main()
