"""The coupled Newton's GMRES forcing rule: FFT pairs and CPU per rule (issue 24).

Usage: python benchmarks/bench_coupled_forcing.py [--sizes 13 14] [--realizations 0 1] [--max-steps K]
                                                  [--rules 1e-3 ew 3e-2]
                                                  [--replay TASK_DIR STEP COUNT]

Each Newton iteration of the coupled law solves its linearised balance by GMRES to the relative tolerance
min(FORCING, max(η, floor, 0.3 tolerance / residual)) (`gfmd.coupled_krylov.forcing`). A rule: "ew", η by
Eisenstat–Walker (`gfmd.coupled_krylov.eisenstat_walker`) over the floor FORCING_MIN (the default since session
28); a number, that floor alone (η = 0; 1e-3 is the rule before). Two measurements, every rule in the same run:

* ramps: the coupled ramps of bench_coupled_handover (seed base scene, φn* = 0.15, c = 0.5, δt = 1 nm, until
  a_rel ≥ 0.5; realization i = profile seed 1 + i) along the default chain, one ramp per rule; p, a_rel and
  (N ≤ 2^14) the nodal states compared with the first rule's;
* --replay: a full-scale study task (`gfmd study run` output, e.g. results/fig8/tasks/<id>, its fields.npz holding
  the state of STEP): steps STEP+1 … STEP+COUNT each relaxed from the same start by every rule in turn (the
  first rule's state carried on), FFT pairs, CPU s and max nodal |Δu| per step.

Writes benchmarks/results/bench_coupled_forcing_<tag>.md.
"""

from __future__ import annotations

import os
import sys
import time
from contextlib import contextmanager
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

# E402 below on purpose: the sibling benchmark is importable only once benchmarks/ is on sys.path (above), and it must
# load before numpy (it sets one BLAS thread, as every timing here assumes, and counts the stability test's pairs)
import bench_coupled_handover as bch  # noqa: E402
import numpy as np  # noqa: E402

from gfmd import chains, coupled_krylov  # noqa: E402
from gfmd.algorithms import coupled_newton  # noqa: E402


@contextmanager
def forcing_rule(rule):
    """The coupled Newton's GMRES solves under `rule`: "ew" (Eisenstat–Walker over FORCING_MIN) or a floor alone."""
    saved = coupled_krylov.FORCING_MIN, coupled_newton.COUPLED_NEWTON_EISENSTAT_WALKER
    coupled_newton.COUPLED_NEWTON_EISENSTAT_WALKER = rule == "ew"
    if rule != "ew":
        coupled_krylov.FORCING_MIN = float(rule)
    try:
        yield
    finally:
        coupled_krylov.FORCING_MIN, coupled_newton.COUPLED_NEWTON_EISENSTAT_WALKER = saved


def label(rule):
    return "Eisenstat–Walker" if rule == "ew" else f"floor {float(rule):g}"


def replay_variants(task, step, count, variants):
    """Table lines: the study task's steps step+1 … step+count, each relaxed from the same start (the first
    variant's state carried on) under every variant, a (label, context manager factory) pair."""
    from gfmd_contact.core import surfaces
    from gfmd_contact.core.loading import indenter_surface, realization_steps
    from gfmd_contact.core.scene import load_scene
    from gfmd.fft import rfft_nodes
    from gfmd.loading import prepare

    task = Path(task)
    scene = load_scene(task / "scene.toml")
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h)
    fields = np.load(task / "fields.npz")
    u = np.stack([fields[f"r0_s{step}_u_x"], fields[f"r0_s{step}_u_z"]])
    current = previous = rfft_nodes(u, (u.shape[1],))
    steps, _ = realization_steps(scene, h, 0)
    lines = [f"Replay of `{task}` (N = {u.shape[1]}) from its step-{step} state; per step and variant: chain label, "
             "FFT pairs, CPU s; max |Δu|/δn against the first variant's state.", "",
             "| step | " + " | ".join(name for name, _ in variants) + " | max |Δu|/δn |",
             "|---|" + "---|" * (len(variants) + 1)]
    rules = [name for name, _ in variants]
    totals = {f: [0.0, 0.0] for f in rules}
    for k in range(step + 1, step + 1 + count):
        z_ind = indenter_surface(h, scene.loading.initial_separation, steps[k])
        out = {}
        for rule, context in variants:
            with context():
                t0 = time.process_time()
                r = chains.relax(cell.physics, cell.law, z_ind, 2 * current - previous, cell.settings, 0.0,
                                 previous=current)
                cpu = time.process_time() - t0
            out[rule] = r
            totals[rule][0] += r.fft_pairs
            totals[rule][1] += cpu
            out[rule, "cpu"] = cpu
        first = out[rules[0]]
        du = max(float(np.max(np.abs(np.stack([first.u_x, first.u_z]) - np.stack([r.u_x, r.u_z]))))
                 for r in (out[f] for f in rules[1:])) if len(rules) > 1 else 0.0
        line = (f"| {k} | " + " | ".join(f"{out[f].method} {out[f].fft_pairs:.0f} {out[f, 'cpu']:.1f}" for f in rules)
                + f" | {du / scene.interface.length_normal:.2g} |")
        lines.append(line)
        print(line, flush=True)
        previous, current = current, first.u_hat
    lines.append("| total | " + " | ".join(f"{totals[f][0]:.0f} pairs, {totals[f][1]:.1f} s" for f in rules) + " | |")
    return lines


def measure(args, variants):
    """The report's table lines, every variant (label, context manager factory) in turn: --replay's steps
    (`replay_variants`), or the ramps of bench_coupled_handover per size and realization (bch.TABLE's rows, the
    first variant the reference)."""
    if args.replay:
        task, step, count = args.replay
        args.sizes, args.realizations = ["replay"], [Path(task).name]
        return replay_variants(task, int(step), int(count), variants)
    lines = list(bch.TABLE)
    for e in args.sizes:
        for real in args.realizations:
            results, bound = {}, bch.tolerance_bound(2**e, real)
            for name, context in variants:
                with context():
                    rows, cpu = bch.run(2**e, real, {}, args.max_steps)
                results[name] = rows
                line = bch.table_row(e, real, name, rows, cpu, results[variants[0][0]], bound)
                lines.append(line)
                print(line, flush=True)
    return lines


def main(argv=None):
    ap = bch.parser(__doc__.splitlines()[0])
    ap.add_argument("--rules", nargs="+", default=["1e-3", "ew", "3e-2"])
    ap.add_argument("--replay", nargs=3, metavar=("TASK_DIR", "STEP", "COUNT"), default=None)
    args = ap.parse_args(argv)
    head = [f"`python benchmarks/bench_coupled_forcing.py {' '.join(argv or sys.argv[1:])}`; {bch.code_version()}; "
            f"FORCING_MIN {coupled_krylov.FORCING_MIN:g}, FORCING {coupled_krylov.FORCING:g}, default rule "
            f"{'Eisenstat–Walker' if coupled_newton.COUPLED_NEWTON_EISENSTAT_WALKER else 'floor'}; load average at "
            f"start {os.getloadavg()[0]:.2f} (2-core machine: CPU s may be under load; FFT pairs deterministic up to "
            "ARPACK's random start in the stability test)", ""]
    variants = [(label(rule), lambda rule=rule: forcing_rule(rule)) for rule in args.rules]
    lines = head + measure(args, variants)
    bch.write(args, "bench_coupled_forcing", lines + ["", f"Load average at end: {os.getloadavg()[0]:.2f}."])


if __name__ == "__main__":
    main()
