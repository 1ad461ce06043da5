"""A force path beyond full contact is refused before the run where that can be known (hard wall, half-plane)."""

import numpy as np
import pytest

import gfmd_contact as gc
from gfmd_contact.core import loading as L
from gfmd_contact.core import surfaces
from gfmd_contact.core.scene import scene_to_toml
from test_load_paths import NM, P_STAR, force_scene


def hard_force_scene(top, **extra):
    return force_scene(top=top, **{"interface.law": "hard-wall", **extra})


def test_full_contact_pressure_of_a_sinusoid_is_westergaards_p_star():
    """p̄_fc = π E* a/λ (Westergaard's full-contact load), computed from the profile and the kernel alone."""
    s = hard_force_scene(0.5)
    h = surfaces.profile(s.surface, 0)
    p_fc = L.full_contact_pressure(h, s.surface.length, s.material.youngs_modulus, s.material.poisson_ratio)
    assert p_fc == pytest.approx(P_STAR, rel=64 * np.finfo(float).eps)  # one FFT pair of 128 nodes


@pytest.mark.parametrize("top, code", [(1.001, 2), (0.5, 0)])
def test_scene_check_refuses_a_hard_wall_force_path_beyond_full_contact(tmp_path, capsys, top, code):
    from gfmd_contact.cli import main

    (tmp_path / "s.toml").write_text(scene_to_toml(hard_force_scene(top)))
    assert main(["scene", "--check", str(tmp_path / "s.toml")]) == code
    err = capsys.readouterr().err
    assert ("loading.path" in err and "beyond full contact" in err) == (code == 2)


def test_rough_hard_wall_stays_below_the_bound_up_to_the_ramps_limit(tmp_path):
    """Displacement control to 0.998 δ_max of a rough profile (hard wall): every p̄ < p̄_fc, so a load ≥ p̄_fc is one the
    ramp cannot reach. Measured: the last step (a_rel = 0.87) carries 0.508 p̄_fc, so a bound too low by 2× (e.g. E*|q|
    for E*|q|/2) fails here; one too high fails the Westergaard test above."""
    s = gc.default_scene().replace(**{"surface.nodes": 256, "surface.length": 320e-9, "surface.realizations": 1, "interface.law": "hard-wall",
                                      "output.field_steps": 2, "output.workers": 1})
    h = surfaces.profile(s.surface, 0)
    d_max = float(np.mean(h) - np.min(h))
    s = s.replace(**{"loading.final_penetration": (1 - L.FULL_CONTACT_MARGIN) * d_max, "loading.steps": 20})
    res = gc.run(s, tmp_path / "run", progress=False)
    p_fc = L.full_contact_pressure(h, s.surface.length, s.material.youngs_modulus, s.material.poisson_ratio)
    p = np.asarray(res.curve["p"], float)
    assert bool(res.curve["converged"].all())
    assert np.all(p < p_fc)
