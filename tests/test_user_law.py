"""The user-defined interface law (gfmd_contact.core.user_law): its consistency check, the numbers it
derives, GFMD and the FE on it, the chain that runs it, and the Python API around it.

The built-in law re-expressed through it (seed Eq. 3 as callables, written here from the formula)
must give the built-in law's results: its derived numbers to the root finders' tolerance, GFMD's and
the FE's curves to the solvers' tolerance (two converged states of one problem).
"""

import dataclasses
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import gfmd.chains as chains
import gfmd.loading as gl
import gfmd_contact as gc
from gfmd_contact.core import laws
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import SceneError, default_scene
from gfmd_contact.core.user_law import CHECK_RTOL, UserLawError, user_law
from gfmd.problem import InterfaceLaw, Problem
from gfmd.solver import Settings
from reference.fem.run import run_realization as fe_realization

ROOT = Path(__file__).resolve().parent.parent
EPS = np.finfo(float).eps

#: a small cohesive ramp on a layer (the FE meshes layers only): N = 64, 6 steps into contact
SCENE = default_scene().replace(**{
    "surface.nodes": 64, "surface.length": 0.32e-6, "surface.rolloff_wavelength": 0.08e-6,
    "surface.rollon_wavelength": 4 * 0.32e-6 / 64, "surface.realizations": 1, "interface.length_normal": 2e-9,
    "loading.initial_separation": 6e-9, "loading.final_penetration": 4e-9, "loading.steps": 6,
    "material.thickness": 0.32e-6, "output.field_steps": 1})


def eq3(phi, dn, name="Eq. 3 as a user law"):
    """Seed Eq. 3 re-expressed through the extension point: V, T_n, dT_n/dΔn from the formula."""
    def energy(g):
        s = g / dn
        return -phi * (1 + s) * np.exp(-s)

    def traction(g):
        s = g / dn
        return phi / dn * s * np.exp(-s)

    def tangent(g):
        s = g / dn
        return phi / dn**2 * (1 - s) * np.exp(-s)

    return user_law(energy, traction, tangent, dn, name=name)


def morse(phi, ell):
    """A Morse-type law V = φ[(1 − e^{−Δ/ℓ})² − 1]: T_n = (2φ/ℓ)(1 − e^{−s})e^{−s}, s = Δ/ℓ."""
    return user_law(lambda g: phi * ((1 - np.exp(-g / ell)) ** 2 - 1),
                    lambda g: 2 * phi / ell * (1 - np.exp(-g / ell)) * np.exp(-g / ell),
                    lambda g: 2 * phi / ell**2 * (2 * np.exp(-2 * g / ell) - np.exp(-g / ell)), ell, name="morse")


def user_scene(scene=SCENE):
    return dataclasses.replace(scene.replace(**{"interface.law": "user"}),
                               user_law=eq3(scene.work_normal, scene.interface.length_normal))


# ---------------------------------------------------------------- the consistency check names the problem

PHI, DN = 0.1, 1e-9


def _parts(**wrong):
    law = eq3(PHI, DN)
    parts = {"energy": law.energy, "traction": law.traction, "tangent": law.tangent_fn, "length": DN}
    parts.update(wrong)
    return parts


@pytest.mark.parametrize("wrong, words", [
    ({"traction": lambda g: -PHI / DN * (g / DN) * np.exp(-g / DN)}, ["traction is not denergy/dΔn", "sign"]),
    ({"traction": lambda g: 2 * PHI / DN * (g / DN) * np.exp(-g / DN)}, ["traction is not denergy/dΔn"]),
    ({"tangent": lambda g: PHI / DN**2 * (1 - g / DN) * np.exp(-g / DN) * 1e9}, ["tangent is not dtraction/dΔn"]),
    ({"tangent": lambda g: PHI / DN * (1 - g / DN) * np.exp(-g / DN)}, ["tangent is not dtraction/dΔn", "units"]),
    ({"energy": lambda g: PHI * (1 + g / DN) * np.exp(-g / DN)}, ["traction is not denergy/dΔn"]),
    ({"traction": lambda g: np.where(g > 5 * DN, np.nan, PHI / DN * (g / DN) * np.exp(-g / DN))},
     ["traction(Δn) is not finite"]),
    ({"energy": lambda g: -PHI * (1 + g[0] / DN) * math.exp(-g[0] / DN) + 0 * g[:3]}, ["energy", "vectorised"]),
    ({"tangent": lambda g: PHI / DN**2 * (1 - float(g / DN)) * np.exp(-g / DN)}, ["tangent(Δn) failed", "vectorised"]),
    ({"traction": 3.0}, ["traction must be a callable"]),
    ({"length": -1e-9}, ["length = -1e-09"]),
])
def test_the_consistency_check_names_what_is_wrong(wrong, words):
    with pytest.raises(UserLawError) as info:
        user_law(**_parts(**wrong), name="bad")
    for w in words:
        assert w in str(info.value), str(info.value)


