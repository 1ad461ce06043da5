"""The sphere references' own pull-off, checked by a second route (no GFMD run).

`reference.analytic.jkr_sphere` states its pull-offs in closed form (load control P_c = −(3/2)πwR, a_c, δ_c;
displacement control δ_d, P_d, a_d) and `reference.analytic.maugis_dugdale_sphere` finds its pull-off as the
minimum of P̄(Ā) (Maugis 1992). Two independent routes to the same numbers:

* the extrema of the JKR curves themselves: min over a of `jkr_sphere.load(a)` (load control) and of
  `jkr_sphere.approach(a)` (displacement control), found numerically (bounded Brent), with the load / approach
  at the minimising a. Tolerance: the value at a smooth minimum is found to its round-off, the reference's own
  `PULL_OFF_ROUNDING` (32 ε) relative; the location a only to √(2·32ε·|f|/|f''|) (a flat minimum), f'' from the
  curve's analytic second derivative;
* the Maugis–Dugdale limits: λ → ∞ must reach the JKR sphere's pull-off (P_c/(πwR), a_c/ℓ, from `jkr_sphere`), λ → 0
  the Derjaguin (DMT) value −2πwR (Maugis 1992). The MD pull-off at λ = 10, 100, 1000 (and 0.01, 0.001, 0.0001)
  is extrapolated (Richardson, the observed order of the three); the extrapolated limit must lie within the last
  difference |P̄(λ₂) − P̄(λ₃)| of the limit value (a monotone convergent sequence: the remaining error is below the
  last step when the order is ≥ 1; measured orders 2.0 (JKR) and 1.5 (DMT)).

A wrong pull-off in either reference (e.g. the DMT −2πwR in the JKR sphere, verification/mutations.py
"jkr-sphere-pull-off") fails both routes by O(1).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

from reference.analytic import jkr_sphere as J
from reference.analytic import maugis_dugdale_sphere as MDS
from verification.plots import table_plot

CASE = "analytic/sphere-references-pull-off"
METHODS = ("analytic-jkr-sphere", "analytic-maugis-dugdale-sphere")
RADIUS, E_STAR, WORK = 1e-6, 70e9 / (1 - 0.45**2), 0.1  # m, Pa, J/m² (any positive values)
ROUND = J.PULL_OFF_ROUNDING
JKR_LAMBDAS, DMT_LAMBDAS = (10.0, 100.0, 1000.0), (1e-2, 1e-3, 1e-4)
DMT_PULL_OFF = -2.0  # P_c/(πwR) of Derjaguin's rigid-sphere limit (Maugis 1992, λ → 0)


def _minimum(f, f2, scale):
    """(argmin, min, location tolerance) of f on (1e-3, 10)·scale by bounded Brent; f2 its second derivative."""
    res = minimize_scalar(f, bounds=(1e-3 * scale, 10 * scale), method="bounded", options={"xatol": 1e-14 * scale})
    x = float(res.x)
    return x, float(f(x)), math.sqrt(2 * ROUND * abs(f(x)) / abs(f2(x)))


def _jkr_numeric():
    """{name: (closed form, numeric, tolerance)} for the JKR sphere's two pull-offs."""
    R, E, w = RADIUS, E_STAR, WORK
    c = math.sqrt(8 * math.pi * w * E)
    load2 = (lambda a: 8 * E * a / R - 0.75 * c * a**-0.5)  # d²P/da²
    approach2 = (lambda a: 2 / R + 0.25 * math.sqrt(2 * math.pi * w / E) * a**-1.5)  # d²δ/da²
    P_c, d_c, a_c = J.pull_off_load_control(R, E, w)
    d_d, P_d, a_d = J.pull_off_displacement_control(R, E, w)
    a1, P1, ta1 = _minimum(lambda a: float(J.load(a, R, E, w)), load2, a_c)
    a2, d2, ta2 = _minimum(lambda a: float(J.approach(a, R, E, w)), approach2, a_d)
    return {"load control: P_c": (P_c, P1, ROUND * abs(P_c)),
            "load control: a_c": (a_c, a1, ta1),
            "load control: δ_c": (d_c, float(J.approach(a1, R, E, w)), 4 * ta1 / a_c * abs(d_c) + ROUND * abs(d_c)),
            "displacement control: δ_d": (d_d, d2, ROUND * abs(d_d)),
            "displacement control: a_d": (a_d, a2, ta2),
            "displacement control: P_d": (P_d, float(J.load(a2, R, E, w)),
                                          3 * ta2 / a_d * abs(P_d) + ROUND * abs(P_d))}


