"""GFMD against Tamaas (PolonskyKeerRey) on the same loads, and the hard-wall solver levers, in one run.

Usage: python benchmarks/bench_vs_tamaas.py [--quick] [--out DIR] [--no-tamaas]

Scene (SI, gfmd_contact.core.conventions): the profile of benchmarks/bench_gfmd.py (default scene,
self-affine H = 0.8, h_rms = 10 nm, ν = 0.45, L = 1.28 µm, λr = L/8, λs = max(4 l, L/4096)),
realization 0, half-plane. Ramp: 10 equal steps of 1.5 nm from first touch (δ = 1.5 … 15 nm),
tolerance 1e-10. GFMD warm-starts like `gfmd_contact.core.ramp` (the last state, from the third step on
the extrapolation 2u_k − u_{k−1}); Tamaas keeps its pressure field between solves (its own warm
start) and is given the mean pressure GFMD found at each step; it gets −h, since it puts contact
at the maximum of its surface. Both run on one thread (OMP/OpenBLAS pinned to 1; GFMD's FFTs
are single-threaded).

Sections (every time is a median over steps, and ratios are taken within this one process, on
the same loads, seconds apart: the machine is shared and noisy):

1. hard wall at N = 2^16, 2^17 (``--sizes 16,18``: those): per variant (``fire``: the FIRE hard wall
   before issue 13 with scipy.fft; ``cg-primal``: the projected CG on the displacements alone,
   `dual_contact_limit = 0`, the default before the dual; ``cg-scipy``: the default hard wall (the
   two-level dual CG on the contact pressures while the contact set is small) with scipy.fft;
   ``cg-band``: the dual CG with the band preconditioner alone, `dual_coarse_block = 0`, the default
   before issue 24; ``cg``: the default with the default FFT backend) iterations, FFT pairs, s/step, s per FFT pair, the KKT residual of every step
   (the solver's residual: max |net nodal force| / p_ref, pulling wall nodes included; the
   state never penetrates), and Tamaas' s/step on the same pressures, GFMD/Tamaas (the default's ramp and
   Tamaas' each whole, in turn, `blocks`; and the ratio with each Tamaas solve interleaved after the GFMD step);
2. cohesive φn* ∈ {0.01, 0.15} × δn ∈ {0.25, 1} nm on the same profile and ramp (N = 2^16, 2^17):
   the levers side by side (FIRE with scipy.fft = before issue 13, FIRE with ducc0, NCG with
   scipy.fft and ducc0, with the numpy and the fused numba kernels of gfmd.kernels), s/step relative
   to the hard-wall CG step re-measured just before each row (NCG and hard wall: each step's fastest
   of 3 runs);
3. iterations per step vs N (N = 2^12 … 2^18): hard-wall CG and cohesive NCG;
4. near full contact: δ up to 0.99999 δ_max (δ_max = mean h − min h) at N = 2^14, a_rel, iterations,
   hard wall (with Tamaas) and cohesive NCG;
5. the seed's Fig. 3 study projected from steps per CPU-second measured at N = 2^17 on a
   window of its ramp (200 steps to δ = 20 nm: dU = 0.1 nm; 6 interfaces, 10 realizations,
   2 cores), cohesive FIRE (before) and NCG (now) from the same approach state;
6. process-level parallel efficiency of 2 realizations on 2 cores (serial vs a 2-process pool);
7. the dual against the primal hard-wall CG by contact fraction (N = 2^16, --quick 2^14; the ramp of
   section 4 up to δ = 0.9 δ_max), each alone on the same steps: the measurement behind
   `Settings.dual_contact_limit`;
8. where the hard-wall iterations go as N grows (N = 2^12 … 2^18): the 1.5 nm ramp, the Fig. 3 step of
   0.1 nm, and CG on the converged contact set held fixed (the linear part, without set changes).

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
from gfmd import kernels as gkernels  # noqa: E402
from gfmd import fft as gfft  # noqa: E402
from gfmd.algorithms import hard_wall_dual_cg  # noqa: E402
from gfmd.problem import Elastic  # noqa: E402
from gfmd.solver import Settings  # noqa: E402

try:
    import tamaas as tm
except ImportError:  # optional
    tm = None

TOL = 1e-10
BLOCK_ROUNDS = 3  # section 1: the default's ramp and Tamaas', each whole, in turn this many times (`blocks`)
REPEATS = 3  # section 2: the NCG and hard-wall steps' times are the fastest of this many runs
D_STEP = 1.5e-9
STEPS = 10


def ramp(case, settings, deltas, backend=None, tamaas=None):
    """GFMD steps at penetrations `deltas` (warm-started as gfmd_contact.core.ramp does); list of dicts."""
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
               "conv": r.converged, "method": r.method, "p": p, "a": float(np.mean(contact)),
               "pen": float(max(0.0, -np.min(r.gap))) / h_rms if case.law.constraint else 0.0, "u": r.u_z,
               "t_z": r.t_z}
        if tamaas is not None:
            row.update(tamaas(p))
        rows.append(row)
        prev, u = (u, r.u_hat) if r.converged else (prev, u)
    os.environ.pop("GFMD_FFT", None)
    return rows


def fastest_of(repeats, case, settings, deltas, backend=None):
    """`ramp` run `repeats` times (the steps are deterministic): each step's time is its fastest run,
    the robust estimate on a shared machine whose speed drifts by tens of per cent within seconds."""
    runs = [ramp(case, settings, deltas, backend) for _ in range(repeats)]
    rows = runs[0]
    for k, row in enumerate(rows):
        row["s"] = min(run[k]["s"] for run in runs)
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
    fft = gfft.Fft(n, backend)
    x = np.random.default_rng(0).standard_normal(n)
    for _ in range(3):
        fft.irfft(fft.rfft(x))
    samples = []
    for _ in range(max(20, int(4e6 // n))):
        t = time.perf_counter()
        fft.irfft(fft.rfft(x))
        samples.append(time.perf_counter() - t)
    return float(np.median(samples))


def blocks(case, settings, deltas, backend):
    """(rows, Tamaas s/step, interleaved rows): the default hard wall's whole ramp, then Tamaas' on its mean pressures
    (a fresh solver: its own warm start from the first load), in turn BLOCK_ROUNDS times; rows carry each step's median
    time over the rounds ("s") and the last round's Tamaas fields; Tamaas s/step the median over rounds of its median.
    Each solver runs its ramp with its own data in the caches, as a user runs it. The interleaved rows: one more ramp
    with each Tamaas solve right after the GFMD step (the measurement before session 48: the GFMD step then starts
    on caches that Tamaas' solve has just filled; both ratios side by side in the results file)."""
    interleaved = ramp(case, settings, deltas, backend, tamaas_solver(case))
    times, tm_times, rows = [], [], None
    for _ in range(BLOCK_ROUNDS):
        rows = ramp(case, settings, deltas, backend)
        times.append([r["s"] for r in rows])
        tam = tamaas_solver(case)
        tm_rows = [tam(r["p"]) for r in rows]
        tm_times.append(float(np.median([t["tm_s"] for t in tm_rows])))
    for r, t, s in zip(rows, tm_rows, np.median(times, axis=0)):
        r.update(t, s=float(s))
    return rows, float(np.median(tm_times)), interleaved


def med(rows, key):
    return float(np.median([r[key] for r in rows]))


def section_hard_wall(sizes, use_tamaas, lines):
    lines += ["## 1. Hard wall, 10 steps of 1.5 nm from first touch, tolerance 1e-10", "",
              "Per N: one row per GFMD variant (medians over the 10 steps; `max KKT` is the largest "
              "residual over the steps, in p_ref = E*ḡ; `pen` the largest penetration in h_rms, "
              "exactly 0 by construction), then Tamaas on the mean pressures of the `cg` row. "
              "`s/pair` = s/step ÷ pairs/step; `pair` the backend's measured rfft+irfft time. The `cg` row and "
              f"Tamaas: each whole ramp in turn, {BLOCK_ROUNDS} rounds (each step's median over them; `blocks`); "
              "`cg interleaved`: one more ramp with each Tamaas solve right after the GFMD step (as before "
              "session 48).", "",
              "| N | code | it/step | pairs/step | s/step | s/pair | pair (s) | s/pair ÷ pair | max KKT | pen | "
              "a_rel last | GFMD/Tamaas |", "|" + "---|" * 12]
    summary = {}
    for e in sizes:
        n = 2**e
        case = bg.Case(n, "hard-wall", 0.0)
        deltas = D_STEP * np.arange(1, STEPS + 1)
        variants = [("fire", Settings(tolerance=TOL, hard_wall="fire"), "scipy"),
                    ("cg-primal", Settings(tolerance=TOL, dual_contact_limit=0.0), None),
                    ("cg-scipy", Settings(tolerance=TOL), "scipy"),
                    ("cg-band", Settings(tolerance=TOL, dual_coarse_block=0), None),
                    ("cg", Settings(tolerance=TOL), None)]
        results = {}
        for name, st, backend in variants:  # with Tamaas, the `cg` ramp here is the warm-up that `blocks` replaces
            results[name] = ramp(case, st, deltas, backend)
            print(f"  N=2^{e} {name}: its {[r['it'] for r in results[name]]}", flush=True)
        t_tm = None
        if use_tamaas:  # the default's ramp and Tamaas' on its loads, each whole, in turn (BLOCK_ROUNDS)
            results["cg"], t_tm, interleaved = blocks(case, variants[-1][1], deltas, variants[-1][2])
            results["cg, interleaved"] = interleaved
        for name, st, backend in variants + ([("cg, interleaved", variants[-1][1], variants[-1][2])]
                                             if use_tamaas else []):
            rows = results[name]
            if name == "cg, interleaved":  # the ratio as measured before session 48
                t_int = med(rows, "tm_s")
                lines.append(f"| 2^{e} | cg interleaved: each Tamaas solve right after the GFMD step | "
                             f"{med(rows, 'it'):.0f} | {med(rows, 'pairs'):.0f} | {med(rows, 's'):.3g} | | | | | | | "
                             f"{med(rows, 's') / t_int:.3f} (1/{t_int / med(rows, 's'):.1f}; Tamaas {t_int:.3g} s) |")
                continue
            b = gfft.fft_backend(backend)
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


COHESIVE = ((0.01, 0.25e-9), (0.01, 1e-9), (0.15, 0.25e-9), (0.15, 1e-9))


def section_cohesive(sizes, lines):
    """Cohesive vs hard wall on the same profile and ramp; FIRE (scipy, ducc0) and NCG (scipy, ducc0; numpy and
    numba kernels)."""
    lines += ["## 2. Cohesive vs hard wall, same profile and ramp", "",
              "Per N and law: the levers side by side in this process, seconds apart: `fire (scipy)` is the "
              "cohesive solver before issue 13 (FIRE, scipy.fft), `fire (ducc0)` the FFT-backend lever alone, "
              "`ncg` the nonlinear preconditioned CG (Settings.cohesive = \"ncg\", the default; `scipy` / `ducc0`: its "
              "FFT, `numpy kernels` / `numba kernels`: its spectral algebra, gfmd.kernels, GFMD_JIT; the default is "
              "the last row). Same 10-step ramp as section 1; the first step starts from the flat surface "
              "at δ = 1.5 nm (jump-in). `hard/s` = the hard-wall `cg` median s/step, measured again on the same "
              "ramp just before each row (seconds apart: the machine's speed drifts by tens of per cent over a "
              f"run); `ratio (row)` = s/step ÷ that row's hard/s, `ratio` = s/step ÷ the median hard/s of all the "
              f"N's rows (the target: ≤ 2; one slow hard-wall run moves the first, not the second). The hard-wall "
              f"and `ncg` times are "
              f"each step's fastest of {REPEATS} runs (`fastest_of`), the FIRE rows one run. `|Δu| / δn`: largest nodal difference "
              "to the `fire (scipy)` states (tolerance 1e-10 p_ref); `method`: what `Relaxed.method` reported "
              "(a fallback would read ncg→fire).", ""]
    summary = {}
    for e in sizes:
        n = 2**e
        deltas = D_STEP * np.arange(1, STEPS + 1)
        hard_case = bg.Case(n, "hard-wall", 0.0)
        hard_rows = ramp(hard_case, Settings(tolerance=TOL), deltas)
        hard_s = med(hard_rows, "s")
        pair = {b: pair_seconds(n, b) for b in ("scipy", gfft.fft_backend())}
        lines += [f"N = 2^{e}: hard-wall cg {med(hard_rows, 'it'):.0f} it/step, {med(hard_rows, 'pairs'):.0f} "
                  f"pairs/step, hard/s = {hard_s:.3g} s/step; pair (s): "
                  + ", ".join(f"{b} {t:.3g}" for b, t in pair.items()), "",
                  "| N | law | δn (nm) | code | it/step | pairs/step | s/step | s/pair | s/pair ÷ pair | hard/s | "
                  "ratio (row) | ratio | max residual | converged | max |Δu| / δn | method |", "|" + "---|" * 16]
        pending, keys = [], []  # (row text before the ratios, s/step, hard/s, row text after); its keys
        for phi, dn in COHESIVE:
            case = cohesive_case(n, phi, dn)
            variants = [("fire", Settings(tolerance=TOL, cohesive="fire"), "scipy", "numpy"),
                        ("fire", Settings(tolerance=TOL, cohesive="fire"), None, "numpy"),
                        ("ncg", Settings(tolerance=TOL), "scipy", "numpy"),
                        ("ncg", Settings(tolerance=TOL), None, "numpy"),
                        ("ncg", Settings(tolerance=TOL), None, None)]
            base = None
            for name, st, backend, jit in variants:
                b = gfft.fft_backend(backend)
                if backend is None and b == "scipy":
                    continue  # no ducc0: the scipy row is all there is
                if jit is None and gkernels.jit_backend() == "numpy":
                    continue  # no numba: the numpy-kernel row is all there is
                if name == "ncg":
                    os.environ["GFMD_JIT"] = jit or gkernels.jit_backend()
                    b += ", " + os.environ["GFMD_JIT"] + " kernels"
                hard_s = med(fastest_of(REPEATS, hard_case, Settings(tolerance=TOL), deltas), "s")
                rows = fastest_of(REPEATS, case, st, deltas, backend) if name == "ncg" else ramp(case, st, deltas,
                                                                                                  backend)
                base = base or rows
                keys.append((phi, dn, name, b))
                s_step, pairs = med(rows, "s"), med(rows, "pairs")
                du = max(float(np.max(np.abs(r["u"] - q["u"]))) for r, q in zip(rows, base)) / dn
                methods = "/".join(sorted({r["method"] for r in rows}))
                pending.append((f"| 2^{e} | φn* = {phi:g} | {dn * 1e9:g} | {name} ({b}) | {med(rows, 'it'):.0f} | "
                                f"{pairs:.0f} | {s_step:.3g} | {s_step / pairs:.3g} | "
                                f"{s_step / pairs / pair[b.split(',')[0]]:.2f} | {hard_s:.3g} | ", s_step, hard_s,
                                f" | {max(r['res'] for r in rows):.2g} | "
                                f"{sum(r['conv'] for r in rows)}/{len(rows)} | {du:.1g} | {methods} |"))
                os.environ.pop("GFMD_JIT", None)
                print(f"  2^{e} cohesive {phi} {dn} {name} ({b}): its {[r['it'] for r in rows]} "
                      f"{s_step:.3g} s/step = {s_step / hard_s:.2f} hard", flush=True)
        hard_med = float(np.median([h for _, _, h, _ in pending]))
        for (head, s_step, hard_s, tail), (phi, dn, name, b) in zip(pending, keys):
            lines.append(f"{head}{s_step / hard_s:.2f} | {s_step / hard_med:.2f}{tail}")
            summary[(e, phi, dn, name, b)] = s_step / hard_med
        lines += [f"Median hard/s over the rows: {hard_med:.3g} s/step.", ""]
    return summary


def section_scaling(sizes, lines):
    laws_ = (("hard wall (cg)", None), ("φn* = 0.15, δn = 1 nm (ncg)", (0.15, 1e-9)),
             ("φn* = 0.15, δn = 0.25 nm (ncg)", (0.15, 0.25e-9)))
    lines += ["## 3. Iterations per step vs N (same ramp; default solvers)", "",
              "Per law: median it/step (max) and median s/step.", "",
              "| N | " + " | ".join(f"{name}: it (max) | s/step" for name, _ in laws_) + " |",
              "|---|" + "---|---|" * len(laws_)]
    for e in sizes:
        cells = []
        for name, law in laws_:
            case = bg.Case(2**e, "hard-wall", 0.0) if law is None else cohesive_case(2**e, *law)
            rows = ramp(case, Settings(tolerance=TOL), D_STEP * np.arange(1, STEPS + 1))
            cells.append(f"{med(rows, 'it'):.0f} ({max(r['it'] for r in rows)}) | {med(rows, 's'):.3g}")
            print(f"  scaling 2^{e} {name}: {[r['it'] for r in rows]}", flush=True)
        lines.append(f"| 2^{e} | " + " | ".join(cells) + " |")
    lines.append("")


def section_full_contact(e, use_tamaas, lines):
    case = bg.Case(2**e, "hard-wall", 0.0)
    d_max = float(np.mean(case.h) - np.min(case.h))
    fractions = np.array([0.2, 0.4, 0.6, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.998, 0.999, 0.9995, 0.9999, 0.99995,
                          0.99999])
    tam = tamaas_solver(case) if use_tamaas else None
    rows = ramp(case, Settings(tolerance=TOL), fractions * d_max, tamaas=tam)
    coh = ramp(cohesive_case(2**e, 0.15, 1e-9), Settings(tolerance=TOL), fractions * d_max)
    lines += [f"## 4. Towards full contact (N = 2^{e}, δ_max = mean h − min h = {d_max * 1e9:.3g} nm)", "",
              "Hard wall (CG, with Tamaas on the same mean pressures) and the cohesive law φn* = 0.15, δn = 1 nm "
              "(NCG; a_rel: nodes in compression) on the same ramp of penetrations δ/δ_max.", "",
              "| δ/δ_max | a_rel | p/E* | CG it | pairs | s | KKT residual | converged | Tamaas s | "
              "Tamaas gap spread (h_rms) | cohesive a_rel | NCG it | NCG residual | NCG converged (method) |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    e_star = case.model.contact_modulus
    for f, r, c in zip(fractions, rows, coh):
        tcols = f"{r['tm_s']:.3g} | {r['tm_spread']:.1g}" if use_tamaas else "– | –"
        lines.append(f"| {f:g} | {r['a']:.3f} | {r['p'] / e_star:.3g} | {r['it']} | {r['pairs']:.0f} | {r['s']:.3g} | "
                     f"{r['res']:.2g} | {r['conv']} | {tcols} | {c['a']:.3f} | {c['it']} | {c['res']:.2g} | "
                     f"{c['conv']} ({c['method']}) |")
    lines.append("")
    print(f"  full contact: a_rel {[round(r['a'], 3) for r in rows]} its {[r['it'] for r in rows]}", flush=True)
    print(f"  full contact cohesive: a_rel {[round(r['a'], 3) for r in coh]} its {[r['it'] for r in coh]}", flush=True)


FIG3 = (("hard-wall", 0.0), ("cohesive", 0.001), ("cohesive", 0.005), ("cohesive", 0.01), ("cohesive", 0.05),
        ("cohesive", 0.15))


def fig3_window(e, law, phi, window, settings, realization=0, approach=None):
    """(CPU s per step list, iterations list, approach state): the Fig. 3 ramp window at δ ≈ 10 nm."""
    n = 2**e
    case = bg.Case(n, law, phi)
    if realization:
        case.h = bg.surfaces.profile(case.scene.surface, realization)
        case.model = bg.build_model(case.scene, case.h)
        case.law = bg.InterfaceLaw(case.model)
    if approach is None:
        coarse = Settings(tolerance=1e-6)
        u = np.zeros((1, n // 2 + 1), complex)
        start = -case.d0 if law == "cohesive" else 0.0
        for delta in np.arange(start, 10e-9 - 0.2e-9, 1e-9):
            u = case.relax(delta, u, coarse).u_hat
        approach = u
    prev = approach
    u = case.relax(10e-9 - 0.1e-9, approach, settings).u_hat
    cpu, its, methods = [], [], set()
    for k in range(window):
        guess = 2 * u - prev
        t = time.process_time()
        r = case.relax(10e-9 + k * 0.1e-9, guess, settings)
        cpu.append(time.process_time() - t)
        its.append(r.iterations)
        methods.add(r.method)
        prev, u = u, r.u_hat
    return cpu, its, approach, methods


def section_fig3(e, window, lines):
    """Steps/CPU-s on a window of the Fig. 3 ramp (dU = 0.1 nm) at δ ≈ 10 nm, per interface."""
    lines += [f"## 5. Fig. 3 study projection (N = 2^{e}, dU = 0.1 nm: 200 steps to δ = 20 nm)", "",
              f"Each interface: approach with 1 nm steps (tolerance 1e-6, untimed) to δ = 10 nm, then {window} timed "
              "steps of 0.1 nm at tolerance 1e-10, warm-started as gfmd_contact.core.ramp does; CPU time (process_time) "
              "per step. Cohesive interfaces: the same window from the same approach state with the cohesive "
              "solver before issue 13 (FIRE, scipy.fft) and the default now (NCG, default FFT backend). "
              "Projection: 10 realizations × 200 steps per interface on 2 cores (ideal process-level scaling; "
              "section 6 measures it).", "",
              "| interface | code | it/step | CPU s/step | steps per CPU-s |", "|---|---|---|---|---|"]
    totals = {"before": 0.0, "now": 0.0}
    for law, phi in FIG3:
        name = "hard wall" if law == "hard-wall" else f"φn* = {phi:g}"
        codes = [("now", "cg" if law == "hard-wall" else "ncg", Settings(tolerance=TOL), None)]
        if law == "cohesive":
            codes.insert(0, ("before", "fire (scipy)", Settings(tolerance=TOL, cohesive="fire"), "scipy"))
        approach = None
        for tag, code, st, backend in codes:
            if backend:
                os.environ["GFMD_FFT"] = backend
            cpu, its, approach, methods = fig3_window(e, law, phi, window, st, approach=approach)
            os.environ.pop("GFMD_FFT", None)
            c = float(np.mean(cpu))
            if law == "hard-wall":
                totals["before"] += c * 200 * 10
            totals[tag] += c * 200 * 10
            lines.append(f"| {name} | {code} ({'/'.join(sorted(methods))}) | {np.median(its):.0f} | {c:.3g} | "
                         f"{1 / c:.3g} |")
            print(f"  fig3 {name} {code}: {c:.3g} CPU s/step, its {its}", flush=True)
    lines.append("")
    for tag, label in (("before", "cohesive FIRE (scipy.fft), hard wall cg"), ("now", "default solvers")):
        total = totals[tag]
        lines.append(f"Projected, {label}: {total:.0f} CPU-s = {total / 3600:.2f} CPU-hours; on 2 cores "
                     f"{total / 2 / 3600:.2f} h wall (ideal scaling).")
    lines.append("")
    return totals


def section_dual_vs_primal(e, lines):
    case = bg.Case(2**e, "hard-wall", 0.0)
    d_max = float(np.mean(case.h) - np.min(case.h))
    fractions = np.array([0.2, 0.3, 0.4, 0.5, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9])
    dual = ramp(case, Settings(tolerance=TOL, dual_contact_limit=1.0), fractions * d_max)
    primal = ramp(case, Settings(tolerance=TOL, dual_contact_limit=0.0), fractions * d_max)
    default = ramp(case, Settings(tolerance=TOL), fractions * d_max)
    limit = Settings().dual_contact_limit
    lines += [f"## 7. Dual vs primal hard-wall CG by contact fraction (N = 2^{e})", "",
              "Each alone on the same ramp (δ/δ_max, tolerance 1e-10, warm-started as above); `default`: "
              f"`dual_contact_limit = {limit}` (the dual while the contact set holds at most that fraction "
              "of the nodes, else the primal).", "",
              "| δ/δ_max | a_rel | dual it | dual pairs | dual s | primal it | primal pairs | primal s | "
              "dual/primal s | default method | default s |", "|" + "---|" * 11]
    for f, a, b, c in zip(fractions, dual, primal, default):
        lines.append(f"| {f:g} | {b['a']:.4f} | {a['it']} | {a['pairs']:.0f} | {a['s']:.3g} | {b['it']} | "
                     f"{b['pairs']:.0f} | {b['s']:.3g} | {a['s'] / b['s']:.2f} | {c['method']} | {c['s']:.3g} |")
    lines.append("")
    print(f"  dual/primal: a_rel {[round(r['a'], 4) for r in primal]} "
          f"s ratio {[round(a['s'] / b['s'], 2) for a, b in zip(dual, primal)]}", flush=True)


def fixed_set_cg(case, pressure, band=False, rel=1e-8, max_it=1000):
    """Iterations of CG on G_AA P = b with the contact set A = {pressure > 0} held fixed (b = G_AA P,
    P the converged pressures, so the answer is known), preconditioned with K_AA exactly (one more FFT
    pair) or, band=True, with the solver's banded K_AA (`gfmd.algorithms.hard_wall_dual_cg._band_stiffness`): until
    max |P_k − P| < rel max P. The linear part of a hard-wall step, without set changes."""
    n = case.model.nodes
    act = np.flatnonzero(pressure > 0)
    k = np.real(case.model.k_zz)
    g = np.real(Elastic(case.model, 0.0, 0.0).inv_mass[0])

    fft = gfft.Fft(n)

    def on_set(kernel, v):  # (kernel χ_A v) on A: one FFT pair
        full = np.zeros(n)
        full[act] = v
        return fft.apply(kernel, full)[act]

    if band:
        k_band = hard_wall_dual_cg._band_stiffness(fft.irfft(k.astype(complex)), act, n, hard_wall_dual_cg.DUAL_BAND_HALF_WIDTH)
    precondition = (lambda v: k_band @ v) if band else (lambda v: on_set(k, v))
    p_true = pressure[act]
    b = on_set(g, p_true)
    x, r = np.zeros_like(b), b.copy()
    s = precondition(r)
    d, rz = s.copy(), float(r @ s)
    for it in range(1, max_it + 1):
        gd = on_set(g, d)
        alpha = rz / float(d @ gd)
        x += alpha * d
        r -= alpha * gd
        if np.max(np.abs(x - p_true)) < rel * np.max(p_true):
            break
        s = precondition(r)
        rz_new = float(r @ s)
        d, rz = s + (rz_new / rz) * d, rz_new
    patches = np.split(act, np.flatnonzero(np.diff(act) > 1) + 1)
    return it, act.size, len(patches), max(p.size for p in patches)


def section_iterations_in_n(sizes, lines):
    small = 0.1e-9  # the seed's Fig. 3 step: 200 steps to δ = 20 nm
    lines += ["## 8. Where the hard-wall iterations go as N grows", "",
              "Same profile at every N: λs = max(4 L/N, L/4096), so from N = 2^14 on the same surface is "
              "resolved more finely and each contact patch spans more nodes. Columns: median it/step of "
              f"the 1.5 nm ramp (section 3's); median it/step at the Fig. 3 step of {small * 1e9:g} nm (10 "
              "steps after 5 of 1.5 nm and 2 more at 0.1 nm; in brackets how many of the 10 passed with the "
              "extrapolated guess alone, 0 iterations); the contact set at the end of the 1.5 nm ramp "
              "(nodes, patches, largest patch); and the iterations CG needs on that set held fixed with the "
              "exact K_AA preconditioner and with the solver's band of it (`fixed_set_cg`, to 1e-8 of max "
              "P): the linear part. The rest of a 1.5 nm step is set "
              "changes: the nodes that penetrate after the guess join at once, and the Polonsky–Keer "
              "projections then release the surplus over the next iterations (a restart each time).", "",
              "| N | it/step, 1.5 nm steps | it/step, 0.1 nm steps (0-iteration steps) | contact nodes | "
              "patches | largest patch | fixed-set CG it, K_AA | fixed-set CG it, band |",
              "|---|---|---|---|---|---|---|---|"]
    for e in sizes:
        case = bg.Case(2**e, "hard-wall", 0.0)
        big = ramp(case, Settings(tolerance=TOL), D_STEP * np.arange(1, STEPS + 1))
        deltas = np.r_[D_STEP * np.arange(1, 6), 5 * D_STEP + small * np.arange(1, 13)]
        fine = ramp(case, Settings(tolerance=TOL), deltas)[7:]
        pressure = -big[-1]["t_z"]  # the contact pressures at the end of the 1.5 nm ramp
        it_lin, nodes, patches, largest = fixed_set_cg(case, pressure)
        it_band = fixed_set_cg(case, pressure, band=True)[0]
        zero = sum(r["it"] == 0 for r in fine)
        lines.append(f"| 2^{e} | {med(big, 'it'):.0f} | {med(fine, 'it'):.0f} ({zero}) | {nodes} | {patches} | "
                     f"{largest} | {it_lin} | {it_band} |")
        print(f"  section 8, 2^{e}: {[r['it'] for r in big]} / {[r['it'] for r in fine]} / {it_lin}, {it_band}", flush=True)
    lines.append("")


def _parallel_job(args):
    e, realization, window = args
    t = time.perf_counter()
    fig3_window(e, "cohesive", 0.15, window, Settings(tolerance=TOL), realization=realization)
    return time.perf_counter() - t


def section_parallel(e, window, lines, fig3_totals=None):
    """Process-level parallel efficiency: 2 realizations one after the other, then in 2 processes."""
    import multiprocessing as mp

    jobs = [(e, 0, window), (e, 1, window)]
    t0 = time.perf_counter()
    serial = [_parallel_job(j) for j in jobs]
    t_serial = time.perf_counter() - t0
    ctx = mp.get_context("fork")
    t0 = time.perf_counter()
    with ctx.Pool(2) as pool:
        each = pool.map(_parallel_job, jobs)
    t_par = time.perf_counter() - t0
    eff = t_serial / (2 * t_par)
    lines += [f"## 6. Parallel efficiency, 2 realizations on 2 cores (N = 2^{e}, φn* = 0.15, NCG)", "",
              f"Each job: the section-5 approach and {window}-step window of realization 0 or 1 (the work of "
              "`gfmd_contact.app.ensemble.run_ensemble` with output.workers = 2, one realization per process). Serial: "
              "one after the other in this process; parallel: a 2-process pool (fork), wall time incl. start-up. "
              "Other jobs share the 2 cores (load average in the header and at the end): the efficiency is a "
              "lower bound.", "",
              "| serial wall (s) | per job serial (s) | parallel wall (s) | per job in parallel (s) | efficiency "
              "t_serial / (2 t_parallel) |", "|---|---|---|---|---|",
              f"| {t_serial:.1f} | {serial[0]:.1f}, {serial[1]:.1f} | {t_par:.1f} | {each[0]:.1f}, {each[1]:.1f} | "
              f"{eff:.2f} |", ""]
    if fig3_totals:
        total = fig3_totals["now"]
        lines += [f"Fig. 3 projection with this efficiency: {total / (2 * eff) / 3600:.2f} h wall on 2 cores.", ""]
    print(f"  parallel: serial {t_serial:.1f} s, parallel {t_par:.1f} s, efficiency {eff:.2f}", flush=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="N = 2^14 only, short sections (≈ 1 min)")
    ap.add_argument("--no-tamaas", action="store_true", help="skip the Tamaas columns")
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results")
    ap.add_argument("--sections", default="1,2,3,4,5,6,7,8")
    ap.add_argument("--sizes", default="", help="section 1's log2 N, comma-separated (default 16,17; --quick 14)")
    ap.add_argument("--suffix", default="", help="appended to the results file name")
    a = ap.parse_args(argv)
    use_tamaas = tm is not None and not a.no_tamaas
    if tm is None and not a.no_tamaas:
        print("Tamaas is not installed (pip install 'gfmd-contact[bench]'): the comparison columns are skipped.")
    if tm is not None:
        tm.set_log_level(tm.LogLevel.error)
    info = bg.machine_info()
    info["fft backend"] = gfft.fft_backend()
    info["tamaas"] = tm.__version__ if tm is not None else "not installed"
    sections = {int(x) for x in a.sections.split(",")}
    lines = ["# GFMD vs Tamaas, hard-wall and cohesive solver levers" + (" (quick)" if a.quick else ""), "",
             "Machine: " + "; ".join(f"{k} = {v}" for k, v in info.items()), "",
             "Generated by `python benchmarks/bench_vs_tamaas.py" + (" --quick" if a.quick else "") +
             "`; every ratio is measured within this one process (2 shared cores, noisy).", ""]
    t0 = time.perf_counter()
    sizes = tuple(int(x) for x in a.sizes.split(",")) if a.sizes else ((14,) if a.quick else (16, 17))
    if 1 in sections:
        section_hard_wall(sizes, use_tamaas, lines)
    if 2 in sections:
        section_cohesive(sizes, lines)
    if 3 in sections:
        section_scaling(range(12, 15) if a.quick else range(12, 19), lines)
    if 4 in sections:
        section_full_contact(12 if a.quick else 14, use_tamaas, lines)
    totals = None
    if 5 in sections:
        totals = section_fig3(12 if a.quick else 17, 3 if a.quick else 10, lines)
    if 6 in sections:
        section_parallel(12 if a.quick else 17, 3 if a.quick else 10, lines, totals)
    if 7 in sections:
        section_dual_vs_primal(14 if a.quick else 16, lines)
    if 8 in sections:
        section_iterations_in_n(range(12, 15) if a.quick else range(12, 19), lines)
    lines.append(f"Total benchmark time {time.perf_counter() - t0:.0f} s; load average at end "
                 + " ".join(f"{v:.2f}" for v in os.getloadavg()) + ".")
    text = "\n".join(lines) + "\n"
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / f"bench_vs_tamaas{'_quick' if a.quick else ''}{a.suffix}.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
