"""gfmd_contact.core.force.solve_load on synthetic p̄(U) curves: the outer search finds the equilibrium that the
stable branch reaches first from the previous state, not another root across an extremum of p̄(U).

The hump is the one measured on the cohesive layer at N = 64 near the pull-off (verification/studies/
fe_force_cycle.py; FE and GFMD alike): unloading (U falling), p̄ grows more tensile to a most tensile
p̄_m = −267.58 MPa at U_m = 2.40 nm, falls back on the far side, and the layer snaps off below U_s = 1.74 nm
(p̄ ≈ −1 MPa beyond). Loads between the previous step's p̄ and p̄_m are carried on the near side (U > U_m);
the far side (U < U_m) is the branch that force control cannot hold.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from gfmd_contact.core import force

NM, MPA = 1e-9, 1e6
U_M, P_M, U_S = 2.40 * NM, -267.58 * MPA, 1.74 * NM
U0, P0 = 2.68 * NM, -266.03 * MPA  # the last accepted step, on the near side
CURV = (P0 - P_M) / (U0 - U_M) ** 2
STEP = 1.0 * NM  # first_step: δ0/10 with δ0 = 10 nm
TOL = 40e3  # FORCE_TOLERANCE × 400 MPa (the path's largest |load|)


def hump(U):
    return P_M + CURV * (U - U_M) ** 2 if U > U_S else -1.0 * MPA * U / U_S


def search(target, base_U=U0, p=hump):
    calls = []

    def solve(U, guess, fallback):
        calls.append(U)
        return SimpleNamespace(state=U, converged=True, iterations=1, p=p(U))

    base = (base_U, base_U, {"p": p(base_U), "a_rel": 0.2}, None)
    out = force.solve_load(solve, lambda sol: {"p": sol.p, "a_rel": 0.2 if sol.p < -10 * MPA else 0.0}, target, base,
                           step=STEP, tolerance=TOL, u_max=np.inf)
    return out, calls


def near_root(target):
    return U_M + np.sqrt((target - P_M) / CURV)


@pytest.mark.parametrize("target", [
    hump(2.18 * NM) + 0.5 * TOL,  # a far-side trial at U0 − STEP/2 lands within the tolerance of this load
    -266.5 * MPA, -267.0 * MPA, -267.5 * MPA])
def test_a_load_short_of_the_extremum_is_carried_on_the_near_side(target):
    out, _ = search(target)
    assert out.converged and out.event is None and not out.detached
    assert abs(out.obs["p"] - target) <= TOL
    assert out.U > U_M, f"U = {out.U / NM:.4f} nm is across the extremum (U_m = {U_M / NM} nm)"
    root = near_root(target)
    assert abs(out.U - root) <= TOL / (2 * CURV * (root - U_M))  # |p̄ − P| ≤ TOL over the local slope


def test_a_load_beyond_the_extremum_detaches():
    out, _ = search(-268.0 * MPA)
    assert out.detached and out.event is not None and out.event["detached"] and out.U == 0.0


def test_the_stable_branch_is_followed_load_by_load_to_the_extremum():
    """Unloading in 0.1 MPa steps from U0: every load up to p̄_m is carried on the near side (U falls
    monotonically towards U_m), the first beyond it (by more than the tolerance) detaches."""
    U = U0
    for target in np.arange(-266.05, -268.0, -0.1) * MPA:  # … −267.55, −267.65 MPa: ≥ 30 kPa from p̄_m
        out, _ = search(target, base_U=U)
        if target < P_M:
            assert out.detached, (target, out.U)
            break
        assert not out.detached and out.event is None and U_M < out.U <= U, (target / MPA, out.U / NM)
        U = out.U
    else:
        pytest.fail("never detached")
