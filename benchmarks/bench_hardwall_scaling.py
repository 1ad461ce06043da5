"""Hard-wall FFT pairs per step against N (issue 24, "hard wall flat in N"), the solvers side by side.

Usage: python benchmarks/bench_hardwall_scaling.py [--quick] [--out DIR] [--sizes 12 14 ...] [--task 17 ...]

Scene (SI): the seed's Fig. 3 scene (studies/seed/seed_base.toml, fig3.toml's hard-wall row: H = 0.8,
h_rms = 10 nm, ν = 0.45, L = 10.24 µm, L/λr = 8, λs = 2.5 nm, so λr/λs = 512) at N = 2^12 … 2^20
(--quick: up to 2^16); below N = 2^14, where λs = 2.5 nm would be under 4 nodes, λs = 4 L/N (as
benchmarks/bench_gfmd.py). N = 2^17 is the seed's full scale (32 nodes per λs). Realization 0 (seed 1).

Ramps from first touch, warm-started as `gfmd_contact.core.ramp` (the last state, from the third step on the
extrapolation 2u_k − u_{k−1}), tolerance 1e-8 (the studies'):
* 1.5 nm steps: δ = 1.5 … 12 nm (8 steps, all counted);
* the Fig. 3 step, 0.1 nm, in three windows: δ to 7.5 nm, 19.5 nm (the end of Fig. 3's ramp, δ = 20 nm) and
  28.5 nm (a_rel ≈ 6 %, beyond Fig. 3, N ≤ 2^17: where the coarse level's cost gate,
  `gfmd.algorithms.hard_wall_two_level_cg.COARSE_ENTRIES_PER_NODE`, leaves the band alone) in 1.5 nm steps
  (not counted), two 0.1 nm steps (not counted), then 8 steps of 0.1 nm (counted);
* a whole Fig. 3 hard-wall task at N = 2^17 (the seed's scale; not with --quick): 200 steps from δ = −12 nm
  (fig3.toml's initial separation) to 20 nm, every step counted.
Per solver variant and N: iterations per step (median, max), FFT pairs per step (median, max; counted by
the solvers: deterministic, independent of load), the max KKT residual over the counted steps (the solver's
residual: max |net nodal force| / p_ref, pulling wall nodes included) and the worst penetration / h_rms
(both recomputed here from the returned fields, independently of the solver's own check), and s/step
(median; measured on a shared, loaded machine: indicative only).

Writes benchmarks/results/bench_hardwall_scaling{,_quick}.md and .csv (every counted step: iterations, FFT
pairs, KKT residual, penetration, a_rel, converged, algorithm, s).
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from pathlib import Path

# before numpy loads BLAS: one thread (the timings are single-threaded); hence the E402 imports below
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
import scipy.fft  # noqa: E402

# the script runs from anywhere: the repository goes on sys.path before the project imports (E402)
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gfmd_contact.core import surfaces  # noqa: E402
from gfmd_contact.core.loading import indenter_surface  # noqa: E402
from gfmd_contact.core.model import build_model  # noqa: E402
from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd.chains import relax  # noqa: E402
from gfmd.problem import InterfaceLaw, wall_net_force  # noqa: E402
from gfmd.settings import Settings  # noqa: E402

TOL = 1e-8  # the studies' tolerance (seed_base.toml)
BIG, SMALL = 1.5e-9, 0.1e-9
#: the .csv's columns per counted step (res: the KKT residual, max |net nodal force| / p_ref)
STEP_COLUMNS = ("it", "pairs", "res", "pen", "a", "conv", "method", "s")
#: the solvers compared: label → Settings (the hard wall's chain is `gfmd.chains.chain_key`'s choice)
VARIANTS = {"dual CG, band (before)": Settings(tolerance=TOL, dual_coarse_block=0),
            "two-level dual CG (now)": Settings(tolerance=TOL)}


def fig3_hard_wall(n):
    """(scene, profile, model, law, wall tolerance) of fig3.toml's hard-wall row at N = n."""
    base = load_scene(ROOT / "studies" / "seed" / "seed_base.toml")
    length = base.surface.length
    scene = base.replace(**{"surface.nodes": n, "interface.law": "hard-wall",
                            "surface.rollon_wavelength": max(4 * length / n, base.surface.rollon_wavelength)})
    h = surfaces.profile(scene.surface, 0)
    model = build_model(scene, h)
    law = InterfaceLaw(model, scene.interface, scene.work_tangential)
    return scene, h, model, law, 1e-12 * max(float(np.ptp(h)), scene.interface.length_normal)


def kkt(model, z, r, wall_tol):
    """(max |net nodal force| / p_ref, max penetration (m)) of the returned u_z, recomputed here."""
    n = model.nodes
    net, _ = wall_net_force(model, np.real(model.k_zz), r.u_z, z - r.u_z <= wall_tol, n)
    return float(np.max(np.abs(net))) / model.reference_traction, max(0.0, float(np.max(r.u_z - z)))


