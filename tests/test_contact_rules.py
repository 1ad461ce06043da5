"""Contact rules (interface.contact_rule) and the cohesive wall (interface.law = "cohesive-wall").

* the rules on constructed fields: "compressive" ⊂ "traction-tolerance" for the cohesive laws, "gap" at
  contact_gap = Δtol/δn is "traction-tolerance", the hard wall's "traction-tolerance" is "compressive",
  and the FE reference's own contact set (`reference.fem.observables.contact_set`) equals the law
  objects' `in_contact` on the same fields, for every law and rule;
* the rules on a converged hard-wall GFMD solution;
* scene validation (errors name the key), the resolved scene and `Scene.replace`, the FE refusal;
* the cohesive wall on converged GFMD steps: the KKT conditions (gap ≥ 0, reaction ≥ 0 on the wall,
  force balance off it), equality with the cohesive law while nothing touches the wall, and the
  hard wall as φn* → 0 (difference ∝ φn*, measured).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gfmd_contact.core import laws, surfaces
from gfmd_contact.core.kernels import contact_modulus
from gfmd_contact.core.loading import displacement_steps, indenter_surface
from gfmd_contact.core.model import softest_normal_stiffness
from gfmd_contact.core.observables import step_observables
from gfmd_contact.core.scene import SceneError, default_scene, load_scene, scene_from_dict, scene_to_dict, scene_to_toml
from gfmd.loading import prepare
from reference.fem.law import CohesiveZone
from reference.fem.observables import contact_set

RULES = ("traction-tolerance", "compressive", "gap")
LAWS = ("hard-wall", "cohesive", "cohesive-wall")
DN = 1e-9


def _scene(law="cohesive", rule="traction-tolerance", **extra):
    keys = {"interface.law": law, "interface.contact_rule": rule, "interface.length_normal": DN, **extra}
    return default_scene().replace(**keys)


# ------------------------------------------------------------------------------------------ constructed fields
@st.composite
def fields(draw):
    """Gaps Δn in [−3, 20] δn on up to 64 nodes, and the cohesive law's traction T_n(Δn) there."""
    n = draw(st.integers(1, 64))
    s = np.array(draw(st.lists(st.floats(-3.0, 20.0), min_size=n, max_size=n)))
    gap = s * DN
    return gap


def _cohesive_traction(scene, gap):
    return laws.law_from_scene(scene).tractions(gap)[0]


@settings(max_examples=60, deadline=None)
@given(gap=fields(), tol=st.floats(1e-6, 0.3))
def test_compressive_is_inside_traction_tolerance_for_the_cohesive_law(gap, tol):
    tol_scene = _scene(**{"interface.contact_tolerance": tol})
    t = _cohesive_traction(tol_scene, gap)
    seed = laws.law_from_scene(tol_scene).in_contact(gap, t)
    compressive = laws.law_from_scene(_scene(rule="compressive")).in_contact(gap, t)
    assert not np.any(compressive & ~seed)
    np.testing.assert_array_equal(compressive, gap < 0)  # T_n < 0 ⇔ Δn < 0 (Eq. 3)


@settings(max_examples=60, deadline=None)
@given(gap=fields(), tol=st.floats(1e-6, 0.3), law=st.sampled_from(["cohesive", "cohesive-wall"]))
def test_gap_rule_at_delta_tol_is_the_traction_tolerance_rule(gap, tol, law):
    seed_law = laws.law_from_scene(_scene(law, **{"interface.contact_tolerance": tol}))
    delta_tol = laws.contact_gap_threshold(tol, DN)
    assert seed_law.contact_gap == delta_tol
    gap_law = laws.law_from_scene(_scene(law, "gap", **{"interface.contact_gap": delta_tol / DN}))
    t = _cohesive_traction(_scene(), gap)
    same = np.abs(gap - delta_tol) > 4 * np.finfo(float).eps * delta_tol  # Δtol/δn·δn may round by an ulp
    np.testing.assert_array_equal(seed_law.in_contact(gap, t)[same], gap_law.in_contact(gap, t)[same])