def _extrapolated(values):
    """(Richardson limit, observed order, last difference) of three values at parameters a factor 10 apart."""
    d1, d2 = values[1] - values[0], values[2] - values[1]
    order = math.log10(abs(d1 / d2))
    return values[2] + d2 / (10**order - 1), order, abs(d2)


def test_jkr_sphere_pull_off_is_the_extremum_of_its_curves(verification_record):
    rows, failed = [], []
    for name, (closed, numeric, tol) in _jkr_numeric().items():
        diff = abs(closed - numeric)
        rows.append([name, f"{closed:.10g}", f"{numeric:.10g}", f"{diff:.3g}", f"{tol:.3g}"])
        verification_record(
            case=f"{CASE}/jkr-extrema", metric=f"|closed form − numeric extremum| ({name})", value=diff,
            tolerance=tol, methods=("analytic-jkr-sphere",),
            tolerance_source="round-off of the value at a smooth minimum (PULL_OFF_ROUNDING = 32ε relative); "
                             "location √(2·32ε|f|/|f''|)",
            resolution={"R_m": RADIUS, "E_star_Pa": E_STAR, "w_J_m2": WORK},
            plots=[table_plot(["quantity", "closed form", "numeric", "|Δ|", "tolerance"], rows,
                              title="JKR sphere: closed-form pull-offs vs the minima of P(a), δ(a)")]
            if len(rows) == 6 else [])
        if diff > tol:
            failed.append(rows[-1])
    assert not failed, failed


def test_maugis_dugdale_sphere_reaches_jkr_and_dmt(verification_record):
    _, P_u, _ = MDS.units(RADIUS, E_STAR, WORK)
    ell = MDS.units(RADIUS, E_STAR, WORK)[0]
    P_c, _, a_c = J.pull_off_load_control(RADIUS, E_STAR, WORK)
    limits = {"λ → ∞: P_c/(πwR) (JKR sphere)": (JKR_LAMBDAS, 0, P_c / P_u),
              "λ → ∞: a_c/ℓ (JKR sphere)": (JKR_LAMBDAS, 1, a_c / ell),
              "λ → 0: P_c/(πwR) (DMT, −2)": (DMT_LAMBDAS, 0, DMT_PULL_OFF)}
    pulls = {lams: [MDS.pull_off(lam) for lam in lams] for lams in (JKR_LAMBDAS, DMT_LAMBDAS)}
    rows, failed = [], []
    for name, (lams, k, target) in limits.items():
        values = [p[k] for p in pulls[lams]]
        limit, order, last = _extrapolated(values)
        diff = abs(limit - target)
        rows.append([name, *(f"{v:.9g}" for v in values), f"{limit:.9g}", f"{target:.9g}", f"{order:.2f}"])
        ok = diff <= last and order >= 1
        verification_record(
            case=f"{CASE}/maugis-dugdale-limits", metric=f"|Richardson limit − target| ({name})", value=diff,
            tolerance=last, methods=METHODS, passed=ok,
            tolerance_source="the last difference of the λ sequence (a monotone sequence converging at order ≥ 1)",
            resolution={"lambdas": list(lams), "order": order},
            plots=[table_plot(["limit", "λ₁", "λ₂", "λ₃", "extrapolated", "target", "order"], rows,
                              title="Maugis–Dugdale sphere pull-off at λ → ∞ and λ → 0")] if len(rows) == 3 else [])
        if not ok:
            failed.append(rows[-1])
    assert not failed, failed
    assert np.all(np.diff([p[0] for p in pulls[JKR_LAMBDAS]]) > 0), pulls  # JKR approached from below
