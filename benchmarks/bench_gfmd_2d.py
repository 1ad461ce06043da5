"""GFMD on 2+1-D surfaces (issue 25): time and FFT pairs per step, memory per node, and Tamaas 2+1-D on the same loads.

Usage: python benchmarks/bench_gfmd_2d.py [--quick] [--out DIR] [--no-tamaas] [--sizes 256 512 ...]

Scene (SI, gfmd_contact.core.conventions): a square periodic cell L = 1.28 µm of N × N nodes (N = 256, 512, 1024, 2048;
--quick: 256, 512), isotropic self-affine heights (H = 0.8, h_rms = 10 nm, C(q) ∝ |q|^(−2−2H) between the
roll-off 2π/(L/8) and the cut-off 2π/(4 l), flat below the roll-off; random phases, seed 0; written here,
as the 2-D scene kinds are another branch's), a half-space of the default scene's material. The 2-D
model is built as tests/test_gfmd_2d.py builds it (`gfmd_contact.core.kernels.wavevector_magnitudes`,
`halfplane_normal`). Loads, warm-started as `gfmd_contact.core.ramp` does (the last state, from the third step the
extrapolation 2u_k − u_{k−1}), tolerance 1e-10 (as benchmarks/bench_vs_tamaas.py; Tamaas 1e-10 too):

* hard wall: STEPS steps pressing from first touch to the rigid overlap of HARD_WALL_OVERLAP of the nodes
  (a_rel ≈ 1–10 %; the dual CG, then the primal where the contact set grows past 15 %);
* cohesive (seed Eq. 3, φn* = 0.01, δn = 2 nm at every size): the same ramp, NCG (FIRE after a stall);
* Tamaas (PolonskyKeerRey, basic_2d, where `import tamaas` works) on the hard-wall pressures GFMD found,
  its own warm start kept between solves; it gets −h (contact at the maximum of its surface).

Columns: s/step and FFT pairs/step (medians over the steps), iterations/step, a_rel at the last step, and
the memory per node: the peak of Python-level allocations (tracemalloc: numpy's arrays; not ducc0's or
numba's internal scratch) over one step (the last load, from the state before it), in bytes per node. One
thread for BLAS and OpenMP (GFMD's FFTs are single-threaded). Times are machine- and load-dependent: the
header records the load average; on a shared machine they are an upper bound.

Writes benchmarks/results/bench_gfmd_2d{,_quick}.md.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import platform
import sys
import time
import tracemalloc
from pathlib import Path

# before numpy loads BLAS: one thread (the timings are single-threaded); hence the E402 imports below
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

# the script runs from anywhere: the repository goes on sys.path before the project imports (E402)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gfmd_contact.core.kernels import halfplane_normal, wavevector_magnitudes  # noqa: E402
from gfmd_contact.core.loading import indenter_surface  # noqa: E402
from gfmd_contact.core.model import build_model  # noqa: E402
from gfmd_contact.core.observables import contact_mask  # noqa: E402
from gfmd_contact.core.scene import default_scene  # noqa: E402
from gfmd.chains import relax  # noqa: E402
from gfmd.fft import fft_backend  # noqa: E402
from gfmd.kernels import jit_backend  # noqa: E402
from gfmd.problem import InterfaceLaw  # noqa: E402
from gfmd.settings import Settings  # noqa: E402

try:
    import tamaas as tm
except ImportError:  # optional (the ``bench`` extra)
    tm = None

LENGTH = 1.28e-6
H_RMS = 10e-9
HURST = 0.8
STEPS = 5
HARD_WALL_OVERLAP = 0.05
PHI_N_STAR = 0.01
LENGTH_NORMAL = 2e-9  # δn/l = 0.4 at 256², 3.2 at 2048²: one law at every size
TOLERANCE = 1e-10
SIZES, QUICK_SIZES = (256, 512, 1024, 2048), (256, 512)


def self_affine(n, seed=0):
    """Isotropic self-affine heights (n, n) (m): module docstring."""
    q1 = 2 * np.pi * np.fft.fftfreq(n, LENGTH / n)
    q = np.hypot(q1[:, None], q1[None, :])
    q_r, q_s = 2 * np.pi / (LENGTH / 8), 2 * np.pi / (4 * LENGTH / n)
    amp = np.where((q > 0) & (q <= q_s), np.maximum(q, q_r) ** (-1 - HURST), 0.0)
    h = np.real(np.fft.ifft2(amp * np.exp(2j * np.pi * np.random.default_rng(seed).random((n, n)))))
    return h * H_RMS / np.std(h)


def surface_model(law, n, h):
    """The 2+1-D model (n × n, L × L, half-space) of the default scene's material and the law `law`."""
    sc = default_scene().replace(**{"surface.kind": "sinusoid", "surface.amplitude": H_RMS, "surface.nodes": n,
                                    "surface.length": LENGTH, "interface.law": law,
                                    "interface.phi_n_star": PHI_N_STAR,
                                    "interface.length_normal": LENGTH_NORMAL})
    m1 = build_model(sc, h[:, 0])
    q = wavevector_magnitudes(n, LENGTH, n, LENGTH)
    m = sc.material
    model = dataclasses.replace(m1, nodes=n * n, q=q, k_zz=np.asarray(halfplane_normal(q, m.youngs_modulus,
                                                                                      m.poisson_ratio)),
                                shape=(n, n), length_y=LENGTH)
    return sc, model