@settings(max_examples=60, deadline=None)
@given(gap=fields(), t=st.lists(st.floats(-1e9, 1e9), min_size=64, max_size=64))
def test_hard_wall_traction_tolerance_is_compressive(gap, t):
    t = np.array(t[:gap.size])
    seed = laws.law_from_scene(_scene("hard-wall")).in_contact(gap, t)
    np.testing.assert_array_equal(seed, laws.law_from_scene(_scene("hard-wall", "compressive")).in_contact(gap, t))
    np.testing.assert_array_equal(seed, t < 0)


@settings(max_examples=80, deadline=None)
@given(gap=fields(), law=st.sampled_from(LAWS), rule=st.sampled_from(RULES), tol=st.floats(1e-6, 0.3),
       contact_gap=st.floats(0.01, 15.0), noise=st.floats(-1e8, 1e8))
def test_fe_contact_set_equals_the_law_objects(gap, law, rule, tol, contact_gap, noise):
    """The FE's own contact-set code and `gfmd_contact.core.laws` agree node by node (as tests/test_fem_law.py ties the laws)."""
    extra = {"interface.contact_tolerance": tol} if rule == "traction-tolerance" else {}
    if rule == "gap":
        extra = {"interface.contact_gap": contact_gap}
    scene = _scene(law, rule, **extra)
    t = _cohesive_traction(_scene(), gap) + noise * (law == "hard-wall")
    fe_gap = None if law == "hard-wall" else CohesiveZone.from_scene(scene).contact_gap(scene.interface.contact_tolerance)
    ours = laws.law_from_scene(scene).in_contact(gap, t)
    theirs = contact_set(scene.interface, gap, t, fe_gap)
    if fe_gap is not None and rule == "traction-tolerance":  # two root finders for Δtol: agree to ~1e-15 relative
        same = np.abs(gap - fe_gap) > 1e-12 * fe_gap
        ours, theirs = ours[same], theirs[same]
    np.testing.assert_array_equal(ours, theirs)


def test_rules_count_what_they_say_on_a_hand_field():
    gap = np.array([-0.5, 0.0, 0.5, 1.0, 2.0, 9.0, 9.2, 30.0]) * DN
    t = _cohesive_traction(_scene(), gap)
    count = {r: laws.law_from_scene(_scene(rule=r)).in_contact(gap, t).tolist() for r in RULES}
    assert count["compressive"] == [True] + [False] * 7
    assert count["gap"] == [True, True, True, True, False, False, False, False]  # Δn ≤ 1 δn
    assert count["traction-tolerance"] == [True] * 6 + [False, False]  # Δn ≤ 9.12 δn
    wall = laws.law_from_scene(_scene("hard-wall", "gap", **{"interface.contact_gap": 2.0}))
    assert wall.in_contact(gap, np.zeros_like(gap)).tolist() == [True] * 5 + [False] * 3  # δn of the interface


# ------------------------------------------------------------------------------------------ GFMD solutions
def _sinusoid(law, phi=0.01, thickness="inf", n=256, tol=1e-10, **extra):
    """h = −5 nm cos(2πx/L), L = 1 µm, N nodes; δ0 = 4 nm, δ from −4 nm to 3 nm in 8 steps (contact from step 5)."""
    return default_scene().replace(**{
        "surface.kind": "sinusoid", "surface.amplitude": 5e-9, "surface.nodes": n, "surface.length": 1e-6,
        "surface.realizations": 1, "interface.law": law, "interface.phi_n_star": phi, "loading.steps": 8,
        "loading.final_penetration": 3e-9, "loading.initial_separation": 4e-9, "material.thickness": thickness,
        "solver.tolerance": tol, **extra})


def _ramp(scene):
    """(cell, h, [StepSolution per step]) of a GFMD ramp, every step converged."""
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h)
    state, out = cell.initial_state(), []
    for u in displacement_steps(scene.loading):
        sol = cell.solve(u, state, None)
        assert sol.converged, sol.messages
        state = sol.state
        out.append(sol)
    return cell, h, out


