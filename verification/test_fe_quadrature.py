"""FE boundary quadrature: nodal (lumped, default) vs Gauss–Legendre vs GFMD (issue #4).

Scene: `verification.scenes.cohesive_sinusoid` with every step's fields kept (a = 50 nm,
L = D = 1 µm, E = 70 GPa, ν = 0.3, normal CZ, φn* = 0.01, δn = 1 nm, δ0 = 2 nm,
δ from −2 nm to 60 nm in 20 steps). FE P2 (`method.name = "fe"`, workbench.methods)
with quadrature="nodal" (f_i = W_i T(Δ_i), Simpson weights) and "gauss"
(f = Bᵀ(w_g T(Δ_g)), 4 Gauss points per facet, z_ind from the Fourier
interpolant of h; `reference.fem.quadrature`); GFMD (FIRE, nodal forces l T_i).
Outputs are nodal for every method: t_n is T at the GFMD nodes' gaps, p =
−⟨t_z⟩ over the nodes (`contact.observables.step_observables`).

Metrics: t_n = max over the field steps 4, 8, …, 20 of ‖t_n^a − t_n^b‖₂/‖t_n^b‖₂;
p = max_k |p_a − p_b| / max_k |p_GFMD|; p_force: the same with the FE pressure
taken from its own equilibrium total boundary force, −Σ_i f_z,i / L = −Σ (S u)_z / L
(GFMD's p is its total nodal force already), at all steps 1–20.

Measured (this module's runs; N = 512 by the same functions in a one-off run, 6 s per FE run):

    N                          64        128       256       512
    t_n  nodal–Gauss           2.54e-3   2.99e-4   3.60e-5   4.39e-6
    t_n  nodal–GFMD            3.89e-3   6.66e-4   9.43e-5   2.51e-5
    t_n  Gauss–GFMD            5.85e-3   8.70e-4   1.12e-4   2.30e-5
    p    nodal–Gauss           9.22e-4   1.16e-4   1.40e-5   1.68e-6
    p    nodal–GFMD            6.72e-4   1.14e-4   1.60e-5   6.66e-7
    p    Gauss–GFMD            1.59e-3   2.30e-4   3.00e-5   2.19e-6
    p_force nodal–Gauss        2.71e-6   6.44e-8   4.36e-9   2.86e-10
    p_force nodal–GFMD         1.15e-5   3.12e-6   2.38e-6   2.14e-6
    p_force Gauss–GFMD         1.01e-5   3.13e-6   2.38e-6   2.14e-6
    Gauss 3 vs 4 pts, t_n      1.2e-5    3.6e-7    1.1e-8    3.6e-10
    Gauss 5 vs 4 pts, t_n      1.1e-7    1.0e-9    8.3e-12   7.0e-14

Observed orders of the nodal–Gauss difference (64→128, 128→256, 256→512):
t_n 3.09, 3.05, 3.04; p 2.99, 3.05, 3.06; p_force 5.4, 3.9, 3.9. It is a
quadrature error that vanishes with refinement, faster than the FE–GFMD
difference (order ≈ 2.5–2.8), and 4 Gauss points per facet are converged (5
points change t_n by ≤ 1.1e-7).
GFMD (nodal forces) is closer to FE nodal than to FE Gauss for N ≤ 256 (ratio
Gauss–GFMD / nodal–GFMD: t_n 1.50, 1.31, 1.19; p 2.4, 2.0, 1.9) but not in t_n
at N = 512 (t_n ratio 0.92; p 3.3): once the nodal–Gauss difference is small
against the FE–GFMD difference, the latter is set by the elasticity
discretisation, not by the quadrature. The ratio is asserted > 1 only at the
tested N = 64, 128 (CI) and 256 (--full).
The p(δ) difference FE–GFMD (6.7e-4 at N = 64) is almost entirely the FE
observable: the node mean of T omits the Simpson midpoint contributions to the
FE's own total force; with p_force the FE–GFMD difference is 1.2e-5 (N = 64)
and levels off at 2.1–2.4e-6 — not GFMD's tolerance (unchanged for
solver.tolerance 1e-8 → 1e-11 at N = 256); cause not investigated.

Tolerances (bound = 3× the N = 64 value, scaled with the observed order 3):
t_n nodal–Gauss ≤ 7.6e-3·(64/N)³, p nodal–Gauss ≤ 2.8e-3·(64/N)³, p_force
nodal–Gauss ≤ 8e-6·(64/N)³; observed orders (64→128) of t_n and p nodal–Gauss
> 2.5 (measured 3.0–3.1); GFMD closer to FE nodal than to FE Gauss (ratio > 1,
the claim itself) for t_n and p. FE–GFMD p_force is recorded, not asserted.
CI cost (N = 64, 128): ≈ 3 s.
"""