def ramp(n, settings, deltas, counted):
    """Rows (dicts) of the counted steps of a warm-started ramp at penetrations `deltas`."""
    scene, h, model, law, wall_tol = fig3_hard_wall(n)
    d0 = scene.loading.initial_separation
    u = prev = np.zeros((1, n // 2 + 1), complex)
    rows = []
    for k, delta in enumerate(deltas):
        z = indenter_surface(h, d0, delta + d0)
        guess = 2 * u - prev if k >= 2 else u
        t = time.perf_counter()
        r = relax(model, law, z, guess, settings, wall_tol)
        dt = time.perf_counter() - t
        if not r.converged:
            print(f"    N={n} δ={delta:.3g}: not converged: {r.message}", flush=True)
        if k >= len(deltas) - counted:
            res, pen = kkt(model, z, r, wall_tol)
            rows.append({"it": r.iterations, "pairs": r.fft_pairs, "res": max(r.residual, res), "pen": pen / np.std(h),
                         "s": dt, "conv": r.converged, "method": r.method, "a": float(np.mean(r.gap <= wall_tol))})
        prev, u = u, r.u_hat
    return rows


def summary(rows):
    it = [r["it"] for r in rows]
    pairs = [r["pairs"] for r in rows]
    methods = sorted({r["method"] for r in rows})
    return (f"{np.median(it):.0f} / {max(it)} | {np.median(pairs):.1f} / {max(pairs):.1f} | "
            f"{max(r['res'] for r in rows):.2e} | {max(r['pen'] for r in rows):.1e} | "
            f"{np.median([r['s'] for r in rows]):.3g} | {np.mean([r['a'] for r in rows]):.4f} | "
            f"{'all' if all(r['conv'] for r in rows) else 'NO'} | {', '.join(methods)} |")


def whole_task(exponents, every):
    """Table lines: FFT pairs per step over a whole Fig. 3 hard-wall task (δ from −12 nm, out of contact, to
    20 nm in 200 steps of 0.16 nm, as fig3.toml's ramp; every step counted, the out-of-contact ones too)."""
    deltas = np.linspace(-12e-9, 20e-9, 201)[1:]
    lines = ["## A whole Fig. 3 hard-wall task (200 steps, δ = −12 … 20 nm)", "",
             "| N | solver | it/step | FFT pairs/step | max KKT residual | max pen./h_rms | s/step (under load) | "
             "a_rel | converged | algorithms | FFT pairs, whole task |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for e in exponents:
        for label, settings in VARIANTS.items():
            rows = ramp(2**e, settings, deltas, deltas.size)
            every += [{"ramp": "whole task", "N": 2**e, "solver": label, "step": k, **{c: r[c] for c in STEP_COLUMNS}}
                      for k, r in enumerate(rows)]
            line = f"| 2^{e} | {label} | " + summary(rows) + f" {sum(r['pairs'] for r in rows):.0f} |"
            lines.append(line)
            print("whole task", line, flush=True)
    return lines + [""]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 2^12 … 2^16 only")
    ap.add_argument("--sizes", type=int, nargs="*", help="exponents e of N = 2^e (default 12 … 20)")
    ap.add_argument("--task", type=int, nargs="*", help="exponents of N for the whole-task table (default 17; "
                    "--quick: none)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    args = ap.parse_args(argv)
    sizes = list(range(12, 17 if args.quick else 21)) if args.sizes is None else args.sizes
    if args.task is None:
        args.task = [] if args.quick else [17]
    ramps = {}  # in the order of the report (the Fig. 3 steps first)
    for top, largest in ((5, 99), (13, 99), (19, 17)):  # δ = 7.5, 19.5, 28.5 nm (the last up to N = 2^17)
        ramps[f"0.1 nm (Fig. 3 step) at δ ≈ {top * BIG * 1e9:g} nm"] = (
            np.r_[BIG * np.arange(1, top + 1), top * BIG + SMALL * np.arange(1, 11)], 8, largest)
        if top == 13:
            ramps["whole task"] = None
    ramps["1.5 nm"] = (BIG * np.arange(1, 9), 8, 99)
    t0 = time.time()
    every = []  # every counted step: its KKT residual and counts (the .csv)
    lines = ["# Hard-wall FFT pairs per step against N (issue 24)", "",
             __doc__.split("\n\n", 2)[2].split("\nWrites")[0].strip(), "",
             "Columns: it/step median / max; FFT pairs/step median / max; max KKT residual (p_ref) and "
             "max penetration / h_rms over the counted steps; s/step median (**measured under load**, 2 cores "
             "shared by several processes: indicative only); mean a_rel; all steps converged; the algorithms "
             "that ran.", ""]
    out = Path(args.out) / f"bench_hardwall_scaling{'_quick' if args.quick else ''}.md"

    def write(final=False):  # after every row: an interrupted run leaves what it measured
        tail = [f"Total {time.time() - t0:.0f} s; load average at end {' '.join(f'{x:.2f}' for x in os.getloadavg())}."]
        out.write_text("\n".join(lines + ([] if final else ["", "(run in progress or interrupted)"]) + tail) + "\n")
        with open(out.with_suffix(".csv"), "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=["ramp", "N", "solver", "step", *STEP_COLUMNS])
            writer.writeheader()
            writer.writerows(every)

    out.parent.mkdir(parents=True, exist_ok=True)
    for name, spec in ramps.items():
        if spec is None:
            lines += whole_task(args.task, every) if args.task else []
            write()
            continue
        deltas, counted, largest = spec
        lines += [f"## {name} steps", "", "| N | solver | it/step | FFT pairs/step | max KKT residual | "
                  "max pen./h_rms | s/step (under load) | a_rel | converged | algorithms |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for e in (e for e in sizes if e <= largest):
            for label, settings in VARIANTS.items():
                rows = ramp(2**e, settings, deltas, counted)
                every += [{"ramp": name, "N": 2**e, "solver": label, "step": k, **{c: r[c] for c in STEP_COLUMNS}}
                          for k, r in enumerate(rows)]
                line = f"| 2^{e} | {label} | " + summary(rows)
                lines.append(line)
                print(name, line, flush=True)
                write()
        lines.append("")
    write(final=True)
    print(f"wrote {out} and {out.with_suffix('.csv')}")


if __name__ == "__main__":
    main()
