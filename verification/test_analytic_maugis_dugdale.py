"""GFMD cohesive cylinder vs Maugis–Dugdale (Baney & Hui 1997; reference-formulas §4.2).

Scene: parabolic cylinder R = 1 µm in a periodic cell L = 1 µm, E = 70 GPa,
ν = 0.45 half-plane, exponential CZ law (normal only), w = φn = 1 J/m²; δn set
so that the mapped Maugis parameter (w = φn, σ0 = φn/(e δn)) is λ = 3 or λ = 1.
Scales: ℓ = 2(wR²/(πE*))^{1/3} ≈ 31 nm (L/ℓ ≈ 32), F_u = (πE*w²R)^{1/3}.
Displacement control, 8 steps from first touch to δ = 3 nm (loading only:
a/ℓ ≈ 1.1…2.3, F/F_u ≈ −0.2…2.4). Pull-off is not tested (the ramp only loads).

Which a: MD has a contact edge a (gap 0) and a cohesive-zone edge c where the gap
is w/σ0 = e δn. The exponential law has no gap-0 edge, but the criterion
"gap = e δn" means the same in both, so c_GFMD = (nodes with Δn ≤ e δn)·l/2 and
a_MD is the root of c_MD(a) = c_GFMD. Metric: max over loads of
|F_GFMD − F_MD(a_MD)|/F_u, F = p̄ L. (Using a from Δn ≤ δn instead gives errors
≈ 1 F_u at λ = 1: the definition matters as much as the law.)

What is justified (reference-formulas §4.2 table: the exponential law's pull-off is
−1% (λ = 3) and −7% (λ = 1) off its Dugdale map): the MD curve is a guide, not an
exact reference. Study (max error / F_u over the 8 loads):

    N          2048     4096     8192       (ℓ/l = 63, 126, 252)
    λ = 3      0.028    0.012    0.011      → converges to ≈ 0.01 F_u (< 1% of F)
    λ = 1      0.179    0.162    0.170      → converged in N: a law-shape offset
                                              (GFMD below MD, up to 7–8% of F)

Asserted (N = 4096, CI): λ = 3: |error| ≤ 0.03 F_u (≈ 2.5× the converged 0.012;
the exponential law ≈ Dugdale here); λ = 1: the signed error lies in
[−0.25, +0.02] F_u — one-sided as the §4.2 table predicts (the exponential law is
less adhesive than its Dugdale map, so at a given c it carries less load), with a
band 1.5× the measured 0.17; and the λ = 3 error must be ≤ ½ the λ = 1 error
(the mapping improves with λ). The JKR difference is recorded for context only.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy.optimize import brentq

from reference.analytic import jkr_cylinder as JC
from reference.analytic import maugis_dugdale as MD
from verification import analytic_cases as ac
from verification.plots import convergence_plot, curve_plot, table_plot
from verification.scenes import cylinder

RADIUS = 1e-6
LENGTH = 1e-6
WORK = 1.0
STEPS = 8
FINAL = 3e-9
METHODS = ("gfmd-fire", "analytic-maugis-dugdale")
CASE = "analytic/maugis-dugdale-cohesive-cylinder"
TOL_SOURCE = ("N-study in verification/test_analytic_maugis_dugdale.py docstring: λ = 3 converges to 0.011 F_u "
              "(bound 0.03); λ = 1 converged offset −0.17 F_u (band [−0.25, 0.02], one-sided per "
              "reference-formulas §4.2 table)")
BANDS = {3.0: (-0.03, 0.03), 1.0: (-0.25, 0.02)}


def _e_star():
    return cylinder(64, RADIUS, LENGTH).material.contact_modulus


def measure(nodes, lam):
    e_star = _e_star()
    dn = 1e-9 * MD.maugis_parameter_from_cohesive_law(WORK, 1e-9, RADIUS, e_star) / lam  # λ ∝ 1/δn
    w, s0 = MD.dugdale_from_cohesive_law(WORK, dn)
    scene = cylinder(nodes, RADIUS, LENGTH, law="cohesive", steps=STEPS, final=FINAL,
                              **{"interface.work_normal": WORK, "interface.length_normal": dn})
    result, wall = ac.run(scene)
    ell, f_u, _ = MD.units(RADIUS, e_star, w)
    rows = []
    for k in range(1, STEPS + 1):
        x, p, gap, pbar, gbar = ac.step_fields(result, k)
        c = ac.half_width_gap(gap, np.e * dn, LENGTH / nodes)
        a = brentq(lambda a: MD.cohesive_zone_edge(a, RADIUS, e_star, w, s0) - c, 1e-3 * c, c * (1 - 1e-12))
        load = pbar * LENGTH
        f_md, f_jkr = MD.load(a, RADIUS, e_star, w, s0), JC.load(a, RADIUS, e_star, w)
        rows.append([k, a / ell, c / ell, load / f_u, f_md / f_u, (load - f_md) / f_u, (load - f_jkr) / f_u])
    signed = [r[5] for r in rows]
    worst = max(signed, key=abs)
    return worst, rows, dn, wall


def _case(lam, nodes_list, verification_record):
    t0 = time.perf_counter()
    data = [measure(n, lam) for n in nodes_list]
    wall = time.perf_counter() - t0
    errors = [d[0] for d in data]
    print(f"λ = {lam}: N {list(nodes_list)} worst signed error / F_u {[f'{e:.3f}' for e in errors]}")
    rows = data[-1][1]
    lo, hi = BANDS[lam]
    h = list(LENGTH / np.asarray(nodes_list, float))
    plots = [
        curve_plot([r[1] for r in rows], {"GFMD": [r[3] for r in rows], "Maugis–Dugdale": [r[4] for r in rows]},
                   xlabel="a_MD / ℓ (from the cohesive edge c)", ylabel="F / F_u",
                   title=f"loading branch, λ = {lam}, N = {nodes_list[-1]}", difference=True),
        convergence_plot(h, [abs(e) for e in errors], xlabel="node spacing l (m)",
                         ylabel="max |F − F_MD| / F_u", title=f"λ = {lam}: error vs l (saturates: law shape)"),
        table_plot(["step", "a/ℓ", "c/ℓ", "F/F_u GFMD", "F/F_u MD", "(F − F_MD)/F_u", "(F − F_JKR)/F_u"],
                   rows, title=f"per load, λ = {lam}, N = {nodes_list[-1]}"),
    ]
    rec = verification_record(
        case=f"{CASE}/lambda-{lam:g}", metric="worst signed (F − F_MD(a))/F_u over the loads",
        value=float(errors[-1]), tolerance=max(abs(lo), abs(hi)), methods=METHODS, tolerance_source=TOL_SOURCE,
        resolution={"N": int(nodes_list[-1]), "N_study": [int(n) for n in nodes_list], "lambda": lam,
                    "delta_n_m": data[-1][2], "band": [lo, hi]},
        wall_s=wall, plots=plots, passed=bool(lo <= errors[-1] <= hi),
        notes=("exponential CZ law mapped to Dugdale by w = φn, σ0 = φn/(eδn); loading branch only; "
               "expected law-shape offset ≈ −1% (λ = 3), −7% (λ = 1) of pull-off (reference-formulas §4.2)"))
    return errors[-1], rec


def test_maugis_dugdale_moderate_lambda(verification_record):
    e3, rec3 = _case(3.0, [2048, 4096], verification_record)
    e1, rec1 = _case(1.0, [2048, 4096], verification_record)
    assert rec3.passed, e3
    assert rec1.passed, e1
    assert abs(e3) <= 0.5 * abs(e1), (e3, e1)


@pytest.mark.slow
def test_maugis_dugdale_moderate_lambda_fine(verification_record):
    e3, rec3 = _case(3.0, [2048, 4096, 8192], verification_record)
    e1, rec1 = _case(1.0, [2048, 4096, 8192], verification_record)
    assert rec3.passed and rec1.passed, (e3, e1)
    assert abs(e3) <= 0.5 * abs(e1), (e3, e1)