from __future__ import annotations

import time

import numpy as np
import pytest

from contact.loading import field_step_indices
from verification.runs import run_method, with_method
from verification.metrics import field_difference
from verification.plots import convergence_plot, curve_plot, profile_plot
from verification.scenes import cohesive_sinusoid

CASE = "fe/quadrature-nodal-vs-gauss"
METHODS = ("fe-p2 (nodal quadrature)", "fe-p2 (Gauss quadrature)", "gfmd-fire")
SOURCE = ("measured table in verification/test_fe_quadrature.py: bound = 3× the N = 64 value × (64/N)³ "
          "(observed order 3.0–3.1)")
TN_BOUND, P_BOUND, PFORCE_BOUND = 7.6e-3, 2.8e-3, 8e-6  # × (64/N)³
ORDER_MIN = 2.5


def scene(n):
    """The cohesive sinusoid with the fields of every step kept (for p_force)."""
    return cohesive_sinusoid(n).replace(**{"output.field_steps": 20})


_CACHE = {}


def field_steps(result):
    """The steps compared in test_fe_cohesive (4, 8, …, 20), for comparable t_n numbers."""
    return field_step_indices(result.scene.loading, 5)


def t_n_difference(a, b):
    """max over the field steps of ‖t_n^a − t_n^b‖₂ / ‖t_n^b‖₂."""
    return field_difference(a, b, "t_n", steps=field_steps(b))


def force_pressure(result):
    """(steps, p (Pa)) from the FE equilibrium total boundary force −Σ (S u)_z / L at the stored steps."""
    steps = np.array(sorted(result.diagnostics["solutions"]))
    length = result.scene.surface.length
    return steps, np.array([-float(np.sum(result.diagnostics["problem"].S @ result.diagnostics["solutions"][k])) / length for k in steps])


def compare(n):
    if n in _CACHE:
        return _CACHE[n]
    sc = scene(n)
    runs, wall = {}, {}
    for name, run in (("nodal", lambda: run_method(with_method(sc, "fe", order=2))),
                      ("gauss", lambda: run_method(with_method(sc, "fe", order=2, quadrature="gauss",
                                                               linear="dense"))),
                      ("gfmd", lambda: run_method(with_method(sc, "gfmd")))):
        t0 = time.perf_counter()
        runs[name] = run()
        wall[name] = time.perf_counter() - t0
        assert runs[name].all_converged, (name, runs[name].messages)
    rn, rq, rg = runs["nodal"], runs["gauss"], runs["gfmd"]
    p_scale = np.max(np.abs(rg.curve["p"]))
    steps, pf_n = force_pressure(rn)
    _, pf_q = force_pressure(rq)

    def p_diff(a, b):
        return float(np.max(np.abs(a - b)) / p_scale)

    out = {"runs": runs, "wall": wall,
           "tn": {"nodal-gauss": t_n_difference(rq, rn), "nodal-gfmd": t_n_difference(rn, rg),
                  "gauss-gfmd": t_n_difference(rq, rg)},
           "p": {"nodal-gauss": p_diff(rq.curve["p"], rn.curve["p"]),
                 "nodal-gfmd": p_diff(rn.curve["p"], rg.curve["p"]),
                 "gauss-gfmd": p_diff(rq.curve["p"], rg.curve["p"])},
           "p_force": {"nodal-gauss": p_diff(pf_n, pf_q), "nodal-gfmd": p_diff(pf_n, rg.curve["p"][steps]),
                       "gauss-gfmd": p_diff(pf_q, rg.curve["p"][steps])}}
    print(f"\nN={n}: " + "; ".join(f"{m} " + ", ".join(f"{k} {v:.3g}" for k, v in out[m].items())
                                  for m in ("tn", "p", "p_force"))
          + "; wall " + ", ".join(f"{k} {v:.2f} s" for k, v in wall.items()))
    _CACHE[n] = out
    return out