def test_a_consistent_law_passes_and_a_slightly_wrong_one_fails_at_the_stated_tolerance():
    # the check's tolerance is CHECK_RTOL of the largest |T_n|: a relative error of 10·CHECK_RTOL in T_n is caught,
    # one of CHECK_RTOL/10 (far above the central difference's own error, module docstring) is not
    law = eq3(PHI, DN)
    for factor, fails in ((1 + 10 * CHECK_RTOL, True), (1 + CHECK_RTOL / 10, False)):
        parts = _parts(traction=lambda g, f=factor: f * law.traction(g))
        if fails:
            with pytest.raises(UserLawError, match="traction is not"):
                user_law(**parts)
        else:
            user_law(**parts)


# ---------------------------------------------------------------- derived numbers

def test_eq3_through_the_extension_point_derives_the_built_in_numbers():
    sc = SCENE
    built_in = laws.law_from_scene(sc)
    user = laws.law_from_scene(user_scene(sc))
    # peak: Brent to xatol 1e-12 δn on a flat maximum (error ~ (1e-12)² relative); Δtol: brentq to
    # xtol 1e-15 δn, rtol 4ε at Δtol ≈ 9 δn; jump-in: brentq to 1e-14 δn on a root ≈ 3 δn
    assert user.peak_traction == pytest.approx(built_in.peak_traction, rel=8 * EPS)
    assert user.contact_gap == pytest.approx(built_in.contact_gap, rel=1e-14)
    assert user.initial_stiffness == built_in.initial_stiffness
    assert user.reference_traction(1.0) == pytest.approx(built_in.reference_traction(1.0), rel=8 * EPS)
    k = 0.5 * built_in.steepest_softening
    assert user.jump_in_separation(k) == pytest.approx(built_in.jump_in_separation(k), rel=1e-12)
    assert user.jump_in_separation(2 * built_in.steepest_softening) == 0.0
    # steepest softening: the max of −dT_n/dΔn on the grid (spacing 0.01 δn); s = 2 is a grid point
    assert user.steepest_softening == pytest.approx(built_in.steepest_softening, rel=1e-12)
    # w = V(50 δn) − min V = φn (1 − 51 e^{−50}): the far end's energy is 1e-20 φn
    assert user.work_normal == pytest.approx(built_in.work_normal, rel=1e-14)
    from gfmd_contact.core import stickiness

    assert stickiness.resolution_warnings(user_scene(sc)) == stickiness.resolution_warnings(sc)
    # l_pz = E* w/σ_max²: w from Brent at xatol 1e-12 δn on V's quadratic minimum, round-off of a few ε
    assert (stickiness.as_dict(user_scene(sc))["process_zone"]["value"]
            == pytest.approx(stickiness.as_dict(sc)["process_zone"]["value"], rel=1e-13))


def test_a_morse_law_derives_its_known_numbers():
    phi, ell, tol = 0.05, 2e-9, 1e-3
    law = morse(phi, ell)
    assert law.peak_gap == pytest.approx(ell * math.log(2), rel=1e-9)  # e^{−s} = 1/2
    assert law.peak_traction == pytest.approx(phi / (2 * ell), rel=1e-14)
    assert law.work_normal == pytest.approx(phi, rel=1e-14)  # V(0) = −φ, V(50 ℓ) ≈ −2e^{−50} φ
    x = (1 - math.sqrt(1 - tol * math.e)) / 2  # 2(1 − x)x φ/ℓ = tol·e·φ/(2ℓ), the decaying branch's root
    assert law.contact_gap == pytest.approx(-ell * math.log(x), rel=1e-13)
    # −k = (2φ/ℓ²)(x − 2x²), x = e^{−s}, is largest at x = 1/4: φ/(4ℓ²). The grid (spacing 0.01 ℓ) meets s = ln 4
    # to δs ≤ 0.005, where −k falls short by ½·|d²(x − 2x²)/ds²|·δs² / (1/8) = ½·(1/4)·δs²·8 = δs² ≤ 2.5e-5
    assert law.steepest_softening == pytest.approx(phi / (4 * ell**2), rel=3e-5)
    assert law.in_contact(np.array([0.0, 10 * ell]), np.zeros(2)).tolist() == [True, False]


# ---------------------------------------------------------------- GFMD and the FE agree with the built-in law

def _close(user, built_in, p_scale, tolerance):
    """Two converged ramps of one problem: equal contact areas, pressures within the stopping test's scale."""
    assert np.array_equal(user.curve["a_rel"], built_in.curve["a_rel"])
    assert np.all(user.curve["converged"]) and np.all(built_in.curve["converged"])
    diff = np.max(np.abs(np.asarray(user.curve["p"]) - np.asarray(built_in.curve["p"])))
    assert diff <= tolerance * p_scale, (diff, p_scale)
    return diff


