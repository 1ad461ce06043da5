"""Strong adhesion and the coupled law along a ramp: iterations and FFT pairs per step (issue 24).

Usage: python benchmarks/bench_adhesion_scaling.py [--quick] [--sizes 12 14 17] [--out DIR]
                                                   [--classes cohesive coupled normal] [--compare]
                                                   [--realization SEED] [--length-normal DN]

Task classes, on the full-scale seed base scene (studies/seed/seed_base.toml, realization seed 1 unless
--realization; δn of the scene unless --length-normal) with
`surface.nodes` = N (L = 10.24 µm fixed; λs,H = max(2.5 nm, 4 L/N), i.e. 10 nm at 2^12), the ramp of
`gfmd_contact.core.loading.realization_steps` (200 steps from δ0 = 12 nm out of contact towards δ = 20 nm), stopped
after the first step whose a_rel reaches A_REL_STOP (0.5; realization seed 1 reaches 0.27 at δ = 20 nm):
  cohesive  φn* = 0.15, c = 0: the Fig. 3 strong-adhesion task (studies/seed/fig3.toml)
  coupled   φn* = 0.15, c = 0.5, δt = 1 nm: Fig. 8's coupled law (studies/seed/fig8.toml)
  normal    the same as coupled with c = 0 (Fig. 8's normal law on the same profile and ramp)

Each step is relaxed by `gfmd.chains.relax` from the ramp's warm start (linear extrapolation, retried
from the last converged state as `gfmd_contact.core.ramp.run_ramp` does); per step: iterations, FFT pairs
(rfft+irfft pairs, `Relaxed.fft_pairs`: deterministic, meaningful under load), a_rel, the chain's
label, and CPU seconds (time.process_time; the machine is shared: MEASURED UNDER LOAD, the
load average is printed). --compare runs the other solver on the same task in the same run: coupled with
Settings.coupled = "fire" (the chain before issue 24; the default, "auto", starts with Newton–Krylov). (The
trust-region Newton–CG measured for the cohesive class in results/bench_adhesion_scaling_full.md was dropped.)
Output: a markdown table per class plus a summary (mean / max pairs per step, coupled / normal ratios).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

# before numpy loads BLAS: one thread (the timings are single-threaded); hence the E402 imports below
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

# the script runs from anywhere: the repository goes on sys.path before the project imports (E402)
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gfmd_contact.core import surfaces  # noqa: E402
from gfmd_contact.core.loading import extrapolation_allowed, indenter_surface, realization_steps  # noqa: E402
from gfmd_contact.core.observables import step_observables  # noqa: E402
from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd.chains import relax  # noqa: E402
from gfmd.loading import prepare, wall_tolerance_of  # noqa: E402
from gfmd_contact.app.study import task_scene  # noqa: E402

SEED = ROOT / "studies" / "seed"
A_REL_STOP = 0.5
#: below 2^15 the base scene's λs,H = 2.5 nm is raised to ROLLON_NODES node spacings (2^12: 10 nm)
ROLLON_NODES = 4
CLASSES = {
    "cohesive": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.0},
    "coupled": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.5,
                "interface.length_tangential": 1e-9},
    "normal": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.0,
               "interface.length_tangential": 1e-9},
}
#: --compare: per class, the other solver run on the same task (label, Settings fields); the default runs as "default"
OTHER = {"coupled": ("fire (before issue 24)", {"coupled": "fire"})}


def task_of(n, cls, realization=1, scene_keys=None):
    """(task scene, profile heights) of class `cls` at N = n: the seed base scene with the class's keys, λs,H raised to
    ROLLON_NODES node spacings where needed, surface seed `realization` (seed_base.toml's seed 1 is realization 1)."""
    base = load_scene(SEED / "seed_base.toml")
    rollon = max(base.surface.rollon_wavelength, ROLLON_NODES * base.surface.length / n)
    keys = {"surface.nodes": n, "surface.rollon_wavelength": rollon, **CLASSES[cls], **(scene_keys or {})}
    scene = task_scene(base.replace(**keys), realization - base.surface.seed)
    return scene, surfaces.profile(scene.surface, 0)


def ramp(n, cls, options=None, max_steps=None, realization=1, scene_keys=None, a_rel_stop=A_REL_STOP, states=None,
         keep_u_hat=False):
    """One task's ramp at N = n: list of per-step dicts (it, pairs, cpu, a_rel, method, converged).

    realization: the surface seed (seed_base.toml's seed 1 is realization 1); scene_keys: more scene
    overrides (e.g. {"interface.length_normal": 0.25e-9}); states: a list that receives each step's
    (p̄, gap) when given; keep_u_hat: each row also holds the accepted spectra u_hat.
    """
    scene, h = task_of(n, cls, realization, scene_keys)
    cell = prepare(scene, h)
    settings = replace(cell.settings, **(options or {}))
    steps, _ = realization_steps(scene, h, 0)
    d0 = scene.loading.initial_separation
    wall_tolerance = wall_tolerance_of(scene, h)  # the study's (`gfmd.loading`)
    current = previous = cell.initial_state()
    rows = []
    for k, displacement in enumerate(steps):
        z_ind = indenter_surface(h, d0, displacement)
        extrapolate = extrapolation_allowed(scene.loading, k)
        guess = 2 * current - previous if extrapolate else current
        t0 = time.process_time()
        r = relax(cell.physics, cell.law, z_ind, guess, settings, wall_tolerance,
                  previous=current if extrapolate else None)  # as the study's ramp (gfmd.loading.GfmdCell.solve)
        it, pairs = r.iterations, r.fft_pairs
        if not r.converged and extrapolate:
            r = relax(cell.physics, cell.law, z_ind, current, settings, wall_tolerance)
            it, pairs = it + r.iterations, pairs + r.fft_pairs
        cpu = time.process_time() - t0
        obs = step_observables(scene, h, r.gap, r.t_z)
        rows.append({"k": k, "delta": displacement - d0, "it": it, "pairs": pairs, "cpu": cpu,
                     "a_rel": float(obs["a_rel"]), "method": r.method, "converged": bool(r.converged),
                     "residual": r.residual, "p": float(obs["p"]), **({"u_hat": r.u_hat} if keep_u_hat else {})})
        if states is not None:
            states.append(np.array(r.gap, copy=True))
        if r.converged:
            previous, current = current, r.u_hat
        if obs["a_rel"] >= a_rel_stop or (max_steps and k + 1 >= max_steps):
            break
    return rows


def summary(rows):
    """Per-task numbers: steps, mean / max pairs and iterations per step, CPU s per step, converged."""
    pairs = np.array([r["pairs"] for r in rows])
    its = np.array([r["it"] for r in rows])
    cpu = np.array([r["cpu"] for r in rows])
    methods = sorted({r["method"] for r in rows})
    return {"steps": len(rows), "pairs_mean": pairs.mean(), "pairs_max": pairs.max(), "it_mean": its.mean(),
            "it_max": its.max(), "cpu_step": cpu.mean(), "a_rel": rows[-1]["a_rel"],
            "converged": sum(r["converged"] for r in rows), "methods": "/".join(methods)}


def profile_lines(rows, every):
    """Pairs per step along the ramp, one line per `every` steps (a_rel, it, pairs)."""
    out = ["| step | δ (nm) | a_rel | it | FFT pairs | algorithm | CPU s (under load) |", "|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["k"] % every == 0 or r is rows[-1] or r["pairs"] == max(x["pairs"] for x in rows):
            out.append(f"| {r['k']} | {r['delta'] * 1e9:.2f} | {r['a_rel']:.3f} | {r['it']} | {r['pairs']:.0f} | "
                       f"{r['method']} | {r['cpu']:.3g} |")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="N = 2^12 and 2^14 only")
    ap.add_argument("--sizes", type=int, nargs="+", help="exponents e of N = 2^e")
    ap.add_argument("--classes", nargs="+", default=list(CLASSES), choices=list(CLASSES))
    ap.add_argument("--compare", action="store_true", help="also run the solver before issue 24 per class")
    ap.add_argument("--max-steps", type=int, default=None)
    ap.add_argument("--realization", type=int, default=1, help="surface seed (seed_base.toml's is 1)")
    ap.add_argument("--length-normal", type=float, default=None, help="interface.length_normal δn (m)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    args = ap.parse_args(argv)
    sizes = args.sizes or ([12, 14] if args.quick else [12, 14, 17])
    tag = "quick" if args.quick and not args.sizes else "full" if not args.sizes else "e" + "_".join(map(str, sizes))
    load0 = os.getloadavg()
    head = ["# Strong adhesion and the coupled law along the ramp (issue 24)", "",
            f"`python benchmarks/bench_adhesion_scaling.py {' '.join(argv or sys.argv[1:])}`; git "
            f"{os.popen(f'git -C {ROOT} rev-parse --short HEAD').read().strip()}; ramp: the seed base scene, "
            f"realization seed {args.realization}"
            f"{f', δn = {args.length_normal:g} m' if args.length_normal else ''}, from δ0 = 12 nm out of contact until a_rel ≥ {A_REL_STOP} (or δ = 20 nm). "
            "FFT pairs and iterations are deterministic counts; CPU s/step are MEASURED UNDER LOAD on a shared "
            f"2-core machine (load average at start {load0[0]:.2f}).", ""]
    table = ["| N | class | solver | steps | it/step mean | it/step max | FFT pairs/step mean | max | "
             "CPU s/step (under load) | converged | final a_rel | algorithms |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    profiles, sums = [], {}
    for e in sizes:
        n = 2**e
        for cls in args.classes:
            variants = [("default", None)]
            if args.compare and cls in OTHER:
                variants.append(OTHER[cls])
            for name, options in variants:
                if cls == "normal" and (e, "cohesive", "default") in sums and name == "default":
                    rows = cohesive_rows  # the same task (c = 0): not run twice
                else:
                    ramp(n, cls, options, max_steps=3)  # warm-up: numba's compilation and FFT plans untimed
                    keys = {"interface.length_normal": args.length_normal} if args.length_normal else None
                    rows = ramp(n, cls, options, args.max_steps, args.realization, keys)
                if cls == "cohesive" and name == "default":
                    cohesive_rows = rows
                s = summary(rows)
                sums[(e, cls, name)] = s
                line = (f"| 2^{e} | {cls} | {name} | {s['steps']} | {s['it_mean']:.1f} | {s['it_max']} | "
                        f"{s['pairs_mean']:.1f} | {s['pairs_max']:.0f} | {s['cpu_step']:.3g} | "
                        f"{s['converged']}/{s['steps']} | {s['a_rel']:.3f} | {s['methods']} |")
                table.append(line)
                print(line, flush=True)
                profiles += [f"### 2^{e} {cls} ({name})", ""] + profile_lines(rows, max(1, len(rows) // 12)) + [""]
    ratios = ["", "## Coupled / normal per step (same profile and ramp)", "",
              "| N | solver | pairs ratio (mean) | CPU ratio (under load) |", "|---|---|---|---|"]
    for (e, cls, name), s in sums.items():
        if cls == "coupled" and (e, "normal", "default") in sums:
            nrm = sums[(e, "normal", "default")]
            ratios.append(f"| 2^{e} | {name} | {s['pairs_mean'] / nrm['pairs_mean']:.2f} | "
                          f"{s['cpu_step'] / nrm['cpu_step']:.2f} |")
    load1 = os.getloadavg()
    text = "\n".join(head + table + ratios + ["", f"Load average at end: {load1[0]:.2f}.", "",
                                              "## Pairs per step along the ramp", ""] + profiles)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out / f"bench_adhesion_scaling_{tag}.md"
    path.write_text(text + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