def _record(rec, n, out):
    rn, rq, rg = (out["runs"][k] for k in ("nodal", "gauss", "gfmd"))
    k = max(rn.fields)
    res = {"N": n, "D/L": 1, "elements": "P2", "Gauss points per facet": 4}
    scale = (64 / n) ** 3
    plots = [profile_plot(rn.x, {"FE nodal": rn.fields[k]["t_n"], "FE Gauss": rq.fields[k]["t_n"],
                                 "GFMD": rg.fields[k]["t_n"]}, xlabel="x (m)", ylabel="t_n (Pa)",
                          title=f"t_n at the last step, N = {n}"),
             curve_plot(rn.curve["delta"], {"FE nodal": rn.curve["p"], "FE Gauss": rq.curve["p"],
                                            "GFMD": rg.curve["p"]}, xlabel="δ (m)", ylabel="p (Pa)",
                        title=f"p(δ), N = {n}")]
    wall = sum(out["wall"].values())
    checks = [
        ("t_n relative L2 FE nodal vs FE Gauss (max over field steps)", out["tn"]["nodal-gauss"], TN_BOUND * scale),
        ("p(δ) max diff / max|p|, FE nodal vs FE Gauss", out["p"]["nodal-gauss"], P_BOUND * scale),
        ("p from total boundary force, FE nodal vs FE Gauss", out["p_force"]["nodal-gauss"], PFORCE_BOUND * scale),
    ]
    for i, (metric, value, bound) in enumerate(checks):
        rec(case=CASE, metric=metric, value=value, tolerance=bound, methods=METHODS[:2], tolerance_source=SOURCE,
            resolution=res, **({"plots": plots, "scene": rn.scene, "wall_s": wall} if i == 0 else {}))
    for quantity in ("tn", "p"):
        name = {"tn": "t_n relative L2", "p": "p(δ) max diff"}[quantity]
        ratio = out[quantity]["gauss-gfmd"] / out[quantity]["nodal-gfmd"]
        diffs = f"nodal–GFMD {out[quantity]['nodal-gfmd']:.3g}, Gauss–GFMD {out[quantity]['gauss-gfmd']:.3g}"
        rec(case=CASE, metric=f"{name}: (FE Gauss vs GFMD) / (FE nodal vs GFMD)", value=ratio, tolerance=None,
            passed=bool(ratio > 1), methods=METHODS, resolution=res,
            tolerance_source=f"claim: GFMD (nodal forces) is closer to FE nodal; must exceed 1 ({diffs}; "
                             "N = 512: t_n ratio 0.92, docstring)")
    for pair in ("nodal-gfmd", "gauss-gfmd"):
        rec(case=CASE, metric=f"p from FE total boundary force, {pair.replace('-', ' vs ')}",
            value=out["p_force"][pair], tolerance=None, passed=None, methods=METHODS, resolution=res,
            tolerance_source="informational: compare with the node-mean p difference "
                             f"{out['p'][pair]:.3g} (docstring)")
    for metric, value, bound in checks:
        assert value < bound, f"N = {n}: {metric} = {value:.3g} exceeds {bound:.3g}"
    assert out["tn"]["gauss-gfmd"] > out["tn"]["nodal-gfmd"], out["tn"]
    assert out["p"]["gauss-gfmd"] > out["p"]["nodal-gfmd"], out["p"]


@pytest.mark.parametrize("n", [64, 128, pytest.param(256, marks=pytest.mark.slow)])
def test_fe_quadrature_sinusoid(n, verification_record):
    _record(verification_record, n, compare(n))


def test_fe_quadrature_order(verification_record):
    ns = [64, 128]
    outs = [compare(n) for n in ns]
    h = [1e-6 / n for n in ns]
    for quantity, label in (("tn", "t_n"), ("p", "p(δ)")):
        errs = [o[quantity]["nodal-gauss"] for o in outs]
        order = float(np.log(errs[0] / errs[1]) / np.log(2))
        verification_record(
            case=CASE, metric=f"observed order of the {label} nodal–Gauss difference (N = 64 → 128)", value=order,
            tolerance=None, passed=bool(order > ORDER_MIN), methods=METHODS[:2], resolution={"N": ns},
            tolerance_source=f"measured 3.0–3.1 (docstring); must exceed {ORDER_MIN}",
            plots=[convergence_plot(h, errs, order=order, xlabel="l = L/N (m)",
                                    ylabel=f"{label} FE nodal vs FE Gauss")])
        assert order > ORDER_MIN, f"{label}: nodal–Gauss difference converges with order {order:.2f} ≤ {ORDER_MIN}"
