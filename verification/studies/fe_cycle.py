"""GFMD vs the FE cell through a full load–unload cycle on a cohesive layer: differences vs N.

Scene: `verification.scenes.cohesive_sinusoid` (a = 50 nm, L = D = 1 µm bonded layer, E = 70 GPa, ν = 0.3,
normal CZ law, δn = 1 nm) made stickier, φn* = 0.15 (the seed's), and driven along the closed
`loading.path` = [−10, 30, −10] nm in 40 + 80 steps (Δδ = 1 nm loading, 0.5 nm unloading) under displacement
control, from out of contact (δ0 = 10 nm = 10 δn): the loading branch jumps into contact (one jump-in), the
unloading branch snaps off (one jump-out) before the path's end, so the loop is closed and W = ∮ p̄ dδ. The FE
passes both jumps with its trust-region energy descent (`reference.fem.solver.SurfaceProblem.descend`).

Each method its own law evaluation, solver and observables: GFMD (FIRE, scene tolerance) and `reference.fem`
P2 (Newton), sharing only the scene; each run's cycle observables from its own curve with `gfmd_contact.core.cycle`.
Differences (GFMD the reference):
* "p": max over the cycle's steps |p̄_FE − p̄_GFMD| / E* (E* = E/(1 − ν²));
* "pull-off": |F_FE − F_GFMD| / |F_GFMD| of the most tensile p̄ on unloading;
* "hysteresis": |W_FE − W_GFMD| / W_GFMD, W = ∮ p̄ dδ around the closed path (trapezoid rule);
* "snap-off δ": |δ_FE − δ_GFMD| / Δδ_unloading (in unloading steps; 0 = the same step);
* "jump-in δ": |δ_FE − δ_GFMD| / Δδ_loading of the jump into contact (in loading steps).
Both discretizations converge to the same continuum problem, so the differences fall with N; observed orders
between neighbouring N are stored. At the jump the branch is followed to the step only: the δ of snap-off is
known to one step (0.5 nm) in each method, so a difference of one step near the jump would show as a large p̄
difference at that step; "p" is therefore also reported off the snap-off step ("p attached", the steps where
both are attached or both detached).

    python -m verification.studies.fe_cycle [--write]

N = 64, 128, 256; `--write` stores them in verification/data/fe_cycle.json (entry "ci"), which
verification/test_fe_cycle.py reads (it re-runs N = CI_NODES).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core import cycle as cyc
from gfmd_contact.core.loading import step_branches
from verification import measured
from verification.runs import run_fe_and_gfmd
from verification.scenes import cohesive_sinusoid

NAME = "fe_cycle"
PHI_N_STAR = 0.15
PATH = (-10e-9, 30e-9, -10e-9)
STEPS = (40, 80)
NODES = (64, 128, 256)
CI_NODES = 128
METRICS = ("p", "pull-off", "hysteresis", "snap-off δ", "jump-in δ")


def scene(nodes):
    return cohesive_sinusoid(nodes).replace(**{"interface.phi_n_star": PHI_N_STAR, "loading.path": list(PATH),
                                               "loading.steps": list(STEPS), "output.field_steps": 0})


def observables(result, s):
    d, p, a = (np.asarray(result.curve[c], float) for c in ("delta", "p", "a_rel"))
    branch, cycle = step_branches(s.loading)
    (row,) = cyc.cycle_observables(d, p, a, branch, cycle)
    if row["snap_off_delta"] is None:
        raise AssertionError(f"no snap-off on unloading: {row}")
    ins = [e for e in row["events"] if e["kind"] == "jump-in" and e["branch"] == "loading"]
    if len(ins) != 1:
        raise AssertionError(f"expected one jump-in on loading: {row['events']}")
    return p, row, ins[0]


def measure(nodes):
    """(differences {metric}, numbers {method: observables}, wall s) at N = nodes."""
    s = scene(nodes)
    t0 = time.perf_counter()
    rf, rg, _, _ = run_fe_and_gfmd(s)
    for label, r in (("FE", rf), ("GFMD", rg)):
        if not r.all_converged:
            raise AssertionError(f"{label} N = {nodes}: not converged: {r.messages[:3]}")
    (pf, of, jf), (pg, og, jg) = observables(rf, s), observables(rg, s)
    e_star = s.material.contact_modulus
    du = abs(PATH[2] - PATH[1]) / STEPS[1]
    dl = abs(PATH[1] - PATH[0]) / STEPS[0]
    diffs = {"p": float(np.max(np.abs(pf - pg))) / e_star,
             "pull-off": abs(of["pull_off_pressure"] - og["pull_off_pressure"]) / abs(og["pull_off_pressure"]),
             "hysteresis": abs(of["hysteresis"] - og["hysteresis"]) / og["hysteresis"],
             "snap-off δ": abs(of["snap_off_delta"] - og["snap_off_delta"]) / du,
             "jump-in δ": abs(jf["delta_after"] - jg["delta_after"]) / dl}
    keep = ("pull_off_pressure", "pull_off_delta", "snap_off_delta", "hysteresis")
    numbers = {"fe": {**{k: of[k] for k in keep}, "jump_in_delta": jf["delta_after"]},
               "gfmd": {**{k: og[k] for k in keep}, "jump_in_delta": jg["delta_after"]},
               "jumps": {"fe": [(e["kind"], e["step"]) for e in of["events"]],
                         "gfmd": [(e["kind"], e["step"]) for e in og["events"]]}}
    return diffs, numbers, time.perf_counter() - t0


def order(e_coarse, e_fine, ratio=2.0):
    return float(np.log(e_coarse / e_fine) / np.log(ratio)) if e_coarse > 0 and e_fine > 0 else float("nan")


def study(nodes=NODES):
    t0 = time.perf_counter()
    data = [measure(n) for n in nodes]
    errors = {m: [d[0][m] for d in data] for m in METRICS}
    orders = {m: [order(a, b) for a, b in zip(e, e[1:])] for m, e in errors.items()}
    return {"nodes": list(nodes), "data": data, "errors": errors, "orders": orders, "wall_s": time.perf_counter() - t0}


def entry(st):
    return measured.make_entry({"N": st["nodes"], "ci_nodes": CI_NODES, "errors": st["errors"], "orders": st["orders"],
                                "numbers": [d[1] for d in st["data"]]},
                               scene=(f"verification.studies.fe_cycle.scene(N): cohesive_sinusoid, φn* = {PHI_N_STAR}, "
                                      f"path {list(PATH)} m, steps {list(STEPS)}"), wall_s=st["wall_s"])


def stored():
    return measured.entry(NAME, "ci")["values"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_cycle.json")
    args = ap.parse_args(argv)
    st = study()
    for m in METRICS:
        print(f"{m}: N {st['nodes']} difference {[f'{e:.3e}' for e in st['errors'][m]]} "
              f"orders {[f'{o:.2f}' for o in st['orders'][m]]}")
    for n, d in zip(st["nodes"], st["data"]):
        print(f"N = {n}: {d[1]} ({d[2]:.1f} s)")
    if args.write:
        print(measured.write(NAME, {"ci": entry(st)},
                             description="GFMD vs FE P2 through a closed load–unload cycle on a cohesive layer "
                                         "(φn* = 0.15): max |Δp̄|/E*, pull-off, W and snap-off differences vs N"))


if __name__ == "__main__":
    main()