def test_hard_wall_rules_on_a_hard_wall_solution():
    scene = _sinusoid("hard-wall")
    _, h, steps = _ramp(scene)
    last = steps[-1]
    obs = {r: step_observables(scene.replace(**{"interface.contact_rule": r}), h, last.gap, last.t_n)["a_rel"]
           for r in ("traction-tolerance", "compressive")}
    assert obs["traction-tolerance"] == obs["compressive"] > 0.1
    compressed = last.t_n < 0
    for g in (1e-6, 1.0, 5.0):  # every compressed node touches the wall (Δn = 0): inside any gap rule
        law = laws.law_from_scene(scene.replace(**{"interface.contact_rule": "gap", "interface.contact_gap": g}))
        inside = law.in_contact(last.gap, last.t_n)
        assert not np.any(compressed & ~inside)
    # the touching set (Δn ≤ 1e-6 δn) adds at most the two edge nodes on the wall with zero reaction
    touching = laws.law_from_scene(scene.replace(**{"interface.contact_rule": "gap", "interface.contact_gap": 1e-6}))
    assert 0 <= touching.in_contact(last.gap, last.t_n).sum() - compressed.sum() <= 2


@pytest.mark.parametrize("thickness", ["inf", 1e-6])
def test_cohesive_wall_step_is_a_kkt_point(thickness):
    """Δn ≥ 0; t_z = T_n(Δn) off the wall; reaction t_z − T_n ≤ 0 (compressive) on it; K u = t − ⟨t⟩ (half-plane:
    the far field carries the mean) or K u = t (layer) to the solver's tolerance. With the net force r of the
    solver (|r| ≤ tol·p_ref): layer t − Ku = r; half-plane t − ⟨t⟩ − Ku = r − ⟨r⟩, so ≤ 2 tol·p_ref."""
    scene = _sinusoid("cohesive-wall", thickness=thickness)
    cell, h, steps = _ramp(scene)
    physics = cell.physics
    assert physics.law.name == "cohesive wall" and physics.law.constraint
    on_wall_steps = 0
    for displacement, sol in zip(displacement_steps(scene.loading), steps):
        f = sol.fields()
        u, gap, t = f["u_z"], f["gap"], f["t_n"]
        assert np.all(gap >= 0.0)
        # the raw gap of the solver's unknowns: the projection kept it ≥ 0 up to FFT round-off
        z_ind = indenter_surface(h, scene.loading.initial_separation, displacement)
        assert np.min(z_ind - np.fft.irfft(sol.state[-1], n=h.size)) > -1e-12 * np.ptp(h)
        np.testing.assert_allclose(gap, z_ind - u, rtol=0, atol=1e-15 * np.ptp(h))
        attraction = physics.law.tractions(gap)[0]
        wall = gap <= 1e-12 * max(np.ptp(h), DN)
        np.testing.assert_array_equal(t[~wall], attraction[~wall])
        assert np.all(t[wall] - attraction[wall] <= 0.0)  # the wall pushes, never pulls
        assert np.all(attraction >= 0.0)  # Eq. 3 for Δn ≥ 0 is tension only
        ku = np.fft.irfft(physics.k_zz * np.fft.rfft(u), n=u.size)
        balance = t - ku - (np.mean(t) if physics.half_plane else 0.0)
        factor = 2.0 if physics.half_plane else 1.0
        assert np.max(np.abs(balance)) <= factor * scene.solver.tolerance * physics.reference_traction
        on_wall_steps += bool(wall.any())
        if wall.any():
            assert np.any(t[wall] < 0)  # a real contact: the wall carries load
    assert on_wall_steps >= 3