def pushes(h):
    """The ramp's indenter displacements from first touch: up to the rigid overlap of HARD_WALL_OVERLAP."""
    top = float(np.quantile(h, HARD_WALL_OVERLAP) - np.min(h))
    return np.linspace(top / STEPS, top, STEPS)


def ramp(sc, model, h, loads, settings, tamaas=None):
    """GFMD steps at `loads` (m), warm-started; list of dicts (and the states for the memory step)."""
    law = InterfaceLaw(model)
    d0 = sc.loading.initial_separation
    wall_tol = 1e-12 * max(float(np.ptp(h)), sc.interface.length_normal)
    u = prev = np.zeros((1,) + model.spectrum_shape, complex)
    rows, states = [], []
    for k, push in enumerate(loads):
        guess = 2 * u - prev if k >= 2 else u
        z = indenter_surface(h, d0, d0 + push)
        t = time.perf_counter()
        r = relax(model, law, z, guess, settings, wall_tol)
        dt = time.perf_counter() - t
        p = -float(np.mean(r.t_z))
        row = {"s": dt, "it": r.iterations, "pairs": r.fft_pairs, "conv": r.converged, "method": r.method, "p": p,
               "a": float(np.mean(contact_mask(model.law, r.gap, r.t_z)))}
        if tamaas is not None and p > 0:
            row.update(tamaas(p))
        rows.append(row)
        states.append((z, guess))
        prev, u = (u, r.u_hat) if r.converged else (prev, u)
        print(f"    step {k}: {dt:.3g} s, {r.iterations} it, {r.fft_pairs:g} pairs, a_rel {row['a']:.4f}, "
              f"{r.method}{'' if r.converged else ' NOT CONVERGED: ' + r.message}", flush=True)
    return rows, states


def memory_per_node(model, h, state, settings, sc):
    """Peak Python-level allocation (bytes) of one step from its guess, per node (tracemalloc)."""
    z, guess = state
    law = InterfaceLaw(model)
    tracemalloc.start()
    tracemalloc.reset_peak()
    relax(model, law, z, guess, settings, 1e-12 * max(float(np.ptp(h)), sc.interface.length_normal))
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return peak / model.nodes


def tamaas_solver(sc, n, h):
    """callable(p) → Tamaas PolonskyKeerRey step on the same surface (its warm start kept)."""
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [LENGTH, LENGTH], [n, n])
    model.E, model.nu = sc.material.youngs_modulus, sc.material.poisson_ratio
    surface = np.ascontiguousarray(-h)
    solver = tm.PolonskyKeerRey(model, surface, TOLERANCE)

    def step(p):
        t = time.perf_counter()
        solver.solve(p)
        dt = time.perf_counter() - t
        return {"tm_s": dt, "tm_a": float(np.mean(np.array(model.traction) > 0))}

    return step


