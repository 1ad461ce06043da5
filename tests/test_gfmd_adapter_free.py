"""The GFMD adapter's penetration on a free boundary (verification/solvers/gfmd.py, far_field.py): in 2+1-D the
approach from the far field under either control, in 1+1-D NaN (the free half-plane has no far-field reference).

Tolerances: P(δ) against Hertz, 3× the stored error of the free Hertz study at N = 32
(verification/data/free_hertz_sphere.json, the same geometry and loads); the far-field approach is closed to `FAR_FIELD_TOLERANCE` × the height range (1e-10); a penetration
path run at the δ a pressure path returned gives back its loads to 1e-6 (the load search's tolerance is 1e-4 of
the load, the solver's 1e-10; the mean-plane δ instead of the far-field one is 5–9 % off here, ~10 % in load).
"""

from __future__ import annotations

import numpy as np
import pytest

from reference.analytic import hertz_sphere as HS
from verification.solvers.gfmd import FAR_FIELD_TOLERANCE, GFMDSolver
from verification.solvers.protocol import Interface, Problem
from verification.studies import free_hertz_sphere as fhs

E_STAR, LENGTH, RADIUS, N = 1e11, 1e-6, 1e-6, 32


def _problem(h, control, path):
    return Problem(heights=h, lengths=(LENGTH,) * h.ndim, contact_modulus=E_STAR, interface=Interface("hard-wall"),
                   boundary="free", control=control, path=tuple(path), name="free gfmd adapter test")


def _sphere():
    x = (np.arange(N) - N // 2) * LENGTH / N
    return (x[:, None] ** 2 + x[None, :] ** 2) / (2 * RADIUS)


def test_free_surface_penetration_is_controlled_and_reported_from_the_far_field():
    h = _sphere()
    loads = [HS.load_from_contact_radius(f * LENGTH / 8, RADIUS, E_STAR) / LENGTH**2 for f in (0.5, 1.0)]
    pressed = GFMDSolver().solve(_problem(h, "pressure", loads)).states
    deltas = [st.penetration for st in pressed]
    stored, nodes = fhs.measured_errors("ci")
    for st in pressed:  # Hertz's load at the far-field approach, to 3× the stored P(δ − s) error at this N
        assert st.mean_pressure * LENGTH**2 == pytest.approx(HS.load_from_approach(st.penetration, RADIUS, E_STAR),
                                                             rel=3 * stored["P(δ)"][nodes.index(N)])
    pushed = GFMDSolver().solve(_problem(h, "penetration", deltas)).states
    for a, b, delta in zip(pressed, pushed, deltas):
        assert abs(b.penetration - delta) <= FAR_FIELD_TOLERANCE * np.ptp(h)
        assert b.mean_pressure == pytest.approx(a.mean_pressure, rel=1e-6)


def test_free_profile_penetration_is_nan():
    x = (np.arange(64) - 32) * LENGTH / 64
    answer = GFMDSolver().solve(_problem(x**2 / (2 * RADIUS), "penetration", [1e-9, 2e-9]))
    assert all(np.isnan(st.penetration) for st in answer.states)
    assert all(st.mean_pressure > 0 for st in answer.states)
