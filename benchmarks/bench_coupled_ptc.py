"""The coupled chain's event steps: FIRE (the default chain) vs pseudo-transient continuation (Ψtc) (issue 24).

Usage: python benchmarks/bench_coupled_ptc.py [--tasks nu:seed_index ...] [--nodes N] [--mass modes|nodes] [--out FILE]

Two chains run whole ramps of the fig8_small coupled tasks (studies/seed/fig8_small.toml: N = 4096, c = 0.5,
φn* = 0.15, 100 steps; ν = 0.1 and 0.45, realizations 0 and 1), each its own ramp (warm starts from its own states):
  newton  the default chain (`gfmd.chains.CHAINS[("coupled", "newton")]`): continuation Newton, FIRE, ...
  ptc     Settings.coupled = "ptc": continuation Newton, Ψtc (`gfmd.algorithms.coupled_ptc`, kept where locally
          stable), then the default chain's FIRE, ...
--nodes N: the same scene at N nodes (surface.nodes only; rollon resolution and the rest unchanged).
Per step: the label, iterations, FFT pairs (deterministic, meaningful under load) and those of the stability test
(`gfmd.coupled_stability`, not in `Relaxed.fft_pairs`: counted here), p; per step the largest nodal difference
between the two chains' states in units of δn. No wall times: the machine is shared.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import replace
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from benchmarks.bench_coupled_stability import stability_and_pairs  # noqa: E402
from gfmd_contact.core import surfaces  # noqa: E402
from gfmd_contact.core.loading import extrapolation_allowed, indenter_surface, realization_steps  # noqa: E402
from gfmd_contact.core.observables import step_observables  # noqa: E402
from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd import chains  # noqa: E402
from gfmd.algorithms import coupled_ptc  # noqa: E402
from gfmd.loading import prepare  # noqa: E402
from gfmd_contact.app.study import task_scene  # noqa: E402

SMALL = ROOT / "studies" / "seed" / "fig3_small_base.toml"
FIG8 = {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.5,
        "interface.length_tangential": 1e-9}
CHAINS = ("newton", "ptc")
_stability_pairs = [0.0]


def _counted_stability(model, law, z_ind, u_hat):
    """`coupled_stability`, its FFT pairs added to _stability_pairs."""
    lowest, pairs = stability_and_pairs(model, law, z_ind, u_hat)
    _stability_pairs[0] += pairs
    return lowest


def relax(which, cell, z_ind, guess, wall_tolerance):
    """`chains.relax` with Settings.coupled = which; (Relaxed, stability-test FFT pairs)."""
    before = _stability_pairs[0]
    r = chains.relax(cell.physics, cell.law, z_ind, guess, replace(cell.settings, coupled=which), wall_tolerance)
    return r, _stability_pairs[0] - before


def ramp(which, scene, h):
    """The whole ramp with chain `which`: rows and nodal states per step (as `gfmd_contact.core.ramp.run_ramp` steps)."""
    cell = prepare(scene, h)
    steps, _ = realization_steps(scene, h, 0)
    wall_tolerance = 1e-12 * max(float(np.ptp(h)), scene.interface.length_normal)
    current = previous = cell.initial_state()
    rows, states = [], []
    for k in range(len(steps)):
        z_ind = indenter_surface(h, scene.loading.initial_separation, steps[k])
        extrapolate = extrapolation_allowed(scene.loading, k)
        r, stab = relax(which, cell, z_ind, 2 * current - previous if extrapolate else current, wall_tolerance)
        it, pairs, method = r.iterations, r.fft_pairs, r.method
        if not r.converged and extrapolate:
            r, more = relax(which, cell, z_ind, current, wall_tolerance)
            it, pairs, stab, method = it + r.iterations, pairs + r.fft_pairs, stab + more, f"{method}; {r.method}"
        obs = step_observables(scene, h, r.gap, r.t_z)
        rows.append({"k": k, "method": method, "it": it, "pairs": pairs, "stab": stab, "p": float(obs["p"]),
                     "converged": bool(r.converged)})
        states.append(np.stack([r.u_x, r.u_z]))
        if r.converged:
            previous, current = current, r.u_hat
        print(which, rows[-1], flush=True)
    return rows, states


def is_event(row):
    return row["method"] != "newton"


def summary(label, rows, diff):
    a, b = rows["newton"], rows["ptc"]
    ev_a, ev_b = [r for r in a if is_event(r)], [r for r in b if is_event(r)]
    cont = [r for r in a if not is_event(r)]

    def tot(rs, stab=True):
        return sum(r["pairs"] + stab * r["stab"] for r in rs)

    return (f"| {label} | {len(a)} | {tot(a):.0f} | {tot(b):.0f} | {len(ev_a)} / {len(ev_b)} | {tot(ev_a):.0f} | "
            f"{tot(ev_b):.0f} | {tot(ev_a, False):.0f} | {tot(ev_b, False):.0f} | {tot(cont) / max(len(cont), 1):.0f} | "
            f"{sum(r['converged'] for r in a)}/{sum(r['converged'] for r in b)} | {max(diff):.2g} |")


def table(rows, diff):
    out = ["| step | newton chain | it | FFT pairs | + stability | ptc chain | it | FFT pairs | + stability | "
           "max |Δu| / δn | p newton (MPa) | p ptc (MPa) |", "|" + "---|" * 12]
    for a, b, d in zip(rows["newton"], rows["ptc"], diff):
        if not (is_event(a) or is_event(b)):
            continue
        out.append(f"| {a['k']} | {a['method']} | {a['it']} | {a['pairs']:.0f} | {a['stab']:.0f} | {b['method']} | "
                   f"{b['it']} | {b['pairs']:.0f} | {b['stab']:.0f} | {d:.2g} | {a['p'] / 1e6:.6g} | "
                   f"{b['p'] / 1e6:.6g} |")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tasks", nargs="+", default=["0.1:0", "0.1:1", "0.45:0", "0.45:1"],
                    help="ν:realization pairs (default: the four fig8_small coupled tasks)")
    ap.add_argument("--nodes", type=int, default=0, help="surface.nodes (0: the scene's 4096)")
    ap.add_argument("--mass", default=coupled_ptc.PTC_MASS, choices=("modes", "nodes"), help="coupled_ptc.PTC_MASS")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_coupled_ptc.md"))
    args = ap.parse_args(argv)
    coupled_ptc.PTC_MASS = args.mass
    chains.coupled_stability = _counted_stability
    base = load_scene(SMALL)
    if args.nodes:
        base = base.replace(**{"surface.nodes": args.nodes})
    lines = [f"`python benchmarks/bench_coupled_ptc.py {' '.join(argv if argv is not None else sys.argv[1:])}` "
             f"(PTC_MASS = {args.mass!r}, PTC_DT_START = {coupled_ptc.PTC_DT_START:g}). FFT pairs include the stability "
             "test's unless said otherwise; event steps: those that left the continuation Newton.", "",
             "| task | steps | FFT pairs newton chain | ptc chain | event steps newton / ptc | event-step pairs newton "
             "| ptc | the same without the stability test: newton | ptc | pairs per continuation step | converged | "
             "max |Δu| / δn |", "|" + "---|" * 12]
    sections = []
    for task in args.tasks:
        nu, realization = float(task.split(":")[0]), int(task.split(":")[1])
        scene = task_scene(base.replace(**{**FIG8, "material.poisson_ratio": nu}), realization)
        h = surfaces.profile(scene.surface, 0)
        rows, states = {}, {}
        for which in CHAINS:
            rows[which], states[which] = ramp(which, scene, h)
        diff = [float(np.max(np.abs(a - b))) / scene.interface.length_normal
                for a, b in zip(states["newton"], states["ptc"])]
        label = f"ν = {nu}, seed {scene.surface.seed} (N = {scene.surface.nodes})"
        lines.append(summary(label, rows, diff))
        sections += ["", f"### {label}: the steps where either chain left the continuation Newton", ""] + table(rows, diff)
    text = "\n".join(lines + sections) + "\n"
    print(text)
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(text)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