def med(rows, key):
    return float(np.median([r[key] for r in rows]))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="256² and 512² only")
    ap.add_argument("--sizes", type=int, nargs="+", help="N of the N × N grids (overrides --quick)")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results")
    ap.add_argument("--no-tamaas", action="store_true", help="skip the Tamaas column")
    a = ap.parse_args(argv)
    sizes = a.sizes or (QUICK_SIZES if a.quick else SIZES)
    use_tamaas = tm is not None and not a.no_tamaas
    if tm is None and not a.no_tamaas:
        print("tamaas is not importable (pip install tamaas, the `bench` extra): the Tamaas column is skipped",
              flush=True)
    if use_tamaas:
        tm.set_log_level(tm.LogLevel.error)
    settings = Settings(tolerance=TOLERANCE)
    load = os.getloadavg()
    lines = ["# GFMD on 2+1-D surfaces: time and FFT pairs per step, memory per node" + (" (quick)" if a.quick else ""),
             "", f"Generated by `python benchmarks/bench_gfmd_2d.py {' '.join(argv or sys.argv[1:])}` on "
             f"{platform.node()} ({platform.processor() or platform.machine()}, {os.cpu_count()} cores), "
             f"load average {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} at the start; FFT {fft_backend()}, "
             f"NCG algebra {jit_backend()}, tamaas {tm.__version__ if tm else 'not installed'}.", "",
             "Scene and columns: the module docstring. Hard wall: ramp to the rigid overlap of "
             f"{HARD_WALL_OVERLAP:g} of the nodes in {STEPS} steps; cohesive: Eq. 3, φn* = {PHI_N_STAR:g}, "
             "δn = 2 nm, the same ramp; Tamaas PKR on the hard-wall pressures GFMD found "
             "(tolerance 1e-10, its own criterion); GFMD tolerance 1e-10 (max |f| / p_ref).", "",
             "| N² | law | algorithm(s) | s/step | FFT pairs/step | iterations/step | s/FFT pair | a_rel (last) | "
             "memory B/node | Tamaas s/step | Tamaas a_rel (last) | GFMD/Tamaas |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for n in sizes:
        h = self_affine(n)
        loads = pushes(h)
        for law in ("hard-wall", "cohesive"):
            print(f"N = {n}², {law}", flush=True)
            sc, model = surface_model(law, n, h)
            tam = tamaas_solver(sc, n, h) if use_tamaas and law == "hard-wall" else None
            rows, states = ramp(sc, model, h, loads, settings, tam)
            mem = memory_per_node(model, h, states[-1], settings, sc)
            s, pairs = med(rows, "s"), med(rows, "pairs")
            methods = ", ".join(sorted({r["method"] for r in rows}))
            conv = sum(r["conv"] for r in rows)
            tcols = "– | – | –"
            if tam is not None and all("tm_s" in r for r in rows):
                t_tm = med(rows, "tm_s")
                tcols = f"{t_tm:.3g} | {rows[-1]['tm_a']:.4f} | {s / t_tm:.3g}"
            unconverged = "" if conv == len(rows) else f" ({conv}/{len(rows)} converged)"
            lines.append(f"| {n}² | {law} | {methods}{unconverged} | "
                         f"{s:.3g} | {pairs:.3g} | {med(rows, 'it'):.3g} | {s / pairs:.3g} | {rows[-1]['a']:.4f} | "
                         f"{mem:.0f} | {tcols} |")
            print(lines[-1], flush=True)
    lines += ["", "Measured on a shared machine (see the load average above): the times are upper bounds, the FFT "
              "pairs and iterations per step and the memory per node are not affected by the load."]
    text = "\n".join(lines) + "\n"
    a.out.mkdir(parents=True, exist_ok=True)
    name = "bench_gfmd_2d" + ("_quick" if a.quick and not a.sizes else "") + ".md"
    (a.out / name).write_text(text)
    print(text)
    print(f"written: {a.out / name}")


if __name__ == "__main__":
    main()