def test_cohesive_wall_equals_the_cohesive_law_out_of_contact():
    """While every gap stays > 0 the two laws are the same equations: the solutions differ by at most the
    solvers' residuals over the smallest stiffness, ‖Δu‖₂ ≤ ‖r₁ − r₂‖₂/λ_min ≤ 2√N tol p_ref/λ_min with
    λ_min = k_min − e⁻²φn/δn² > 0 (no mode can soften to instability on this scene)."""
    cz_cell, h, cz = _ramp(_sinusoid("cohesive", tol=1e-12))
    cw_cell, _, cw = _ramp(_sinusoid("cohesive-wall", tol=1e-12))
    physics = cz_cell.physics
    lam = softest_normal_stiffness(physics) - physics.law.steepest_softening
    assert lam > 0
    bound = 2 * math.sqrt(h.size) * 1e-12 * physics.reference_traction / lam
    free_steps = 0
    for a, b in zip(cz, cw):
        if np.min(b.gap) <= 0 or np.min(a.gap) <= 0:
            continue
        free_steps += 1
        assert np.linalg.norm(a.fields()["u_z"] - b.fields()["u_z"]) <= bound
    assert free_steps >= 4


#: measured (this scene, half-plane, N = 256, tol 1e-10): max over the 9 steps of |u_cw − u_hw| =
#: 5.16e-11, 5.20e-12, 5.21e-13 m at φn* = 1e-3, 1e-4, 1e-5, i.e. ∝ φn* (fitted order 1.00, the linear
#: response of the hard-wall solution to a small attraction); p differs by 9.1e6, 9.1e5, 9.1e4 Pa
PHI_STARS = (1e-3, 1e-4, 1e-5)


def test_cohesive_wall_tends_to_the_hard_wall_as_phi_vanishes():
    """The difference to the hard wall shrinks ∝ φn*: observed order in u and p within 0.05 of 1 (measured
    1.00, see PHI_STARS), and the hard wall's contact set is reached at φn* ≤ 1e-4 (measured: 2 edge nodes
    differ at 1e-3, none below)."""
    _, _, hard = _ramp(_sinusoid("hard-wall"))
    du, dp, dset = [], [], []
    for phi in PHI_STARS:
        _, _, cw = _ramp(_sinusoid("cohesive-wall", phi=phi))
        du.append(max(np.max(np.abs(a.fields()["u_z"] - b.fields()["u_z"])) for a, b in zip(hard, cw)))
        dp.append(max(abs(np.mean(a.t_n) - np.mean(b.t_n)) for a, b in zip(hard, cw)))
        dset.append(max(int(np.sum((a.t_n < 0) != (b.t_n < 0))) for a, b in zip(hard, cw)))
    for d in (du, dp):
        order = np.polyfit(np.log(PHI_STARS), np.log(d), 1)[0]
        assert abs(order - 1.0) < 0.05, (d, order)
    assert dset[1] == dset[2] == 0


# ------------------------------------------------------------------------------------------ scene
@pytest.mark.parametrize("interface, key", [
    ({"contact_rule": "touching"}, "interface.contact_rule"),
    ({"contact_rule": 3}, "interface.contact_rule"),
    ({"contact_rule": "gap", "contact_gap": 0.0}, "interface.contact_gap"),
    ({"contact_rule": "gap", "contact_gap": -1.0}, "interface.contact_gap"),
    ({"contact_rule": "gap", "contact_gap": math.inf}, "interface.contact_gap"),
    ({"contact_rule": "gap", "contact_gap": math.nan}, "interface.contact_gap"),
    ({"contact_rule": "gap", "contact_gap": "1"}, "interface.contact_gap"),
    ({"contact_rule": "gap", "contact_gap": True}, "interface.contact_gap"),
    ({"contact_gap": 1.0}, "interface.contact_gap"),  # a key of rule "gap" under the default rule
    ({"contact_rule": "compressive", "contact_gap": 1.0}, "interface.contact_gap"),
    ({"contact_rule": "gap", "contact_tolerance": 1e-3}, "interface.contact_tolerance"),
    ({"contact_rule": "compressive", "contact_tolerance": 1e-3}, "interface.contact_tolerance"),
    ({"law": "cohesive-wall", "tangential_ratio": 0.5}, "interface.tangential_ratio"),
    ({"law": "cohesive-walls"}, "interface.law"),
])
def test_scene_refuses_naming_the_key(interface, key):
    with pytest.raises(SceneError, match=key.replace(".", r"\.")):
        scene_from_dict({"interface": interface})


