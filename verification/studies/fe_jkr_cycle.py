"""The FE cell's load–unload cycle of the adhesive sinusoid vs Johnson's (1995) JKR-wavy solution, errors vs δn.

Scene: that of `verification.studies.jkr_cycle` (h = −h0 cos(2πx/λ), h0 = 10 nm, λ = L = 1 µm, E = 70 GPa,
ν = 0.45, exponential CZ law with φn = w fixed at Johnson's α = 0.3, δn lowered at fixed w: d/λ = D_REL)
on a bonded layer of depth D = 2λ instead of the half-plane (the FE meshes a finite layer; at D = 2λ the
fundamental mode's compliance equals the half-plane's to ~1e-9, the higher modes' closer still), along
`loading.path` = [−0.6 h0, 0.6 h0, −0.6 h0] in STEPS steps (Δδ = 0.02 h0 loading, 0.005 h0 unloading: half
the GFMD study's step counts, so that an FE case fits a 2-core minute), displacement control, from out of
contact: the FE passes the jump-in and the snap-off with its trust-region energy descent
(`reference.fem.solver.SurfaceProblem.descend`).

Analytic cycle and metrics: `verification.studies.jkr_cycle.cycle_errors` (the same code as GFMD's study):
pull-off, snap-off δ, jump-in δ, hysteresis W = ∮ p̄ dδ, and both branches' max |p̄ − p̄_J(δ)|/p*, from the FE
run's own curve (its own law and observables, `reference.fem`). Rate = least-squares slope of log error vs
log δn. The FE node count is fixed per entry (NODES); the process zone d must stay resolved (d/λ = 0.01 is
d = 5 l at N = 512, 10 P2 surface points).

    python -m verification.studies.fe_jkr_cycle [--write] [--subset ci|full]

`--write` stores the errors in verification/data/fe_jkr_cycle.json (entry "ci": N = 256, d/λ = 0.04, 0.02;
"full": N = 512 adding 0.01), read by verification/test_fe_jkr_cycle.py.
"""

from __future__ import annotations

import argparse

import numpy as np

from gfmd_contact.core import cycle as cyc
from gfmd_contact.core.loading import step_branches
from verification import analytic_cases as ac
from verification import measured
from verification.runs import run_fe
from verification.studies import jkr_cycle as jc
from verification.studies import jkr_sinusoid as js

NAME = "fe_jkr_cycle"
STEPS = (60, 240)
DEPTH = 2 * jc.LENGTH
LEVELS = {"ci": (256, (0.04, 0.02)), "full": (512, (0.04, 0.02, 0.01))}
METRICS = ("pull-off", "snap-off δ", "jump-in δ", "hysteresis", "loading branch", "unloading branch")


def scene(nodes, d_rel):
    return jc.scene(nodes, d_rel).replace(**{"material.thickness": DEPTH, "loading.steps": list(STEPS)})


def measure(nodes, d_rel):
    """(errors {metric}, numbers {FE observables}, curve (δ/h0, p̄/p*, branch), δn, wall s)."""
    s = scene(nodes, d_rel)
    result, wall = run_fe(s)
    errors, numbers, curve = jc.cycle_errors(result, s, d_rel, jc.layer_compliance(s.material))
    numbers["fallback_steps"] = [int(k) for k in result.diagnostics.get("fallback_steps", [])]
    numbers["jump_steps"] = jump_steps(result, s)
    return errors, numbers, curve, js.delta_n(d_rel), wall


def jump_steps(result, s):
    """The steps of the run's jump-in and jump-out events (`gfmd_contact.core.cycle`)."""
    d, p, a = (np.asarray(result.curve[c], float) for c in ("delta", "p", "a_rel"))
    (row,) = cyc.cycle_observables(d, p, a, *step_branches(s.loading))
    return [int(e["step"]) for e in row["events"]]


def study(subset):
    nodes, d_rel = LEVELS[subset]
    data, errors, wall = ac.convergence_study(lambda dr: measure(nodes, dr), d_rel, METRICS)
    dns = np.array([x[3] for x in data])
    return {"nodes": nodes, "d_rel": list(d_rel), "delta_n": dns, "data": data, "errors": errors,
            "rates": ac.orders_in(dns, errors), "wall_s": wall}


def entry(st, subset):
    return measured.make_entry({"N": st["nodes"], "d_over_lambda": st["d_rel"], "delta_n_m": list(st["delta_n"]),
                                "errors": {m: list(e) for m, e in st["errors"].items()}, "rates": st["rates"],
                                "fe": [x[1] for x in st["data"]], "johnson": johnson_numbers(),
                                "wall_s_per_case": [x[4] for x in st["data"]]},
                               scene=(f"verification.studies.fe_jkr_cycle.scene({st['nodes']}, d/λ): jkr_cycle's sinusoid "
                                      f"on a layer D = 2λ, steps {list(STEPS)}"), subset=subset, wall_s=st["wall_s"])


def johnson_numbers():
    """Johnson's cycle on the layer (its mean compliance C in series, `jkr_cycle.analytic`), scaled as GFMD's."""
    c = jc.layer_compliance(scene(64, 0.04).material)
    ref = jc.analytic(c)
    return {"compliance_m_per_Pa": c, "pull_off_over_p_star": ref["pull_off"] / ref["p_star"],
            "snap_off_delta_over_h0": ref["delta_off"] / jc.H0, "hysteresis_J_per_m2": ref["hysteresis"],
            "a_off_over_lambda": ref["a_off"] / jc.LENGTH, "a_in_over_lambda": ref["a_in"] / jc.LENGTH}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/fe_jkr_cycle.json")
    ap.add_argument("--subset", choices=sorted(LEVELS), action="append", help="default: all")
    args = ap.parse_args(argv)
    entries = {}
    for subset in args.subset or sorted(LEVELS):
        st = study(subset)
        ac.print_orders(subset, "δn", st["delta_n"], st["errors"], st["rates"])
        for dr, x in zip(st["d_rel"], st["data"]):
            print(f"{subset} d/λ = {dr}: FE {x[1]} ({x[4]:.1f} s)")
        entries[subset] = entry(st, subset)
    print("Johnson on the layer:", johnson_numbers())
    if args.write:
        old = measured.load(NAME)["entries"] if measured.path(NAME).exists() else {}
        print(measured.write(NAME, {**old, **entries},
                             description="FE P2 (layer D = 2λ) cohesive sinusoid load–unload cycle vs Johnson JKR-wavy under "
                                         "displacement control: errors of pull-off, snap-off, jump-in, hysteresis and both "
                                         "branches vs δn at fixed α = 0.3, rates vs δn (least squares)"))


if __name__ == "__main__":
    main()
