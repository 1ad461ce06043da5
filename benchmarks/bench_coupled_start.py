"""The coupled chain's start: the extrapolated guess, or the last state where the guess is far worse (issue 24).

Usage: python benchmarks/bench_coupled_start.py [--sizes 13 14] [--realizations 0 1] [--max-steps K]
                                                [--replay TASK_DIR STEP COUNT] [--margins M ...]

The ramp warm-starts a step from the linear extrapolation of its last two states; through a snap that carries the
snapped nodes on into the indenter, and the continuation Newton, which from there moves a node a law length, hands
the step to FIRE. `gfmd.chains.relax` with `previous` (the last state) starts the coupled chains from it where the
guess's nodal force residual is more than COUPLED_START_MARGIN times its own (`gfmd.chains.COUPLED_BETTER_START`).
Variants, each on its own ramp in one run (bench_coupled_forcing.measure): "guess" (off: the chain before), "better
start" (the default) and, with --margins, "margin M" for each M (1: the smaller residual wins):

* ramps: the coupled ramps of bench_coupled_handover (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, until
  a_rel ≥ 0.5; realization i = profile seed 1 + i); p, a_rel and (N ≤ 2^14) the nodal states compared with "guess"'s;
* --replay: a full-scale study task (`gfmd study run` output, its fields.npz holding the state of STEP), steps
  STEP+1 … STEP+COUNT each relaxed from the same two states by every variant.

--fire-check E R K (after the ramps): at N = 2^E, realization R, step K, the new chain's state (the ramp to K − 1
with the default chain), the chain's before (from the guess) and FIRE alone (`Settings.coupled = "fire"`) from the
last state and from the guess, each pair's largest nodal distance in δn: which start's damped dynamics each chain's
answer is.

Writes benchmarks/results/bench_coupled_start_<tag>.md; the count of steps started from the last state is printed
with the table.
"""

from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

# E402 below on purpose: the sibling benchmarks are importable only once benchmarks/ is on sys.path (above), and
# bench_coupled_handover must load before numpy (it sets one BLAS thread, as every timing here assumes)
import bench_coupled_forcing as bcf  # noqa: E402
import bench_coupled_handover as bch  # noqa: E402

import numpy as np  # noqa: E402

from gfmd_contact.core.loading import indenter_surface, realization_steps  # noqa: E402
from gfmd import chains  # noqa: E402

_from_last = [0, 0]  # coupled steps started from the last state, of all relaxed under "better start"


@contextmanager
def better_start(on, margin=None):
    """The coupled chains with COUPLED_BETTER_START = `on` (and COUPLED_START_MARGIN = `margin` where given); under
    True, counts the steps that started from the last state."""
    saved, inner = (chains.COUPLED_BETTER_START, chains.COUPLED_START_MARGIN), chains.better_start

    def choose(problem, guess, previous, margin):
        start, residuals, pairs, state = inner(problem, guess, previous, margin)
        _from_last[0] += start is previous
        _from_last[1] += 1
        return start, residuals, pairs, state

    chains.COUPLED_BETTER_START, chains.better_start = on, choose
    if margin is not None:
        chains.COUPLED_START_MARGIN = margin
    try:
        yield
    finally:
        (chains.COUPLED_BETTER_START, chains.COUPLED_START_MARGIN), chains.better_start = saved, inner


def fire_check(e, realization, step):
    """Lines: at N = 2^e, realization, `step`, the chains' and FIRE's states from the guess and the last state."""
    bas = bch.bas
    n = 2**e
    rows = bas.ramp(n, "coupled", None, step, 1 + realization, keep_u_hat=True)  # steps 0 … step − 1
    base = bas.load_scene(bas.SEED / "seed_base.toml")
    rollon = max(base.surface.rollon_wavelength, bas.ROLLON_NODES * base.surface.length / n)
    scene = bas.task_scene(base.replace(**{"surface.nodes": n, "surface.rollon_wavelength": rollon,
                                           **bas.CLASSES["coupled"]}), 1 + realization - base.surface.seed)
    h = bas.surfaces.profile(scene.surface, 0)
    cell = bas.prepare(scene, h)
    steps, _ = realization_steps(scene, h, 0)
    z_ind = indenter_surface(h, scene.loading.initial_separation, steps[step])
    last = rows[step - 1]["u_hat"]
    guess = 2 * last - rows[step - 2]["u_hat"]
    fire = replace(cell.settings, coupled="fire")
    runs = {"new chain": (guess, last, cell.settings), "chain from the guess": (guess, None, cell.settings),
            "FIRE from the last state": (last, None, fire), "FIRE from the guess": (guess, None, fire)}
    states = {}
    lines = [f"Step {step} of realization {realization} at 2^{e} (`--fire-check {e} {realization} {step}`):", ""]
    for name, (start, previous, settings) in runs.items():
        r = chains.relax(cell.physics, cell.law, z_ind, start, settings, 0.0, previous=previous)
        states[name] = np.fft.irfft(r.u_hat, n)
        lines.append(f"- {name}: {r.method}, converged {r.converged}, {r.fft_pairs:.0f} FFT pairs")
    names = list(states)
    lines += [f"- {a} vs {b}: {np.max(np.abs(states[a] - states[b])) / scene.interface.length_normal:.3g} δn"
              for i, a in enumerate(names) for b in names[i + 1:]]
    return [""] + lines


def main(argv=None):
    ap = bch.parser(__doc__.splitlines()[0])
    ap.add_argument("--replay", nargs=3, metavar=("TASK_DIR", "STEP", "COUNT"), default=None)
    ap.add_argument("--margins", type=float, nargs="*", default=[])
    ap.add_argument("--fire-check", type=int, nargs=3, metavar=("E", "R", "K"), default=None)
    args = ap.parse_args(argv)
    variants = [("guess", lambda: better_start(False)),
                (f"better start (margin {chains.COUPLED_START_MARGIN:g})", lambda: better_start(True))]
    variants += [(f"margin {m:g}", lambda m=m: better_start(True, m)) for m in args.margins]
    command = f"python benchmarks/bench_coupled_start.py {' '.join(argv or sys.argv[1:])}"
    head = [f"`{command}`; {bch.code_version()}; load average at start {os.getloadavg()[0]:.2f} (2-core machine: "
            "CPU s may be under load; FFT pairs deterministic)", ""]
    _from_last[:] = [0, 0]
    lines = head + bcf.measure(args, variants)
    lines += ["", f"Under the variants but \"guess\": {_from_last[0]} of the {_from_last[1]} extrapolated steps "
                  "started from the last state."]
    if args.fire_check:
        lines += fire_check(*args.fire_check)
    bch.write(args, "bench_coupled_start", lines + ["", f"Load average at end: {os.getloadavg()[0]:.2f}."])


if __name__ == "__main__":
    main()
