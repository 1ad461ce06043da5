"""GFMD vs the FE cell through a force-controlled load–unload cycle on a cohesive layer: differences vs N.

Scene: `verification.studies.fe_cycle.scene` (cohesive_sinusoid, φn* = 0.15, δn = 1 nm, layer D = L = 1 µm)
under `loading.control = "force"` (`gfmd_contact.core.force`): from p̄ = 0 with the indenter out of contact
(δ0 = 10 nm = 10 δn) along the mean pressure path `PATH` = [0, 400, −320] MPa in 5 + 18 steps (ΔP = 80 MPa
loading, 40 MPa unloading). Under force control the approach branch (p̄ growing more tensile as the indenter
nears, dp̄/dU < 0) carries no compressive load: the first step jumps into contact (an instability event,
"jump-in"). The attached branch then carries every load down to the pull-off (≈ −266 MPa, the most tensile
p̄ of the displacement-controlled cycle, verification/data/fe_cycle.json); the first load beyond it (−280 MPa)
finds no equilibrium: the body detaches ("jump-out", detached, δ back to −δ0), and stays detached at −320 MPa.
The loads −240 and −280 MPa bracket the pull-off ≥ 13 MPa from it at every N measured (FE and GFMD pull-offs
differ by < 1 MPa), so the event lies in the same step in both methods by construction of the path, not by luck.

Each method its own law, solver and observables (GFMD FIRE, `reference.fem` P2 with its trust-region descent),
both through the one ramp and the generic outer search on U (`gfmd_contact.core.force.solve_load`); they share the scene.
Differences (GFMD the reference):
* "δ": max |δ_FE − δ_GFMD| over the steps where both are attached (the stable branches: loading after the
  jump-in, unloading down to the last load carried), / the path's δ extent (max δ − min δ of GFMD);
* "pull-off load": |P_FE − P_GFMD| / ΔP_unloading of the load at which contact is lost (the detached
  event's load; 0 = the same step);
* "a_rel at events": max over the events of |Δa_rel| before and after, in nodes (`measured.node_count`);
* "event steps": max |step_FE − step_GFMD| over the events (the kinds and detached flags must agree).
Each method must reach every carried load: |p̄ − P| ≤ `gfmd_contact.core.force.tolerance` (otherwise AssertionError).
How much of "δ" that tolerance can make: "δ from the load tolerance" = max |p̄_FE − p̄_GFMD| · |dδ/dP| / extent
over the same steps (dδ/dP from GFMD's neighbouring steps on the branch), stored next to it.
The pull-off itself (`pull_off`, entry "pull-off"): each method's detach load under force control in 0.5 MPa steps
against its own displacement-controlled extremum of p̄ (sampled in 0.05 nm steps, parabola vertex): the loads
carried reach it, the first one not carried lies beyond it (within the search tolerance and the sampling), so
no method leaves the attached branch before its end (or holds a load beyond it).
Both discretizations converge to the same continuum problem, so "δ" falls with N; its observed orders between
neighbouring N are stored. The others are 0 when both methods jump in the same step onto the same state.

    python -m verification.studies.fe_force_cycle [--write]

N = 64, 128, 256 (the pull-off at 64, 128); `--write` stores them in verification/data/fe_force_cycle.json (entries
"ci" and "pull-off"), which verification/test_fe_force_cycle.py reads (it re-runs N = CI_NODES, PULL_OFF_NODES).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core import cycle as cyc
from gfmd_contact.core import force
from gfmd_contact.core.loading import path_values, step_branches
from verification import measured
from verification.runs import run_fe_and_gfmd
from verification.studies import fe_cycle

NAME = "fe_force_cycle"
#: corners of p̄ (Pa): unloaded, compressive, tensile beyond the pull-off (≈ −266 MPa)
PATH = (0.0, 400e6, -320e6)
STEPS = (5, 18)
#: start out of contact: δ = −δ0 (p̄ ≈ −0.3 MPa from the law's tail, a_rel = 0)
INITIAL_SEPARATION = 10e-9
NODES = (64, 128, 256)
CI_NODES = 128
METRICS = ("δ", "pull-off load", "a_rel at events", "event steps")
#: the pull-off itself (`pull_off`), at N = PULL_OFF_NODES: displacement control sampled in 0.05 nm steps across
#: the most tensile p̄ (loaded to δ = 0, past the jump-in at −5 nm, then unloaded), force control in 0.5 MPa
#: steps across it (loaded to 100 MPa, unloaded to −262 MPa, then the fine steps to −270 MPa)
PULL_OFF_NODES = 64
PULL_OFF_DELTA_PATH = (-10e-9, 0.0, -7.0e-9, -8.4e-9)
PULL_OFF_DELTA_STEPS = (10, 7, 28)
PULL_OFF_LOAD_PATH = (0.0, 100e6, -262e6, -270e6)
PULL_OFF_LOAD_STEPS = (1, 4, 16)


def scene(nodes):
    return fe_cycle.scene(nodes).replace(**{"loading.control": "force", "loading.path": list(PATH),
                                            "loading.steps": list(STEPS),
                                            "loading.initial_separation": INITIAL_SEPARATION})


def observables(result, s):
    """(δ per step, attached mask, cycle row with its events, loads) of one force-controlled run; raises
    AssertionError where a carried load is missed or the cycle lacks its jump-in or its detachment."""
    d, p, a, U = (np.asarray(result.curve[c], float) for c in ("delta", "p", "a_rel", "U"))
    branch, cycle = step_branches(s.loading)
    events = [{**e, "branch": str(branch[e["step"]]), "cycle": int(cycle[e["step"]])}
              for e in result.diagnostics.get("instabilities", [])]
    (row,) = cyc.cycle_observables(d, p, a, branch, cycle, events=events)
    loads = path_values(s.loading)
    attached = U > 0.0  # step 0 and the detached steps sit at the start U = 0 (δ = −δ0)
    missed = np.flatnonzero(attached & (np.abs(p - loads) > force.tolerance(s.loading)))
    if missed.size:
        raise AssertionError(f"carried loads missed at steps {list(missed)}: p̄ {p[missed]} vs P {loads[missed]}")
    kinds = [(e["kind"], e["branch"], bool(e["detached"])) for e in row["events"]]
    if kinds != [("jump-in", "loading", False), ("jump-out", "unloading", True)]:
        raise AssertionError(f"expected a jump-in on loading and a detachment on unloading: {row['events']}")
    if "pull_off_load" not in row:
        raise AssertionError(f"no pull-off load: {row}")
    return d, attached, row


def measure(nodes):
    """(differences {metric}, numbers {method: observables}, wall s) at N = nodes."""
    s = scene(nodes)
    t0 = time.perf_counter()
    rf, rg, _, _ = run_fe_and_gfmd(s)
    for label, r in (("FE", rf), ("GFMD", rg)):
        if not r.all_converged:
            raise AssertionError(f"{label} N = {nodes}: not converged: {r.messages[:3]}")
    (df, af, of), (dg, ag, og) = observables(rf, s), observables(rg, s)
    both = af & ag
    dP = abs(PATH[2] - PATH[1]) / STEPS[1]
    ef, eg = of["events"], og["events"]
    diffs = {"δ": float(np.max(np.abs(df[both] - dg[both]))) / float(np.ptp(dg)),
             "pull-off load": abs(of["pull_off_load"] - og["pull_off_load"]) / dP,
             "a_rel at events": max(measured.node_count(abs(x[k] - y[k]), nodes)
                                    for x, y in zip(ef, eg) for k in ("a_rel_before", "a_rel_after")),
             "event steps": max(abs(x["step"] - y["step"]) for x, y in zip(ef, eg))}
    slope = branch_slope(dg, path_values(s.loading), ag, step_branches(s.loading)[0])
    pf, pg = (np.asarray(r.curve["p"], float) for r in (rf, rg))
    from_tolerance = float(np.max(np.abs((pf - pg) * slope)[both])) / float(np.ptp(dg))
    keep = ("kind", "step", "load", "delta_before", "delta_after", "a_rel_before", "a_rel_after")
    numbers = {"δ from the load tolerance": from_tolerance}
    numbers.update({m: {"pull_off_load": o["pull_off_load"], "pull_off_carried": o["pull_off_pressure"],
                   "snap_off_delta": o["snap_off_delta"], "events": [{k: e[k] for k in keep} for e in o["events"]]}
               for m, o in (("fe", of), ("gfmd", og))})
    return diffs, numbers, time.perf_counter() - t0


def branch_slope(delta, loads, attached, branch):
    """dδ/dP (m/Pa) per step from the neighbouring attached steps of the same branch (np.gradient over each
    run of them; 0 where a run has one step)."""
    out = np.zeros(delta.size)
    k = 0
    while k < delta.size:
        j = k
        while j + 1 < delta.size and attached[k] and attached[j + 1] and branch[j + 1] == branch[k]:
            j += 1
        if attached[k] and j > k:
            out[k:j + 1] = np.gradient(delta[k:j + 1], loads[k:j + 1])
        k = j + 1
    return out


def pull_off_scenes(nodes):
    """(displacement-controlled scene sampling p̄(δ) in PULL_OFF_DELTA_STEP steps across the pull-off,
    force-controlled scene stepping the load in PULL_OFF_LOAD_STEP steps across it)."""
    disp = fe_cycle.scene(nodes).replace(**{"loading.path": list(PULL_OFF_DELTA_PATH),
                                            "loading.steps": list(PULL_OFF_DELTA_STEPS)})
    return disp, scene(nodes).replace(**{"loading.path": list(PULL_OFF_LOAD_PATH),
                                         "loading.steps": list(PULL_OFF_LOAD_STEPS)})


def pull_off(nodes=PULL_OFF_NODES):
    """Per method ("fe", "gfmd"): the force-controlled pull-off against the method's own displacement-controlled
    extremum of p̄: {"extremum" (Pa, the vertex of the parabola through the most tensile sampled p̄ and its two
    neighbours), "sampling" (Pa, |sampled − vertex|), "carried" (Pa, the most tensile load carried), "detached"
    (Pa, the load that detached the body), "detached_minus_extremum" (Pa), "step" (Pa, the load step there),
    "tolerance" (Pa, the outer search's |p̄ − P|)}, and the wall time (s). The loads carried must reach the extremum and the first one not carried
    must lie beyond it (verification/test_fe_force_cycle.py)."""
    t0 = time.perf_counter()
    disp, forced = pull_off_scenes(nodes)
    runs = {"disp": run_fe_and_gfmd(disp), "force": run_fe_and_gfmd(forced)}
    for kind, (rf, rg, _, _) in runs.items():
        for label, r in (("FE", rf), ("GFMD", rg)):
            if not r.all_converged:
                raise AssertionError(f"{label} {kind} N = {nodes}: not converged: {r.messages[:3]}")
    fine = np.arange(disp.loading.steps + 1) > sum(PULL_OFF_DELTA_STEPS[:-1])  # the last segment's steps
    out = {}
    for i, m in enumerate(("fe", "gfmd")):
        p = np.asarray(runs["disp"][i].curve["p"], float)
        k = int(np.flatnonzero(fine)[np.argmin(p[fine])])
        if not (fine[k - 1] and k + 1 < p.size):
            raise AssertionError(f"{m} N = {nodes}: the most tensile p̄ is at the edge of the sampled range (step {k})")
        y0, y1, y2 = p[k - 1], p[k], p[k + 1]
        vertex = y1 - (y2 - y0) ** 2 / (8.0 * (y0 - 2.0 * y1 + y2))
        d, attached, row = observables(runs["force"][i], forced)
        out[m] = {"extremum": float(vertex), "sampling": float(abs(y1 - vertex)),
                  "carried": float(row["pull_off_pressure"]), "detached": float(row["pull_off_load"]),
                  "detached_minus_extremum": float(row["pull_off_load"] - vertex),
                  "step": abs(PULL_OFF_LOAD_PATH[3] - PULL_OFF_LOAD_PATH[2]) / PULL_OFF_LOAD_STEPS[2],
                  "tolerance": force.tolerance(forced.loading)}
    return out, time.perf_counter() - t0


def study(nodes=NODES):
    t0 = time.perf_counter()
    data = [measure(n) for n in nodes]
    errors = {m: [d[0][m] for d in data] for m in METRICS}
    orders = {m: [fe_cycle.order(a, b) for a, b in zip(e, e[1:])] for m, e in errors.items()}
    return {"nodes": list(nodes), "data": data, "errors": errors, "orders": orders, "wall_s": time.perf_counter() - t0}


def pull_off_entry(nodes=(PULL_OFF_NODES, 2 * PULL_OFF_NODES)):
    t0 = time.perf_counter()
    data = {f"N={n}": pull_off(n)[0] for n in nodes}
    return measured.make_entry(data, scene=(f"verification.studies.fe_force_cycle.pull_off_scenes(N): displacement path "
                                            f"{list(PULL_OFF_DELTA_PATH)} m in {list(PULL_OFF_DELTA_STEPS)} steps, force "
                                            f"path {list(PULL_OFF_LOAD_PATH)} Pa in {list(PULL_OFF_LOAD_STEPS)} steps"),
                               wall_s=time.perf_counter() - t0)


def entry(st):
    return measured.make_entry({"N": st["nodes"], "ci_nodes": CI_NODES, "errors": st["errors"], "orders": st["orders"],
                                "numbers": [d[1] for d in st["data"]], "wall_s": [d[2] for d in st["data"]]},
                               scene=(f"verification.studies.fe_force_cycle.scene(N): cohesive_sinusoid, φn* = "
                                      f"{fe_cycle.PHI_N_STAR}, force control, path {list(PATH)} Pa, steps "
                                      f"{list(STEPS)}, δ0 = {INITIAL_SEPARATION} m"), wall_s=st["wall_s"])


def stored():
    return measured.entry(NAME, "ci")["values"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_force_cycle.json")
    args = ap.parse_args(argv)
    st = study()
    for m in METRICS:
        print(f"{m}: N {st['nodes']} difference {[f'{e:.3e}' for e in st['errors'][m]]} "
              f"orders {[f'{o:.2f}' for o in st['orders'][m]]}")
    for n, d in zip(st["nodes"], st["data"]):
        print(f"N = {n}: {d[1]} ({d[2]:.1f} s)")
    po = pull_off_entry()
    for n, v in po["values"].items():
        print(f"pull-off {n}: {v}")
    if args.write:
        print(measured.write(NAME, {"ci": entry(st), "pull-off": po},
                             description="GFMD vs FE P2 through a force-controlled load–unload cycle on a cohesive "
                                         "layer (φn* = 0.15): δ on the stable branches, pull-off load, a_rel at the "
                                         "events and the events' steps vs N"))


if __name__ == "__main__":
    main()
