"""GFMD vs the FE cell through a force-controlled load–unload cycle on a cohesive layer (each its own law and
observables, both through the one ramp and the generic outer search `gfmd_contact.core.force`).

Study, scene and metrics: `verification.studies.fe_force_cycle` (cohesive_sinusoid with φn* = 0.15 under
`loading.control = "force"`, p̄ path [0, 400, −320] MPa in 5 + 18 steps from out of contact: a jump-in at the
first load, the attached branch down to the last load carried, then detachment beyond the pull-off). Its
differences vs N = 64, 128, 256 (and their observed orders) are in verification/data/fe_force_cycle.json
(regenerate: `python -m verification.studies.fe_force_cycle --write`).

Asserted at the CI N (128, a few seconds): each difference ≤ FACTOR × the stored one at that N (the measured
discretization difference; a rerun reproduces it to round-off), so the events' loads, steps and a_rel before and
after are the same in both methods (stored 0); the stored orders of the δ difference are positive (it falls with
N: both methods converge to one continuum answer); and the δ difference is the discretizations', not the outer
search's (the share its load tolerance can make is below the difference).
"""

from __future__ import annotations

import pytest

from verification import measured
from verification.plots import convergence_plot, table_plot
from verification.studies import fe_force_cycle as ffc

METHODS = ("gfmd-fire", "fe-p2")
CASE = "fe/cohesive-layer-force-cycle"
FACTOR = 2.0
LABELS = {"δ": "max |δ_FE − δ_GFMD| / δ extent on the stable branches",
          "pull-off load": "|Δ P_detach| / ΔP_unloading (load steps)",
          "a_rel at events": "max |Δ a_rel| before/after the events (nodes)",
          "event steps": "max |Δ step| of the events"}


@pytest.fixture(scope="module")
def ci_run():
    return ffc.measure(ffc.CI_NODES)


@pytest.mark.parametrize("metric", ffc.METRICS)
def test_fe_force_cycle(metric, ci_run, verification_record):
    diffs, numbers, wall = ci_run
    s = ffc.stored()
    e = measured.entry(ffc.NAME, "ci")
    i = s["N"].index(ffc.CI_NODES)
    bound = FACTOR * s["errors"][metric][i]
    h = [1e-6 / n for n in s["N"]]
    rows = [[m, numbers[m]["pull_off_load"], numbers[m]["pull_off_carried"], numbers[m]["snap_off_delta"],
             [(x["kind"], x["step"], x["a_rel_before"], x["a_rel_after"]) for x in numbers[m]["events"]]]
            for m in ("gfmd", "fe")]
    plots = [convergence_plot(h, [max(v, 1e-16) for v in s["errors"][metric]], xlabel="node spacing l (m)",
                              ylabel=LABELS[metric], title=f"{metric}: GFMD–FE difference vs l (stored study)"),
             table_plot(["method", "pull-off load (Pa)", "last carried p̄ (Pa)", "δ before detaching (m)",
                         "events (kind, step, a_rel before, after)"], rows,
                        title=f"force-controlled cycle at N = {ffc.CI_NODES}")]
    rec = verification_record(
        case=CASE, metric=f"{LABELS[metric]} at N = {ffc.CI_NODES}", value=float(diffs[metric]), tolerance=bound,
        methods=METHODS,
        tolerance_source=(f"{FACTOR:g}× the difference at N = {ffc.CI_NODES} in verification/data/fe_force_cycle.json "
                          f"({e['code_version']}, {e['date']}); orders between N {s['N']}: {s['orders'][metric]}"),
        resolution={"N": ffc.CI_NODES, "N_study": s["N"], "load_path_Pa": list(ffc.PATH), "steps": list(ffc.STEPS)},
        wall_s=wall, plots=plots, passed=bool(diffs[metric] <= bound),
        notes=f"events FE {numbers['fe']['events']}; GFMD {numbers['gfmd']['events']}")
    assert rec.passed, (metric, diffs[metric], bound)


def test_fe_force_cycle_delta_converges_and_is_not_the_search_tolerance(ci_run):
    """The stored δ differences fall with N at a positive observed order, and at the CI N the outer search's
    load tolerance accounts for less than the δ difference measured (so the comparison sees the discretizations)."""
    diffs, numbers, _ = ci_run
    s = ffc.stored()
    orders = s["orders"]["δ"]
    assert orders and all(o > 0 for o in orders), orders
    assert numbers["δ from the load tolerance"] < diffs["δ"], (numbers["δ from the load tolerance"], diffs["δ"])


@pytest.fixture(scope="module")
def pull_off_run():
    return ffc.pull_off(ffc.PULL_OFF_NODES)


@pytest.mark.parametrize("method", ["fe", "gfmd"])
def test_force_controlled_pull_off_is_the_end_of_the_attached_branch(method, pull_off_run, verification_record):
    """Under force control the body detaches at the first load beyond the most tensile p̄ the method's own
    displacement control passes (the end of the attached branch): the loads carried reach the extremum
    (carried ≥ extremum − tolerance − sampling) and the detach load P_d lies beyond it, P_d − extremum ∈
    (−(ΔP + tolerance + sampling), tolerance). A search that left the branch early (across the extremum onto its
    far side, as the fixed first step δ0/10 did) fails the right end; one that held a load no attached state
    carries fails the left."""
    numbers, wall = pull_off_run
    x = numbers[method]
    slack = x["tolerance"] + x["sampling"]
    value = x["detached"] - x["extremum"]
    passed = -(x["step"] + slack) < value < x["tolerance"] and x["carried"] >= x["extremum"] - slack
    rec = verification_record(
        case=f"{CASE}/pull-off/{method}", metric=f"P_detach − extremum of p̄ (Pa) at N = {ffc.PULL_OFF_NODES}",
        value=float(value), tolerance=float(x["step"] + slack), methods=({"fe": "fe-p2", "gfmd": "gfmd-fire"}[method],),
        tolerance_source=(f"derived: the load step ΔP = {x['step']:.3g} Pa + the search tolerance {x['tolerance']:.3g} Pa "
                          f"+ the displacement sampling {x['sampling']:.3g} Pa, one-sided (< tolerance) beyond the extremum"),
        resolution={"N": ffc.PULL_OFF_NODES, "load_path_Pa": list(ffc.PULL_OFF_LOAD_PATH),
                    "load_steps": list(ffc.PULL_OFF_LOAD_STEPS), "delta_path_m": list(ffc.PULL_OFF_DELTA_PATH),
                    "delta_steps": list(ffc.PULL_OFF_DELTA_STEPS)},
        wall_s=wall, passed=bool(passed), notes=f"{method}: {x}")
    assert rec.passed, (method, x)
