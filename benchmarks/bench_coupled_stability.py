"""The coupled chains' stability test (`gfmd.coupled_stability`): the Newton's two-level GMRES against scipy's (issue 24).

Usage: python benchmarks/bench_coupled_stability.py [--nodes N ...] [--saved SCENE STEP_NPZ STATE_NPZ ...] [--out FILE]

The test computes the tangent's eigenvalues nearest 0 by shift-invert Arnoldi; each of its solves J x = b ran
scipy's GMRES (restart 120, its Gram–Schmidt a Python loop over 2N-vectors) preconditioned by the FIRE mass alone
before session 37, and runs the coupled Newton's GMRES (`gfmd.gmres`) right-preconditioned by K⁻¹ and the coarse
space on the stiff nodes now (`coupled_stability.SOLVER`). Both on the same states, in one process, one after the
other, per state: CPU s (time.process_time), FFT pairs, the lowest Re λ in units of φn/δn² and the two values'
relative difference.

States: the fig8_small task's (studies/seed/fig3_small_base.toml with c = 0.5, δt = 1 nm, φn* = 0.15, seed 2) last
step, δ = 20 nm, at N = --nodes (default 4096; ν = 0.1 and 0.45), relaxed by the default chain from the ramp's
state at step 99; and --saved: a full-scale state (a task's scene.toml, an npz with the step's `displacement`, an
npz with the converged `state`: e.g. Fig. 8's seed-7 task at 2^17, ν = 0.1, steps 199 and 200, where the test took
330 and 399 s in the study). Writes benchmarks/results/bench_coupled_stability.md (or --out).
"""

from __future__ import annotations

import argparse
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

from benchmarks.report import header, write  # noqa: E402
from gfmd_contact.core import surfaces  # noqa: E402
from gfmd_contact.core.loading import indenter_surface, realization_steps  # noqa: E402
from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd import chains, coupled_stability  # noqa: E402
from gfmd.loading import prepare, run_realization  # noqa: E402

BASE = ROOT / "studies" / "seed" / "fig3_small_base.toml"
FIG8 = {"interface.tangential_ratio": 0.5, "interface.length_tangential": 1e-9, "interface.phi_n_star": 0.15,
        "surface.seed": 2, "surface.realizations": 1}
SOLVERS = ("scipy", "newton")


class _Stop(Exception):
    pass


def small_state(nodes, nu):
    """(label, cell, z_ind, u_hat): fig8_small's last step at N = nodes, relaxed from the ramp's state at step 99."""
    scene = load_scene(BASE).replace(**FIG8, **{"material.poisson_ratio": nu, "surface.nodes": nodes})
    saved = {}

    def checkpoint(result, state):
        if state.step == 99:
            saved.update(current=state.current.copy(), previous=state.previous.copy())
            raise _Stop

    try:
        run_realization(scene, 0, checkpoint=checkpoint)
    except _Stop:
        pass
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h, 0)
    steps, _ = realization_steps(scene, h, 0)
    z_ind = indenter_surface(h, scene.loading.initial_separation, steps[100])
    r = chains.relax(cell.physics, cell.law, z_ind, 2 * saved["current"] - saved["previous"], cell.settings,
                     previous=saved["current"])
    if not r.converged:
        raise SystemExit(f"fig8_small at N = {nodes}, ν = {nu}: step 100 did not converge ({r.message})")
    return f"fig8_small, N = {nodes}, ν = {nu}, step 100 ({r.method})", cell, z_ind, r.u_hat


def saved_state(scene_path, step_path, state_path):
    """(label, cell, z_ind, u_hat) of a saved state: the task's scene, the step's displacement, the state."""
    scene = load_scene(scene_path)
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h, 0)
    z_ind = indenter_surface(h, scene.loading.initial_separation, float(np.load(step_path)["displacement"]))
    label = f"{Path(scene_path).parent.name}, N = {scene.surface.nodes}, seed {scene.surface.seed}, {Path(step_path).stem}"
    return label, cell, z_ind, np.load(state_path)["state"]


def stability_and_pairs(model, law, z_ind, u_hat):
    """(`coupled_stability`'s lowest Re λ, the FFT pairs it took): its Fft swapped for one that registers itself."""
    made = []

    class Counting(coupled_stability.Fft):
        def __init__(self, *a, **k):
            super().__init__(*a, **k)
            made.append(self)

    with mock.patch.object(coupled_stability, "Fft", Counting):
        lowest = coupled_stability.coupled_stability(model, law, z_ind, u_hat)
    return lowest, sum(f.pairs for f in made)


def measure(cell, z_ind, u_hat, solver):
    """(CPU s, FFT pairs, lowest Re λ / (φn/δn²)) of the stability test with `solver`."""
    with mock.patch.object(coupled_stability, "SOLVER", solver):
        t0 = time.process_time()
        lowest, pairs = stability_and_pairs(cell.physics, cell.law, z_ind, u_hat)
        cpu = time.process_time() - t0
    return cpu, pairs, lowest / cell.law.k_int_z


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=int, nargs="+", default=[4096])
    ap.add_argument("--nu", type=float, nargs="+", default=[0.1, 0.45])
    ap.add_argument("--saved", nargs=3, action="append", default=[], metavar=("SCENE", "STEP_NPZ", "STATE_NPZ"))
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_coupled_stability.md"))
    args = ap.parse_args(argv)
    lines = header("The coupled stability test: the Newton's two-level GMRES against scipy's",
                   "bench_coupled_stability.py", argv)
    lines += ["| state | solver | CPU s | FFT pairs | lowest Re λ / (φn/δn²) | scipy / newton CPU | relative difference |",
              "|---|---|---|---|---|---|---|"]
    states = [(nodes, nu) for nodes in args.nodes for nu in args.nu] + [tuple(s) for s in args.saved]
    for spec in states:
        label, cell, z_ind, u_hat = small_state(*spec) if len(spec) == 2 else saved_state(*spec)
        got = {solver: measure(cell, z_ind, u_hat, solver) for solver in SOLVERS}
        ratio = got["scipy"][0] / got["newton"][0]
        diff = abs(got["newton"][2] - got["scipy"][2]) / abs(got["scipy"][2])
        for solver in SOLVERS:
            cpu, pairs, lowest = got[solver]
            last = f"{ratio:.2f} | {diff:.2g}" if solver == "newton" else "|"
            lines.append(f"| {label} | {solver} | {cpu:.2f} | {pairs:.0f} | {lowest:.6g} | {last} |")
        print(lines[-2], lines[-1], sep="\n", flush=True)
    write(lines, args.out)


if __name__ == "__main__":
    main()
