"""The FE cell's load–unload cycle of the adhesive sinusoid vs Johnson's (1995) JKR-wavy solution, displacement control.

Study, scene, analytic cycle and metrics: `verification.studies.fe_jkr_cycle` (the GFMD study's sinusoid, α = 0.3,
on a layer D = 2λ whose mean compliance C = D(1+ν)(1−2ν)/(E(1−ν)) enters Johnson's δ(a) = h0 − ḡ(a) + C p̄(a);
path [−0.6 h0, 0.6 h0, −0.6 h0] in 60 + 240 steps from out of contact, δn lowered at fixed w). Its measured
errors and rates are in verification/data/fe_jkr_cycle.json (regenerate: `python -m verification.studies.fe_jkr_cycle
--write`): "ci" N = 256 at d/λ = 0.04, 0.02 (≈ 15 s per case), "full" N = 512 adding d/λ = 0.01 (slow).

Asserted, as for GFMD (verification/test_jkr_cycle.py): each metric's error at the smallest δn ≤ FACTOR × the
stored one (a regression bound on the measured error), and the observed rate in δn ≥ the stored rate minus
MARGIN. The FE must have needed its fallback (the trust-region energy descent) at the jump-in and the snap-off:
without it there is no closed FE loop from out of contact (pseudo-transient continuation stalled at the jump-in).
"""

from __future__ import annotations

import pytest

from verification import analytic_cases as ac
from verification import measured
from verification.plots import convergence_plot, curve_plot, table_plot
from verification.studies import fe_jkr_cycle as fj

METHODS = ("fe-p2", "analytic-jkr-sinusoid")
CASE = "fe/jkr-wavy-cohesive-sinusoid-cycle"
FACTOR = 2.0
MARGIN = 0.3
LABELS = {"pull-off": "|p̄_pull-off − Johnson| / p*", "snap-off δ": "|δ_snap-off − Johnson| / h0",
          "jump-in δ": "|δ_jump-in − 0| / h0", "hysteresis": "|W − W_Johnson| / W_Johnson",
          "loading branch": "max |p̄ − p̄_J(δ)| / p*, loading", "unloading branch": "max |p̄ − p̄_J(δ)| / p*, unloading"}


@pytest.mark.parametrize("subset", ["ci", pytest.param("full", marks=pytest.mark.slow)])
def test_fe_jkr_cycle_delta_n_convergence(subset, verification_record):
    stored = measured.entry(fj.NAME, subset)
    values = stored["values"]
    stored_errors, stored_rates = values["errors"], values["rates"]
    st = fj.study(subset)
    dns, errors, rates = st["delta_n"], st["errors"], st["rates"]
    ac.print_orders(subset, "δn", dns, errors, rates)
    ref = fj.johnson_numbers()
    d, p, branch = st["data"][-1][2]
    records = []
    for m in fj.METRICS:
        bound = FACTOR * stored_errors[m][-1]
        plots = [curve_plot(d, {f"FE d/λ = {st['d_rel'][-1]}": p}, xlabel="δ / h0", ylabel="p̄ / p*",
                            title="FE p̄–δ cycle (loading then unloading), smallest δn"),
                 table_plot(["d/λ"] + list(st["data"][0][1]), [[dr] + list(x[1].values()) for dr, x in
                                                               zip(st["d_rel"], st["data"])],
                            title=f"FE cycle observables; Johnson on the layer: {ref}"),
                 convergence_plot(list(dns), list(errors[m]), order=rates[m], xlabel="δn (m) at fixed w",
                                  ylabel=LABELS[m], title=f"{m}: FE error vs δn (rate {rates[m]:.2f})")]
        rec = verification_record(
            case=CASE, metric=f"{LABELS[m]} at d/λ = {st['d_rel'][-1]}, N = {st['nodes']}", value=float(errors[m][-1]),
            tolerance=bound, methods=METHODS,
            tolerance_source=(f"{FACTOR:g}× the error at d/λ = {st['d_rel'][-1]} in verification/data/fe_jkr_cycle.json "
                              f"[{subset}] ({stored['code_version']}, {stored['date']}); rate ≥ stored "
                              f"{stored_rates[m]:.2f} − {MARGIN}"),
            resolution={"N": st["nodes"], "delta_n_m": [float(v) for v in dns], "d_over_lambda": st["d_rel"],
                        "rate_in_delta_n": rates[m], "min_rate": stored_rates[m] - MARGIN, "steps": list(fj.STEPS)},
            wall_s=st["wall_s"], plots=plots, notes=f"layer D = 2λ; displacement control; Johnson on the layer {ref}")
        records.append((m, rec))
    for x in st["data"]:  # the jump-in and the snap-off went through the FE's fallback
        assert set(x[1]["jump_steps"]) <= set(x[1]["fallback_steps"]), x[1]
    ac.assert_study(records, rates, {m: stored_rates[m] - MARGIN for m in fj.METRICS}, errors)