def test_coupled_unknowns_refused_for_the_cohesive_wall():
    with pytest.raises(SceneError, match=r"solver\.unknowns"):
        scene_from_dict({"interface": {"law": "cohesive-wall"}, "solver": {"unknowns": "coupled"}})


@pytest.mark.parametrize("law", LAWS)
@pytest.mark.parametrize("rule", RULES)
def test_resolved_scene_round_trip_and_rule_keys(tmp_path, law, rule):
    extra = {"interface.contact_gap": 2.5} if rule == "gap" else {}
    scene = _scene(law, rule, **extra)
    path = tmp_path / "s.toml"
    path.write_text(scene_to_toml(scene))
    again = load_scene(path)
    assert again.interface == scene.interface
    written = set(scene_to_dict(scene)["interface"])
    assert "contact_rule" in written
    assert ("contact_gap" in written) == (rule == "gap")
    assert ("contact_tolerance" in written) == (rule == "traction-tolerance")


def test_defaults_are_the_seeds_choices():
    i = default_scene().interface
    assert i.contact_rule == "traction-tolerance" and i.law == "cohesive"
    assert scene_from_dict({}).interface.contact_rule == "traction-tolerance"


def test_replace_drops_the_old_rules_key():
    gap = default_scene().replace(**{"interface.contact_rule": "gap", "interface.contact_gap": 3.0})
    assert gap.interface.contact_gap == 3.0
    back = gap.replace(**{"interface.contact_rule": "traction-tolerance"})
    assert back.interface.contact_gap == 1.0 and back.interface.contact_rule == "traction-tolerance"
    with pytest.raises(SceneError, match=r"interface\.contact_gap"):
        gap.replace(**{"interface.contact_rule": "compressive", "interface.contact_gap": 2.0})


def test_fe_refuses_the_cohesive_wall():
    from reference.fem.run import refusal, run_realization
    from gfmd_contact.app.methods import method_of
    scene = _sinusoid("cohesive-wall", thickness=1e-6, n=64).replace(**{"method.name": "fe"})
    with pytest.raises(SceneError, match="cohesive-wall"):
        method_of(scene).refuse(scene)
    with pytest.raises(ValueError, match="cohesive-wall"):
        run_realization(scene)
    assert refusal(scene.replace(**{"interface.law": "cohesive"})) is None


def test_cohesive_wall_law_object():
    scene = _scene("cohesive-wall", **{"interface.phi_n_star": 0.01})
    law = laws.law_from_scene(scene)
    cz = laws.law_from_scene(_scene("cohesive", **{"interface.phi_n_star": 0.01}))
    assert law.constraint and law.adhesive and not law.tangential
    assert law.peak_traction == cz.peak_traction and law.contact_gap == cz.contact_gap
    e_star = contact_modulus(scene.material.youngs_modulus, scene.material.poisson_ratio)
    assert law.reference_traction(e_star) == cz.reference_traction(e_star)
    for k in (1e14, 1e16, 1e18):
        assert law.jump_in_separation(k) == cz.jump_in_separation(k)
    gap = np.linspace(-3, 10, 27) * DN
    t = law.tractions(gap)[0]
    np.testing.assert_array_equal(t[gap > 0], cz.tractions(gap[gap > 0])[0])  # Eq. 3 off the wall
    assert np.all(t[gap <= 0] == 0.0)  # no repulsive branch: the wall's reaction replaces it
    assert not law.needs_tangential(scene.material)
    with pytest.raises(ValueError, match="frictionless"):
        laws.law_from_scene(scene, tangential=True)
