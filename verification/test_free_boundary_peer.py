"""GFMD on a free half-space vs ContactMechanics' FreeFFTElasticHalfSpace (an independent code, the peers extra).

ContactMechanics solves the free (non-periodic) half-space on the same discretisation, uniform pressure on each
pixel (Love's rectangle) with zero padding, by its constrained conjugate gradients, its displacements relative
to the far field. GFMD's free boundary clamps the padded cell's mean instead and reports the far-field shift s
(`gfmd_contact.core.free_boundary`): at the far-field approach δ − s both must give the same contact pressures.
Checked on the Hertz sphere and on a rough (self-affine) surface, 2+1-D, hard wall, 32 × 32 nodes.

Tolerance: both solve the same discrete problem to a relative residual of 1e-10 (GFMD: × p_ref; ContactMechanics:
forcetol and pentol 1e-12 of their scales), so the pressures agree to 10 × 1e-10 of the peak pressure; measured
7e-11 (sphere) and 9e-12 (rough), max over the loads. A kernel off by 0.1 %, or a shift s off by 0.1 % of δ,
moves them by ≥ 1e-4.
"""

from __future__ import annotations

import numpy as np
import pytest

from verification import analytic_cases as ac
from verification.studies import free_hertz_sphere as fs

TOLERANCE = 10 * ac.ANALYTIC_TOLERANCE
NODES = 32


def _rough(nodes):
    """A self-affine 2+1-D surface (H = 0.8, h_rms = 5 nm, λr = L/4, λs = 4 l) on the free region L × L, hard wall,
    displacement control in 4 steps to δ = 10 nm."""
    from gfmd_contact.core.scene import default_scene

    return default_scene().replace(**{
        "surface.kind": "self-affine", "surface.nodes": nodes, "surface.nodes_y": nodes, "surface.length": fs.LENGTH,
        "surface.length_y": fs.LENGTH, "surface.boundary": "free", "surface.realizations": 1, "surface.hurst": 0.8,
        "surface.h_rms": 5e-9, "surface.rolloff_wavelength": fs.LENGTH / 4, "surface.rollon_wavelength":
        4 * fs.LENGTH / nodes, "interface.law": "hard-wall", "loading.initial_separation": 0.0,
        "loading.final_penetration": 10e-9, "loading.steps": 4, "output.field_steps": 4,
        "solver.tolerance": ac.ANALYTIC_TOLERANCE})


def _peer_pressures(result, step, scene):
    """ContactMechanics' pressures (Pa) at GFMD's far-field approach δ − s of `step` (lengths in L, E* = 1)."""
    cm = pytest.importorskip("ContactMechanics", reason="the peers extra (pip install gfmd-contact[peers])")
    from ContactMechanics.Optimization import constrained_conjugate_gradients
    from SurfaceTopography import Topography

    length, shape = scene.surface.length, np.shape(result.h)
    h = np.asarray(result.h) / length
    substrate = cm.FreeFFTElasticHalfSpace(shape, 1.0, (1.0, 1.0))
    far = float(result.curve["delta"][step]) - float(result.diagnostics["far_field_shift"][step])
    out = constrained_conjugate_gradients(substrate, Topography(-h, (1.0, 1.0), periodic=False),
                                          pentol=1e-12 * float(np.ptp(h)), forcetol=1e-12, maxiter=100000,
                                          offset=far / length + float(h.min()))
    assert out.success, out.message
    return np.asarray(out.jac) * np.prod(shape) * scene.material.contact_modulus


@pytest.mark.parametrize("kind", ["hertz-sphere", "rough"])
def test_free_gfmd_matches_contactmechanics_free_half_space(kind, verification_record):
    pytest.importorskip("ContactMechanics", reason="the peers extra (pip install gfmd-contact[peers])")
    scene = fs.scene(NODES) if kind == "hertz-sphere" else _rough(NODES)
    result, wall = ac.run(scene)
    worst = 0.0
    for step in sorted(result.fields):
        if step == 0:
            continue
        p = -np.asarray(result.fields[step]["t_n"], float)
        worst = max(worst, float(np.max(np.abs(_peer_pressures(result, step, scene) - p)) / np.max(p)))
    rec = verification_record(
        case=f"cross-code/free-half-space-contactmechanics/{kind}", metric="max |p_GFMD − p_CM| / max p_GFMD",
        value=worst, tolerance=TOLERANCE, methods=("gfmd-free", "contactmechanics-free"), scene=scene,
        tolerance_source="10 × the solvers' relative residual 1e-10 (the same discrete problem on both sides)",
        resolution={"N": NODES, "dimension": "2+1-D", "boundary": "free"}, wall_s=wall,
        notes="ContactMechanics at GFMD's far-field approach δ − s (Result.diagnostics['far_field_shift'])")
    assert rec.passed, worst
