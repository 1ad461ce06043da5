"""A user law's derived contact rule against the built-in law it re-expresses, on the same run.

Seed Eq. 3 written here from the formula as a user law (`gfmd_contact.user_law`: V, T_n, dT_n/dΔn as numpy
callables and δn; nothing else given) must behave as the built-in cohesive law on the same scene
(`verification.scenes.cohesive_sinusoid`, N = 128, 20 steps into contact, fields at every step). The user law
derives its traction-tolerance contact gap Δtol by root finding on its own callables (`gfmd_contact.core.user_law`);
the built-in law has it in closed form (Lambert W, `gfmd_contact.core.law_equations.contact_gap_threshold`):

* Δtol: the two routes to the same root; tolerance the root finder's (1e-15 δn + 4ε Δtol) plus the Lambert W's
  round-off (8ε Δtol);
* a_rel at every step: the contact set of two converged states of one problem, counted by each law's own rule:
  equal (a count of steps that differ, tolerance 0). The nodes near Δtol ≈ 9.1 δn are many (the gap grows
  smoothly away from the contact edge), so a Δtol off by a few per cent changes a_rel at most steps;
* p̄ at every step: two converged states (max|f| < τ p_ref each) differ by at most k_max |Δu| + 2τ p_ref,
  |Δu| ≤ 2τ p_ref √N / k_min (`verification.converged_bounds`).

verification/mutations.py "user-law-tolerance-gap" (Δtol without the factor e) fails the a_rel and Δtol checks.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from gfmd_contact import user_law
from gfmd_contact.core.laws import law_from_scene
from verification.converged_bounds import state_bounds
from verification.plots import curve_plot
from verification.runs import run_gfmd
from verification.scenes import cohesive_sinusoid

CASE = "user-law/contact-rule-vs-built-in"
METHODS = ("gfmd-user-law", "gfmd-built-in-law")
NODES = 128
EPS = np.finfo(float).eps


def eq3_user_law(phi, dn):
    """Seed Eq. 3, V = −φn(1 + s)e^{−s}, s = Δn/δn, through the extension point."""
    def energy(g):
        return -phi * (1 + g / dn) * np.exp(-g / dn)

    def traction(g):
        return phi / dn * (g / dn) * np.exp(-g / dn)

    def tangent(g):
        return phi / dn**2 * (1 - g / dn) * np.exp(-g / dn)

    return user_law(energy, traction, tangent, dn, name="seed Eq. 3 as a user law")


def _scenes():
    built_in = cohesive_sinusoid(NODES).replace(**{"output.field_steps": 20})
    law = eq3_user_law(built_in.work_normal, built_in.interface.length_normal)
    return built_in, dataclasses.replace(built_in.replace(**{"interface.law": "user"}), user_law=law)


def test_user_law_contact_rule_equals_the_built_in(verification_record):
    built_in, user = _scenes()
    gap_b, gap_u = law_from_scene(built_in).contact_gap, law_from_scene(user).contact_gap
    dn = built_in.interface.length_normal
    (rb, wb), (ru, wu) = run_gfmd(built_in), run_gfmd(user)
    a_b, a_u = np.asarray(rb.curve["a_rel"], float), np.asarray(ru.curve["a_rel"], float)
    p_b, p_u = np.asarray(rb.curve["p"], float), np.asarray(ru.curve["p"], float)
    checks = {"Δtol: |user − built-in| (m)": (abs(gap_u - gap_b), 1e-15 * dn + 12 * EPS * gap_b),
              "a_rel: steps that differ": (int(np.sum(a_b != a_u)), 0),
              "p̄: max |user − built-in| (Pa)": (float(np.max(np.abs(p_u - p_b))), state_bounds(built_in)[1])}
    plot = curve_plot(list(rb.curve["delta"]), {"built-in a_rel": list(a_b), "user law a_rel": list(a_u)},
                      xlabel="δ (m)", ylabel="a_rel", title="seed Eq. 3 built in and as a user law")
    failed = []
    for metric, (value, tol) in checks.items():
        verification_record(
            case=CASE, metric=metric, value=value, tolerance=tol, methods=METHODS, wall_s=wb + wu,
            tolerance_source=("root finder + Lambert W round-off" if metric.startswith("Δtol") else
                              "a count: exact" if tol == 0 else "converged-state bound k_max|Δu| + 2τ p_ref"),
            resolution={"N": NODES, "steps": len(a_b) - 1}, scene=built_in,
            plots=[plot] if metric.startswith("a_rel") else [],
            notes=f"Δtol built-in {gap_b / dn:.6g} δn, user law {gap_u / dn:.6g} δn")
        if value > tol:
            failed.append((metric, value, tol))
    assert not failed, failed
