"""The FE's fallback through a jump into contact (`reference.fem.solver.SurfaceProblem.descend`).

Scene: `verification.studies.fe_cycle.scene(32)` (cohesive sinusoid on a layer, φn* = 0.15, δn = 1 nm, from
δ = −10 nm in 1 nm steps). At δ = −5 nm no equilibrium is near the previous one (the surface jumps into
contact): Newton from the previous state fails; the trust-region descent must reach a locally stable
equilibrium of lower energy within the tolerance, in contact; cut short it must say it did not converge.
"""

from __future__ import annotations

import numpy as np
import pytest

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import displacement_steps
from reference.fem.geometry import surface_indenter
from reference.fem.run import prepare_cohesive
from verification.studies import fe_cycle

TOL = 1e-10
JUMP_STEP = 5  # δ = −5 nm


@pytest.fixture(scope="module")
def before_jump():
    s = fe_cycle.scene(32)
    prob = prepare_cohesive(s, surfaces.profile(s.surface)).prob
    u_steps = displacement_steps(s.loading)

    def z(k):
        return surface_indenter(prob.h_surface, prob.h_min, s.loading.initial_separation, u_steps[k])

    u = np.zeros(prob.S.shape[0])
    for k in range(JUMP_STEP):
        u, res, _, ok, how = prob.solve_step(u, z(k), TOL, fallback_from=u)
        assert ok and how == "newton", (k, res, how)
    return prob, u, z(JUMP_STEP)


def test_newton_fails_at_the_jump(before_jump):
    prob, u, z = before_jump
    _, _, _, ok = prob.newton(u.copy(), z, TOL)
    assert not ok or not prob.stable(prob.newton(u.copy(), z, TOL)[0], z)


def test_descent_reaches_a_stable_contact_state(before_jump):
    prob, u, z = before_jump
    u1, res, _, ok = prob.descend(u.copy(), z, TOL * 1e3)
    assert ok and res <= TOL * 1e3
    assert prob.energy(u1, z) < prob.energy(u, z)
    assert prob.stable(u1, z)
    gap0, gap1 = z - prob.split(u)[1], z - prob.split(u1)[1]
    assert gap1.min() < prob.dn < gap0.min()  # jumped into contact (the closest point within δn)
    u2, res2, _, ok2, how = prob.solve_step(u.copy(), z, TOL, fallback_from=u)
    assert ok2 and res2 <= TOL and how.startswith("trust-region energy descent")


def test_descent_cut_short_reports_not_converged(before_jump):
    prob, u, z = before_jump
    _, res, iterations, ok = prob.descend(u.copy(), z, TOL, max_iter=3)
    assert not ok and res > TOL and iterations == 3
