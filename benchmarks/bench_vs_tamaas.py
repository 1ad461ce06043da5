"""GFMD against Tamaas (PolonskyKeerRey) on the same loads, and the hard-wall solver levers, in one run.

Usage: python benchmarks/bench_vs_tamaas.py [--quick] [--out DIR] [--no-tamaas]

Scene (SI, contact.conventions): the profile of benchmarks/bench_gfmd.py (default scene,
self-affine H = 0.8, h_rms = 10 nm, ν = 0.45, L = 1.28 µm, λr = L/8, λs = max(4 l, L/4096)),
realization 0, half-plane. Ramp: 10 equal steps of 1.5 nm from first touch (δ = 1.5 … 15 nm),
tolerance 1e-10. GFMD warm-starts like `contact.ramp` (the last state, from the third step on
the extrapolation 2u_k − u_{k−1}); Tamaas keeps its pressure field between solves (its own warm
start) and is given the mean pressure GFMD found at each step; it gets −h, since it puts contact
at the maximum of its surface. Both run on one thread (OMP/OpenBLAS pinned to 1; GFMD's FFTs
are single-threaded).

Sections (every time is a median over steps, and ratios are taken within this one process, on
the same loads, seconds apart: the machine is shared and noisy):

1. hard wall at N = 2^16, 2^17: per variant (``fire``: the FIRE hard wall before issue 13 with
   scipy.fft; ``cg-scipy``: the projected CG with scipy.fft; ``cg``: the CG with the default
   FFT backend) iterations, FFT pairs, s/step, s per FFT pair, the KKT residual of every step
   (the solver's residual: max |net nodal force| / p_ref, pulling wall nodes included; the
   state never penetrates), and Tamaas' s/step on the same pressures, GFMD/Tamaas;
2. cohesive φn* ∈ {0.01, 0.15} × δn ∈ {0.25, 1} nm on the same profile and ramp (N = 2^16),
   s/step relative to the hard-wall CG step;
3. iterations per step vs N (hard-wall CG, N = 2^12 … 2^18);
4. near full contact: steps to 0.998 δ_max (δ_max = mean h − min h) at N = 2^14, a_rel, iterations;
5. the seed's Fig. 3 study projected from steps per CPU-second measured at N = 2^17 on a
   window of its ramp (200 steps to δ = 20 nm: dU = 0.1 nm; 6 interfaces, 10 realizations,
   2 cores).

Writes benchmarks/results/bench_vs_tamaas{,_quick}.md. Tamaas is optional (the ``bench`` extra);
without it the comparison columns are skipped with a message.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

# imports below these lines on purpose (noqa: E402): one BLAS thread must be set before numpy loads
# BLAS, and the script, run from anywhere, puts the repository and benchmarks/ on sys.path itself
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import bench_gfmd as bg  # noqa: E402
from gfmd import solver as gsolver  # noqa: E402
from gfmd.solver import Settings  # noqa: E402

try:
    import tamaas as tm
except ImportError:  # optional
    tm = None

TOL = 1e-10
D_STEP = 1.5e-9
STEPS = 10


def ramp(case, settings, deltas, backend=None, tamaas=None):
    """GFMD steps at penetrations `deltas` (warm-started as contact.ramp does); list of dicts."""
    if backend:
        os.environ["GFMD_FFT"] = backend
    n = case.model.nodes
    u = prev = np.zeros((case.model.components, n // 2 + 1), complex)
    rows = []
    h_rms = float(np.std(case.h))
    for k, delta in enumerate(deltas):
        guess = 2 * u - prev if k >= 2 else u
        t = time.perf_counter()
        r = case.relax(delta, guess, settings)
        dt = time.perf_counter() - t
        if not r.converged:
            print(f"    step {k} did not converge: {r.message}", flush=True)
        pairs = r.fft_pairs or 2 * r.iterations + 2  # FIRE hard wall: two pairs per iteration
        p = -float(np.mean(r.t_z))
        contact = r.gap <= case.wall_tol if case.law.constraint else r.t_z < 0
        row = {"delta": delta, "it": r.iterations, "pairs": pairs, "s": dt, "res": r.residual,
               "conv": r.converged, "p": p, "a": float(np.mean(contact)),
               "pen": float(max(0.0, -np.min(r.gap))) / h_rms if case.law.constraint else 0.0, "u": r.u_z}
        if tamaas is not None:
            row.update(tamaas(p))
        rows.append(row)
        prev, u = (u, r.u_hat) if r.converged else (prev, u)
    os.environ.pop("GFMD_FFT", None)
    return rows


def tamaas_solver(case):
    """callable(p) → Tamaas step on the same profile (its warm start kept between calls)."""
    s, m = case.scene.surface, case.scene.material
    model = tm.ModelFactory.createModel(tm.model_type.basic_1d, [s.length], [s.nodes])
    model.E, model.nu = m.youngs_modulus, m.poisson_ratio
    surface = np.ascontiguousarray(-case.h)  # Tamaas: contact at the maximum of its surface
    solver = tm.PolonskyKeerRey(model, surface, TOL)
    h_rms = float(np.std(case.h))

    def step(p):
        t = time.perf_counter()
        solver.solve(p)
        dt = time.perf_counter() - t
        trac = np.array(model.traction).ravel()
        disp = np.array(model.displacement).ravel()
        gap = disp - surface  # up to a rigid shift: zero on the contact set when exact
        on = trac > 0
        spread = float(np.ptp(gap[on])) / h_rms if on.any() else 0.0
        level = float(np.median(gap[on])) if on.any() else 0.0
        pen = int(np.count_nonzero(gap < level - 1e-9 * h_rms))
        return {"tm_s": dt, "tm_spread": spread, "tm_pen": pen, "tm_u": -(disp - disp.mean())}

    return step


def cohesive_case(n, phi, length_normal):
    """bench_gfmd.Case of the cohesive law φn* = phi with δn = length_normal (m)."""
    case = bg.Case(n, "cohesive", phi)
    case.scene = case.scene.replace(**{"interface.length_normal": length_normal})
    case.model = bg.build_model(case.scene, case.h)
    case.law = bg.InterfaceLaw(case.model)
    case.d0 = case.scene.loading.initial_separation
    return case


def pair_seconds(n, backend):
    fft = gsolver._Fft(n, backend)
    x = np.random.default_rng(0).standard_normal(n)
    for _ in range(3):
        fft.irfft(fft.rfft(x))
    samples = []
    for _ in range(max(20, int(4e6 // n))):
        t = time.perf_counter()
        fft.irfft(fft.rfft(x))
        samples.append(time.perf_counter() - t)
    return float(np.median(samples))


def med(rows, key):
    return float(np.median([r[key] for r in rows]))


def section_hard_wall(sizes, use_tamaas, lines):
    lines += ["## 1. Hard wall, 10 steps of 1.5 nm from first touch, tolerance 1e-10", "",
              "Per N: one row per GFMD variant (medians over the 10 steps; `max KKT` is the largest "
              "residual over the steps, in p_ref = E*ḡ; `pen` the largest penetration in h_rms, "
              "exactly 0 by construction), then Tamaas on the mean pressures of the `cg` row. "
              "`s/pair` = s/step ÷ pairs/step; `pair` the backend's measured rfft+irfft time.", "",
              "| N | code | it/step | pairs/step | s/step | s/pair | pair (s) | s/pair ÷ pair | max KKT | pen | "
              "a_rel last | GFMD/Tamaas |", "|" + "---|" * 12]
    summary = {}
    for e in sizes:
        n = 2**e
        case = bg.Case(n, "hard-wall", 0.0)
        deltas = D_STEP * np.arange(1, STEPS + 1)
        variants = [("fire", Settings(tolerance=TOL, hard_wall="fire"), "scipy"),
                    ("cg-scipy", Settings(tolerance=TOL), "scipy"),
                    ("cg", Settings(tolerance=TOL), None)]
        results = {}
        for name, st, backend in variants:
            tam = tamaas_solver(case) if (use_tamaas and name == "cg") else None
            results[name] = ramp(case, st, deltas, backend, tam)
            print(f"  N=2^{e} {name}: its {[r['it'] for r in results[name]]}", flush=True)
        t_tm = med(results["cg"], "tm_s") if use_tamaas else None
        for name, st, backend in variants:
            rows = results[name]
            b = gsolver.fft_backend(backend)
            t_pair = pair_seconds(n, b)
            s_step, pairs = med(rows, "s"), med(rows, "pairs")
            ratio = f"{s_step / t_tm:.3f} (1/{t_tm / s_step:.1f})" if t_tm else "–"
            lines.append(f"| 2^{e} | {name} ({b}) | {med(rows, 'it'):.0f} | {pairs:.0f} | {s_step:.3g} | "
                         f"{s_step / pairs:.3g} | {t_pair:.3g} | {s_step / pairs / t_pair:.2f} | "
                         f"{max(r['res'] for r in rows):.2g} | {max(r['pen'] for r in rows):.1g} | "
                         f"{rows[-1]['a']:.4f} | {ratio} |")
            summary[(e, name)] = s_step
        if use_tamaas:
            rows = results["cg"]
            du = max(float(np.max(np.abs(r["u"] - r["u"].mean() - r["tm_u"]))) for r in rows) / float(np.std(case.h))
            lines.append(f"| 2^{e} | Tamaas {tm.__version__} PKR | | | {t_tm:.3g} | | | | gap spread on contact "
                         f"≤ {max(r['tm_spread'] for r in rows):.1g} h_rms, penetrating nodes ≤ "
                         f"{max(r['tm_pen'] for r in rows)} | max |u_GFMD − u_Tamaas| = {du:.1g} h_rms | | 1 |")
        per_step = " ".join(f"{r['res']:.1e}" for r in results["cg"])
        lines.append(f"| 2^{e} | cg: KKT residual of every step | | | | | | | {per_step} | | | |")
    lines.append("")
    return summary


def section_cohesive(e, lines, hard_s):
    lines += ["## 2. Cohesive vs hard wall, same profile and ramp (N = 2^%d)" % e, "",
              "Cohesive laws run FIRE, unchanged by issue 13 (scipy.fft: the ducc0 backend serves the hard wall only so far); the first step "
              "starts from the flat surface at δ = 1.5 nm (jump-in). ratio = median s/step ÷ the "
              "hard-wall `cg` median s/step measured in section 1 (same process).", "",
              "| law | δn (nm) | it/step | pairs/step | s/step | ratio to hard wall | max residual | converged |",
              "|---|---|---|---|---|---|---|---|"]
    n = 2**e
    for phi in (0.01, 0.15):
        for dn in (0.25e-9, 1e-9):
            rows = ramp(cohesive_case(n, phi, dn), Settings(tolerance=TOL), D_STEP * np.arange(1, STEPS + 1))
            pairs = [r["it"] * 1.05 for r in rows]  # one pair per iteration + a check pair every 10
            s = med(rows, "s")
            lines.append(f"| φn* = {phi:g} | {dn * 1e9:g} | {med(rows, 'it'):.0f} | {np.median(pairs):.0f} | {s:.3g} | "
                         f"{s / hard_s:.1f} | {max(r['res'] for r in rows):.2g} | "
                         f"{sum(r['conv'] for r in rows)}/{len(rows)} |")
            print(f"  cohesive {phi} {dn}: {s:.3g} s/step", flush=True)
    lines.append("")


def section_scaling(sizes, lines):
    lines += ["## 3. Iterations per step vs N (hard-wall CG, same ramp)", "",
              "| N | median it/step | max it/step | median pairs/step | median s/step |", "|---|---|---|---|---|"]
    for e in sizes:
        case = bg.Case(2**e, "hard-wall", 0.0)
        rows = ramp(case, Settings(tolerance=TOL), D_STEP * np.arange(1, STEPS + 1))
        lines.append(f"| 2^{e} | {med(rows, 'it'):.0f} | {max(r['it'] for r in rows)} | {med(rows, 'pairs'):.0f} | "
                     f"{med(rows, 's'):.3g} |")
        print(f"  scaling 2^{e}: {[r['it'] for r in rows]}", flush=True)
    lines.append("")


def section_full_contact(e, use_tamaas, lines):
    case = bg.Case(2**e, "hard-wall", 0.0)
    d_max = float(np.mean(case.h) - np.min(case.h))
    fractions = np.array([0.2, 0.4, 0.6, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.998, 0.999, 0.9995])
    tam = tamaas_solver(case) if use_tamaas else None
    rows = ramp(case, Settings(tolerance=TOL), fractions * d_max, tamaas=tam)
    lines += [f"## 4. Towards full contact (hard wall, N = 2^{e}, δ_max = mean h − min h = {d_max * 1e9:.3g} nm)", "",
              "| δ/δ_max | a_rel | p/E* | CG it | pairs | s | KKT residual | converged | Tamaas s | Tamaas gap spread (h_rms) |",
              "|---|---|---|---|---|---|---|---|---|---|"]
    e_star = case.model.contact_modulus
    for f, r in zip(fractions, rows):
        tcols = f"{r['tm_s']:.3g} | {r['tm_spread']:.1g}" if use_tamaas else "– | –"
        lines.append(f"| {f:g} | {r['a']:.3f} | {r['p'] / e_star:.3g} | {r['it']} | {r['pairs']:.0f} | {r['s']:.3g} | "
                     f"{r['res']:.2g} | {r['conv']} | {tcols} |")
    lines.append("")
    print(f"  full contact: a_rel {[round(r['a'], 3) for r in rows]} its {[r['it'] for r in rows]}", flush=True)


FIG3 = (("hard-wall", 0.0), ("cohesive", 0.001), ("cohesive", 0.005), ("cohesive", 0.01), ("cohesive", 0.05),
        ("cohesive", 0.15))


def section_fig3(e, window, lines):
    """Steps/CPU-s on a window of the Fig. 3 ramp (dU = 0.1 nm) at δ ≈ 10 nm, per interface."""
    n = 2**e
    lines += [f"## 5. Fig. 3 study projection (N = 2^{e}, dU = 0.1 nm: 200 steps to δ = 20 nm)", "",
              f"Each interface: approach with 1 nm steps (tolerance 1e-6, untimed) to δ = 10 nm, then {window} timed "
              "steps of 0.1 nm at tolerance 1e-10, warm-started as contact.ramp does; CPU time (process_time) "
              "per step. Projection: 10 realizations × 200 steps per interface on 2 cores (ideal "
              "process-level scaling: two independent single-threaded processes).", "",
              "| interface | it/step | CPU s/step | steps per CPU-s |", "|---|---|---|---|"]
    total = 0.0
    for law, phi in FIG3:
        case = bg.Case(n, law, phi)
        st = Settings(tolerance=TOL)
        coarse = Settings(tolerance=1e-6)
        u = np.zeros((1, n // 2 + 1), complex)
        start = -case.d0 if law == "cohesive" else 0.0
        for delta in np.arange(start, 10e-9 - 0.2e-9, 1e-9):
            u = case.relax(delta, u, coarse).u_hat
        prev = u
        u = case.relax(10e-9 - 0.1e-9, u, st).u_hat
        cpu, its = [], []
        for k in range(window):
            guess = 2 * u - prev
            t = time.process_time()
            r = case.relax(10e-9 + k * 0.1e-9, guess, st)
            cpu.append(time.process_time() - t)
            its.append(r.iterations)
            prev, u = u, r.u_hat
        c = float(np.mean(cpu))
        total += c * 200 * 10
        name = "hard wall" if law == "hard-wall" else f"φn* = {phi:g}"
        lines.append(f"| {name} | {np.median(its):.0f} | {c:.3g} | {1 / c:.3g} |")
        print(f"  fig3 {name}: {c:.3g} CPU s/step", flush=True)
    lines += ["", f"Projected: {total:.0f} CPU-s = {total / 3600:.2f} CPU-hours; on 2 cores "
              f"{total / 2 / 3600:.2f} h wall (ideal scaling).", ""]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="N = 2^14 only, short sections (≈ 1 min)")
    ap.add_argument("--no-tamaas", action="store_true", help="skip the Tamaas columns")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results")
    ap.add_argument("--sections", default="1,2,3,4,5")
    a = ap.parse_args(argv)
    use_tamaas = tm is not None and not a.no_tamaas
    if tm is None and not a.no_tamaas:
        print("Tamaas is not installed (pip install 'gfmd-contact[bench]'): the comparison columns are skipped.")
    if tm is not None:
        tm.set_log_level(tm.LogLevel.error)
    info = bg.machine_info()
    info["fft backend"] = gsolver.fft_backend()
    info["tamaas"] = tm.__version__ if tm is not None else "not installed"
    sections = {int(x) for x in a.sections.split(",")}
    lines = ["# GFMD vs Tamaas, hard-wall solver levers" + (" (quick)" if a.quick else ""), "",
             "Machine: " + "; ".join(f"{k} = {v}" for k, v in info.items()), "",
             "Generated by `python benchmarks/bench_vs_tamaas.py" + (" --quick" if a.quick else "") +
             "`; every ratio is measured within this one process (2 shared cores, noisy).", ""]
    t0 = time.perf_counter()
    sizes = (14,) if a.quick else (16, 17)
    hard = {}
    if 1 in sections:
        hard = section_hard_wall(sizes, use_tamaas, lines)
    if 2 in sections:
        e = 14 if a.quick else 16
        if (e, "cg") not in hard:
            case = bg.Case(2**e, "hard-wall", 0.0)
            hard[(e, "cg")] = med(ramp(case, Settings(tolerance=TOL), D_STEP * np.arange(1, STEPS + 1)), "s")
        section_cohesive(e, lines, hard[(e, "cg")])
    if 3 in sections:
        section_scaling(range(12, 15) if a.quick else range(12, 19), lines)
    if 4 in sections:
        section_full_contact(12 if a.quick else 14, use_tamaas, lines)
    if 5 in sections:
        section_fig3(12 if a.quick else 17, 3 if a.quick else 10, lines)
    lines.append(f"Total benchmark time {time.perf_counter() - t0:.0f} s; load average at end "
                 + " ".join(f"{v:.2f}" for v in os.getloadavg()) + ".")
    text = "\n".join(lines) + "\n"
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / f"bench_vs_tamaas{'_quick' if a.quick else ''}.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