def test_gfmd_on_eq3_as_a_user_law_matches_the_built_in_law():
    # each step stops at max|f| < tolerance·p_ref; the mean pressure of two such states of one problem
    # differs by at most the mean force residuals, < 2·tolerance·p_ref (measured: 1.4e-18 p_ref, the same
    # iterations per step: the generic nodal path differs from the fused Eq. 3 one by round-off only)
    built_in, user = gl.run_realization(SCENE, 0), gl.run_realization(user_scene(), 0)
    p_ref = build_model(SCENE, built_in.h).reference_traction
    _close(user, built_in, p_ref, 2 * SCENE.solver.tolerance)
    assert set(user.diagnostics["algorithms"]) == {"ncg"} == set(built_in.diagnostics["algorithms"])
    assert user.method == built_in.method == "gfmd-ncg" and user.model.startswith("Eq. 3 as a user law")


def test_the_fe_on_eq3_as_a_user_law_matches_its_own_built_in_law():
    built_in, user = fe_realization(SCENE, 0), fe_realization(user_scene(), 0)
    p_ref = build_model(SCENE, built_in.h).reference_traction  # the FE's own scale E*ḡ, as GFMD's
    _close(user, built_in, p_ref, 2 * SCENE.solver.tolerance)


# ---------------------------------------------------------------- the chain and its labels

def _problem(scene):
    model = build_model(scene)
    z = np.full(model.nodes, scene.loading.initial_separation)
    return Problem(model, InterfaceLaw(model), z)


def test_the_user_law_has_the_normal_laws_chain_ncg_then_fire():
    """A user law is a normal law with a potential (the law protocol): the chains of every such law."""
    problem = _problem(user_scene())
    assert problem.kind == "cohesive"
    assert chains.chain_key(problem, Settings()) == ("cohesive", "ncg")
    assert chains.labels(("cohesive", "ncg"), Settings()) == ("ncg", "fire")
    assert chains.chain_key(problem, Settings(method="verlet")) == ("cohesive", "verlet")
    assert chains.chain_key(problem, Settings(cohesive="fire")) == ("cohesive", "fire")


def test_a_stalled_user_law_step_is_finished_by_fire_and_labelled_so(monkeypatch):
    import gfmd.algorithms.ncg as ncg
    monkeypatch.setattr(ncg, "NCG_BUDGET", 2)
    sc = user_scene()
    result = gl.run_realization(sc, 0, settings=Settings(tolerance=sc.solver.tolerance, max_iterations=20000))
    assert "ncg→fire" in set(result.diagnostics["algorithms"]) and np.all(result.curve["converged"])


def test_the_energy_of_the_problem_is_the_users():
    sc = user_scene()
    problem = _problem(sc)
    built_in = _problem(SCENE)
    u = np.zeros((1, sc.surface.nodes // 2 + 1), complex)
    assert problem.energy(u) == pytest.approx(built_in.energy(u), rel=1e-15)


# ---------------------------------------------------------------- the Python API and its refusals

@pytest.mark.filterwarnings("ignore:under-resolved")
def test_run_with_a_user_law_says_what_ran(tmp_path):
    law = eq3(SCENE.work_normal, SCENE.interface.length_normal, name="my Eq. 3")
    res = gc.run(SCENE, out=tmp_path / "u", law=law, progress=False)
    assert res.meta["user_law"]["name"] == "my Eq. 3" and res.meta["user_law"]["reproducible_from_scene_toml"] is False
    assert any("cannot be reproduced from scene.toml alone" in n for n in res.meta["notes"])
    assert "my Eq. 3" in res.meta["model"] and res.meta["method"] == "gfmd-ncg"
    assert 'law = "user"' in (tmp_path / "u" / "scene.toml").read_text()
    again = gc.open_run(tmp_path / "u")
    with pytest.raises(SceneError, match="cannot run from scene.toml alone"):
        gc.run(again.scene, out=tmp_path / "v", progress=False)
    done = subprocess.run([sys.executable, "-m", "gfmd", "run", str(tmp_path / "u" / "scene.toml"), "--out",
                           str(tmp_path / "w")], capture_output=True, text=True, timeout=300,
                          env={**__import__("os").environ, "PYTHONPATH": str(ROOT)})
    assert done.returncode == 2 and "interface.law = \"user\"" in done.stderr


def test_refusals_name_the_key():
    law = eq3(PHI, DN)
    with pytest.raises(SceneError, match="interface.tangential_ratio"):
        gc.with_law(gc.change(SCENE, {"interface.tangential_ratio": 0.5}), law)
    with pytest.raises(SceneError, match="solver.unknowns"):
        gc.change(gc.with_law(SCENE, law), {"solver.unknowns": "coupled"})
    with pytest.raises(SceneError, match="module-level"):
        gc.run(SCENE, law=morse(0.05, 2e-9), workers=2, progress=False)
    with pytest.raises(SceneError, match="expected a user law"):
        gc.with_law(SCENE, lambda g: g)
    with pytest.raises(gc.StudyError, match="cannot hold the user law"):
        gc.make_study(gc.with_law(SCENE, law), axes={"surface.nodes": [64, 128]})


def test_with_law_survives_changes():
    scene = gc.with_law(SCENE, eq3(PHI, DN))
    changed = gc.change(scene, {"surface.nodes": 128})
    assert changed.user_law is scene.user_law and changed.interface.law == "user"
    assert gc.change(scene, {"interface.law": "cohesive"}).user_law is None
