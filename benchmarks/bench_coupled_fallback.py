"""The coupled law's fallback steps before / after the GMRES fail-fast of the Newton continuation (issue 24).

Usage: python benchmarks/bench_coupled_fallback.py [--small] [--replay RUN_DIR FIRST LAST ...] [--out FILE]

Two chains relax the same steps from the same warm starts, one after the other in one run:
  before  the Newton-first chain as it was: the continuation Newton goes on with inexact GMRES directions
          (up to COUPLED_NEWTON_ITERATIONS = 60) before FIRE;
  after   the "newton" chain (`gfmd.chains.CHAINS[("coupled", "newton")]`): its continuation Newton
          (Settings.coupled_gmres_give_up) gives the step up at the first GMRES solve that misses its tolerance.
--small: the coupled tasks of studies/seed/fig8_small.toml (N = 4096, 100 steps, ν = 0.1 and 0.45, c = 0.5,
realizations 0 and 1), whole ramps; each chain runs its own ramp (warm starts from its own states).
--replay RUN_DIR FIRST LAST: a saved full-scale task (a `gfmd run` / study task directory whose partial/ holds
realization0_stepK.npz with the ramp's warm start, K = FIRST − 1): steps FIRST..LAST replayed from the saved warm
start; the recorded curve (partial/realization0.csv) gives the run's own p per step for comparison.
Per step: the chain's label, iterations, FFT pairs (deterministic, meaningful under load), CPU s (time.process_time;
the machine is shared, MEASURED UNDER LOAD), p; per chain the totals; per step the largest nodal difference between
the two chains' states in units of δn (the same equilibrium to the solver tolerance, or not).
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from dataclasses import replace
from pathlib import Path

# before numpy loads BLAS: one thread (the timings are single-threaded); hence the E402 imports below
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

# the script runs from anywhere: the repository goes on sys.path before the project imports (E402)
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gfmd_contact.core import surfaces  # noqa: E402
from gfmd_contact.core.loading import extrapolation_allowed, indenter_surface, realization_steps  # noqa: E402
from gfmd_contact.core.observables import step_observables  # noqa: E402
from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd import chains  # noqa: E402
from gfmd.loading import prepare  # noqa: E402
from gfmd_contact.app.study import task_scene  # noqa: E402

SMALL = ROOT / "studies" / "seed" / "fig3_small_base.toml"
FIG8 = {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.5,
        "interface.length_tangential": 1e-9}
KEY = ("coupled", "newton")
#: the chain before the fail-fast: its first link the plain Newton (same acceptance test)
BEFORE = (replace(chains.CHAINS[KEY][0], options=()),) + chains.CHAINS[KEY][1:]
CHAIN = {"before": BEFORE, "after": chains.CHAINS[KEY]}


def relax_with(which, cell, z_ind, guess, wall_tolerance):
    """`chains.relax` with the chain `which` ("before" / "after"); (Relaxed, CPU s)."""
    saved = chains.CHAINS[KEY]
    chains.CHAINS[KEY] = CHAIN[which]
    try:
        t0 = time.process_time()
        r = chains.relax(cell.physics, cell.law, z_ind, guess, cell.settings, wall_tolerance)
        return r, time.process_time() - t0
    finally:
        chains.CHAINS[KEY] = saved


def step(which, cell, scene, h, k, steps, current, previous, wall_tolerance):
    """One ramp step as `gfmd_contact.core.ramp.run_ramp` takes it: extrapolated warm start, retried from the last state."""
    z_ind = indenter_surface(h, scene.loading.initial_separation, steps[k])
    extrapolate = extrapolation_allowed(scene.loading, k)
    r, cpu = relax_with(which, cell, z_ind, 2 * current - previous if extrapolate else current, wall_tolerance)
    it, pairs, method = r.iterations, r.fft_pairs, r.method
    if not r.converged and extrapolate:
        r, more = relax_with(which, cell, z_ind, current, wall_tolerance)
        it, pairs, cpu, method = it + r.iterations, pairs + r.fft_pairs, cpu + more, f"{method}; {r.method}"
    obs = step_observables(scene, h, r.gap, r.t_z)
    return r, {"k": k, "method": method, "it": it, "pairs": pairs, "cpu": cpu, "p": float(obs["p"]),
               "a_rel": float(obs["a_rel"]), "converged": bool(r.converged)}


def nodal(r):
    return np.stack([r.u_x, r.u_z])


def run_steps(scene, h, first, last, current, previous, which_chains=tuple(CHAIN)):
    """The chains over steps first..last; {which: rows}, per-step state difference (δn; NaN unless both ran)."""
    cell = prepare(scene, h)
    steps, _ = realization_steps(scene, h, 0)
    wall_tolerance = 1e-12 * max(float(np.ptp(h)), scene.interface.length_normal)
    rows, states = {}, {}
    for which in which_chains:
        cur, prev, rows[which], states[which] = current, previous, [], []
        for k in range(first, min(last, len(steps) - 1) + 1):
            r, row = step(which, cell, scene, h, k, steps, cur, prev, wall_tolerance)
            rows[which].append(row)
            states[which].append(nodal(r))
            if r.converged:
                prev, cur = cur, r.u_hat
            print(which, row, flush=True)
    if len(rows) < 2:  # one chain: the other's columns empty
        other = "after" if "before" in rows else "before"
        rows[other] = [dict(r, method="—", it=0, pairs=0.0, cpu=0.0) for r in rows[which_chains[0]]]
        return rows, [float("nan")] * len(rows[other])
    diff = [float(np.max(np.abs(a - b))) / scene.interface.length_normal
            for a, b in zip(states["before"], states["after"])]
    return rows, diff


def table(rows, diff, recorded=None, only_fallback=True):
    head = ("| step | before: algorithm | it | FFT pairs | CPU s | after: algorithm | it | FFT pairs | CPU s | "
            "max |Δu| / δn | p after (MPa) |" + (" p recorded (MPa) |" if recorded else ""))
    out = [head, "|" + "---|" * (11 + bool(recorded))]
    for b, a, d in zip(rows["before"], rows["after"], diff):
        if only_fallback and b["method"] == a["method"] == "newton" and b["pairs"] == a["pairs"]:
            continue
        line = (f"| {b['k']} | {b['method']} | {b['it']} | {b['pairs']:.0f} | {b['cpu']:.3g} | {a['method']} | "
                f"{a['it']} | {a['pairs']:.0f} | {a['cpu']:.3g} | {d:.2g} | {a['p'] / 1e6:.6g} |")
        if recorded:
            line += f" {recorded.get(b['k'], float('nan')) / 1e6:.6g} |"
        out.append(line)
    return out


def totals(rows, diff, label):
    b, a = rows["before"], rows["after"]
    sb, sa = sum(r["pairs"] for r in b), sum(r["pairs"] for r in a)
    cb, ca = sum(r["cpu"] for r in b), sum(r["cpu"] for r in a)
    same = all(x["method"].split("→")[-1] == y["method"].split("→")[-1] for x, y in zip(b, a))
    return (f"| {label} | {len(b)} | {sb:.0f} | {sa:.0f} | {sb / sa:.2f} | {cb:.1f} | {ca:.1f} | "
            f"{sum(r['converged'] for r in b)}/{sum(r['converged'] for r in a)} | {max(diff):.2g} | "
            f"{'yes' if same else 'no'} |")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--small", action="store_true", help="the fig8_small coupled tasks, whole ramps")
    ap.add_argument("--replay", nargs=3, action="append", default=[], metavar=("RUN_DIR", "FIRST", "LAST"),
                    help="replay steps of a saved task (repeatable)")
    ap.add_argument("--chains", nargs="+", default=list(CHAIN), choices=list(CHAIN),
                    help="which chains --replay runs (a full-scale 'before' step can take minutes)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_coupled_fallback.md"))
    args = ap.parse_args(argv)
    load0 = os.getloadavg()
    lines = ["# The coupled chain's fallback steps: Newton continuation before / after the GMRES fail-fast (issue 24)",
             "", f"`python benchmarks/bench_coupled_fallback.py {' '.join(argv or sys.argv[1:])}`. FFT pairs and "
             "iterations are deterministic; CPU s are MEASURED UNDER LOAD on a shared 2-core machine (load average "
             f"at start {load0[0]:.2f}). Only the steps where the two chains differ (a fallback ran) are listed; "
             "max |Δu| / δn: the largest nodal difference between the two chains' states.", "",
             "| task | steps | FFT pairs before | after | before / after | CPU s before | after | converged before/after "
             "| max |Δu| / δn | same last algorithm |", "|---|---|---|---|---|---|---|---|---|---|"]
    sections = []
    if args.small:
        base = load_scene(SMALL)
        for nu in (0.1, 0.45):
            for realization in (0, 1):
                scene = task_scene(base.replace(**{**FIG8, "material.poisson_ratio": nu}), realization)
                h = surfaces.profile(scene.surface, 0)
                zero = prepare(scene, h).initial_state()
                rows, diff = run_steps(scene, h, 0, scene.loading.steps, zero, zero)
                label = f"fig8_small ν = {nu}, seed {scene.surface.seed} (N = 4096)"
                lines.append(totals(rows, diff, label))
                sections += ["", f"## {label}", ""] + table(rows, diff)
    for replay in args.replay:
        run_dir, first, last = Path(replay[0]), int(replay[1]), int(replay[2])
        scene = load_scene(run_dir / "scene.toml")
        h = surfaces.profile(scene.surface, 0)
        with np.load(run_dir / "partial" / f"realization0_step{first - 1}.npz") as z:
            current, previous = z["ramp_current"], z["ramp_previous"]
        recorded = {}
        csv_path = run_dir / "partial" / "realization0.csv"
        if csv_path.is_file():
            with open(csv_path) as f:
                recorded = {int(r["step"]): float(r["p"]) for r in csv.DictReader(f)}
        rows, diff = run_steps(scene, h, first, last, current, previous, tuple(args.chains))
        label = (f"{run_dir.name}: ν = {scene.material.poisson_ratio}, seed {scene.surface.seed}, "
                 f"N = {scene.surface.nodes}, steps {first}–{last}")
        lines.append(totals(rows, diff, label))
        sections += ["", f"## {label}", "", "p recorded: the study run's curve (the chain before, the same code "
                     "otherwise).", ""] + table(rows, diff, recorded, only_fallback=False)
    lines += sections + ["", f"Load average at end: {os.getloadavg()[0]:.2f}."]
    text = "\n".join(lines) + "\n"
    print(text)
    Path(args.out).write_text(text)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
