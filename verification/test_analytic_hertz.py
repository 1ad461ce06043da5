"""GFMD hard wall vs Hertz line contact (reference-formulas §2) in a large periodic cell.

Scene: parabolic cylinder h = x²/(2R), R = 1 µm, cell L = 1 µm, E = 70 GPa,
ν = 0.45 half-plane, frictionless hard wall, solver tolerance 1e-10.
Displacement control in 4 steps to the tip penetration δ of §2.2 for a = L/200,
so a/L ≈ 0.0023, 0.0034, 0.0043, 0.0050 (L ≥ 200a: the periodic images change
a(F) by ≈ 0.8 (a/L)² ≤ 2e-5, measured below the discretisation error here).

Metrics (max over the four loads), F = p̄ L:
* a(F): |a_GFMD − a_H(F)|/a_H, a_GFMD = 2√(Σx²p/Σp) (second moment of the
  pressure; exact for the elliptic Hertz pressure, no node-count quantisation —
  the node count gives errors of up to 7% at 10 nodes per half-width).
* p(x): ‖p − p_H‖₂/‖p_H‖₂ over the nodes inside the Hertz contact.

Convergence study (measured when the tolerances were set; the test prints it):

    N             2048     4096     8192     16384    32768    65536
    a/l (max)     10       20       41       82       164      328
    a(F) rel.     1.1e-2   8.6e-4   2.3e-4   1.0e-4   3.1e-5   2.0e-5
    p(x) rel. L2  1.4e-2   8.8e-3   6.9e-3   1.9e-3   8.8e-4   6.4e-4

Observed orders (least squares): CI (2048…16384) a(F) ≈ 2.2, p(x) 0.91; slow
(…65536) a(F) 1.75 (the last point meets the periodic-image floor ≈ 2e-5), p(x) 0.97.

Tolerances (CI: N = 2048…16384): orders a(F) ≥ 1.2, p(x) ≥ 0.6 (measured minus
the scatter of the contact edge moving across nodes); finest-N errors ≤ ≈ 3× the
values measured at N = 16384 (4e-4 and 6e-3). A wrong modulus or radius (factor
2 in E*) would give an a(F) error of 30%.
"""

from __future__ import annotations


import numpy as np
import pytest

from reference.analytic import hertz as H
from verification import analytic_cases as ac
from verification.metrics import relative_l2
from verification.plots import profile_plot, table_plot
from verification.scenes import cylinder

RADIUS = 1e-6
LENGTH = 1e-6
STEPS = 4
A_MAX = LENGTH / 200
FINAL = A_MAX**2 / (4 * RADIUS) * (2 * np.log(LENGTH / (np.pi * A_MAX)) + 1)  # §2.2 δ_rel at a = A_MAX
METHODS = ("gfmd-fire", "analytic-hertz")
CASE = "analytic/hertz-hard-wall-cylinder"
TOL_SOURCE = ("convergence study in verification/test_analytic_hertz.py docstring: orders a(F) ≈ 2.0 "
              "(1.5 once resolved), p(x) ≈ 1.0; finest-N bound ≈ 3× the error measured at N = 16384")
MIN_ORDER = {"a(F)": 1.2, "p(x)": 0.6}
LABELS = {"a(F)": "max |a − a_Hertz(F)| / a_Hertz", "p(x)": "max rel. L2 of p(x) in contact"}


def measure(nodes):
    scene = cylinder(nodes, RADIUS, LENGTH, steps=STEPS, final=FINAL)
    result, wall = ac.run(scene)
    e_star = scene.material.contact_modulus
    rows, errs = [], {"a(F)": [], "p(x)": []}
    for k in range(1, STEPS + 1):
        x, p, gap, pbar, gbar = ac.step_fields(result, k)
        load = pbar * LENGTH
        a_h = H.half_width(load, RADIUS, e_star)
        a = ac.half_width_second_moment(x, p)
        ph = H.pressure(x, load, RADIUS, e_star)
        inside = ph > 0
        e_a, e_p = abs(a - a_h) / a_h, relative_l2(ph[inside], p[inside])
        errs["a(F)"].append(e_a)
        errs["p(x)"].append(e_p)
        rows.append([k, load, a_h / LENGTH, a / LENGTH, a_h / (LENGTH / nodes), e_a, e_p])
    x, p, gap, pbar, gbar = ac.step_fields(result, STEPS)
    ph = H.pressure(x, pbar * LENGTH, RADIUS, e_star)
    a_h = H.half_width(pbar * LENGTH, RADIUS, e_star)
    near = np.abs(x) <= 1.5 * a_h
    fields = dict(x=x[near] / a_h, p=p[near] / ph.max(), ph=ph[near] / ph.max())
    return {m: max(v) for m, v in errs.items()}, rows, fields, wall


def _study(nodes, verification_record, bound_finest, tag):
    data, errors, wall = ac.convergence_study(measure, nodes, MIN_ORDER)
    orders = ac.orders_in(nodes, errors, sign=-1)
    ac.print_orders(tag, "N", nodes, errors, orders)
    rows, fields = data[-1][1], data[-1][2]
    plots = [profile_plot(fields["x"], {"GFMD": fields["p"], "Hertz": fields["ph"]}, xlabel="x / a_Hertz",
                          ylabel="p / p0", title=f"pressure at the last load, N = {nodes[-1]}"),
             table_plot(["step", "F (N/m)", "a_H/L", "a_GFMD/L", "a_H/l", "err a", "err p L2"], rows,
                        title=f"per load, N = {nodes[-1]}")]
    ac.record_n_study(verification_record, case=CASE, methods=METHODS, nodes=nodes, length=LENGTH, errors=errors,
                      orders=orders, labels=LABELS, bounds=bound_finest, min_order=MIN_ORDER,
                      tolerance_source=TOL_SOURCE, wall=wall, plots=plots, resolution={"L/a": 200},
                      notes="R = L = 1 µm, a ≤ L/200, 4 loads")


def test_hertz_convergence(verification_record):
    _study(np.array([2048, 4096, 8192, 16384]), verification_record, {"a(F)": 4e-4, "p(x)": 6e-3}, "CI")


@pytest.mark.slow
def test_hertz_convergence_fine(verification_record):
    # measured at N = 65536: 2.0e-5 / 6.4e-4; bounds ≈ 4–6× (a(F) is at the periodic floor)
    _study(np.array([2048, 4096, 8192, 16384, 32768, 65536]), verification_record,
           {"a(F)": 1.2e-4, "p(x)": 3.5e-3}, "slow")
