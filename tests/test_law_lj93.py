"""The LJ 9-3 wall (`gfmd_contact.core.law_lj93`), the law added through the law protocol alone.

Checked like the other laws: its energy, traction and tangent against each other by central differences (the user
law's consistency check, which fails on a wrong sign or factor: checked on a mutated tangent), its closed-form
scalars against the same quantities derived numerically from its callables (`gfmd_contact.core.user_law`), its
scene keys (errors naming the key, a TOML round trip), a `gfmd run` of a scene.toml through the normal path, and
the Maugis–Dugdale pull-off of a cylinder over λ with the scene and analytic solution of
`verification.studies.md_pulloff` (the study of seed Eq. 3), the law mapped by its w and peak traction.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from gfmd_contact.core import law_protocol, laws
from gfmd_contact.core.errors import SceneError
from gfmd_contact.core.law_lj93 import CORE, X_PEAK, Lj93Wall
from gfmd_contact.core.scene import load_scene, scene_from_dict
from gfmd_contact.core.scene_toml import scene_to_toml
from gfmd_contact.core.user_law import UserLawError, user_law

W, Z0 = 0.05, 0.4e-9  # J/m², m


def _as_user_law(law, tangent=None):
    """The wall's callables as a user law: construction runs the consistency check and derives the scalars."""
    return user_law(law.potential, lambda g: law.tractions(g)[0], tangent or (lambda g: law.tangent(g)[0]),
                    law.range_length, name="LJ 9-3 as callables")


def test_the_wall_answers_the_law_protocol_as_every_built_in_law():
    base = scene_from_dict({})
    built_in = [laws.law_from_scene(base.replace(**{"interface.law": name})) for name in
                ("hard-wall", "cohesive", "cohesive-wall")]
    built_in.append(laws.law_from_scene(base.replace(**{"interface.tangential_ratio": 0.5})))
    for law in built_in + [Lj93Wall(W, Z0), _as_user_law(Lj93Wall(W, Z0))]:
        assert law_protocol.missing(law) == [], type(law).__name__


def test_energy_traction_and_tangent_are_consistent_by_central_differences():
    """T_n = dV/dΔn and dT_n/dΔn = d T_n/dΔn on Δn/z0 ∈ [−1, 12] (inside the core too), within the user law's
    CHECK_RTOL; the same check fails on a tangent off by 1 % or of the wrong sign."""
    law = Lj93Wall(W, Z0)
    _as_user_law(law)  # raises UserLawError where inconsistent
    for wrong in (lambda g: 1.01 * law.tangent(g)[0], lambda g: -law.tangent(g)[0]):
        with pytest.raises(UserLawError, match="tangent"):
            _as_user_law(law, tangent=wrong)


def test_the_closed_forms_match_the_scalars_derived_from_the_callables():
    law = Lj93Wall(W, Z0)
    numeric = _as_user_law(law)
    assert float(law.potential(0.0)) == pytest.approx(-W, rel=1e-14)
    assert float(law.tractions(0.0)[0]) == pytest.approx(0.0, abs=1e-9 * law.peak_traction)
    assert law.initial_stiffness[1] == pytest.approx(float(law.tangent(0.0)[0]), rel=1e-12)
    assert law.peak_traction == pytest.approx(numeric.peak_traction, rel=1e-9)
    assert numeric.peak_gap == pytest.approx(Z0 / X_PEAK - Z0, rel=1e-5)
    # the sample grid's spacing (SAMPLE_REACH/SAMPLE_POINTS lengths) limits the grid-derived ones
    assert law.steepest_softening == pytest.approx(numeric.steepest_softening, rel=1e-4)
    assert law.work_of_adhesion == pytest.approx(numeric.work_normal, rel=1e-3)  # V(50 z0) ≠ 0: the z⁻³ tail
    assert law.contact_gap == pytest.approx(numeric.contact_gap, rel=1e-9)
    for k in (0.1, 0.5, 0.9):
        stiffness = k * law.steepest_softening
        assert law.jump_in_separation(stiffness) == pytest.approx(numeric.jump_in_separation(stiffness), rel=1e-8)
    t = 1e-4 * law.peak_traction
    assert law.far_reach(t) == pytest.approx(numeric.far_reach(t), abs=2 * 50.0 / 5000)
    assert float(law.tractions(law.far_reach(t) * Z0)[0]) == pytest.approx(t, rel=1e-9)
    # the core: finite and repulsive, continuous in V, T_n and the tangent at z = CORE z0
    g = (CORE - 1.0) * Z0 + np.array([-1e-6, 1e-6]) * Z0
    for f in (law.potential, lambda x: law.tractions(x)[0], lambda x: law.tangent(x)[0]):
        a, b = f(g)
        assert a == pytest.approx(b, rel=1e-4)
    deep = law.tractions(np.array([-5.0, -100.0]) * Z0)[0]
    assert np.all(np.isfinite(deep)) and np.all(deep < 0)


LJ_INTERFACE = {"law": "lj93", "work_of_adhesion": W, "range_length": Z0}


@pytest.mark.parametrize("change, key", [
    ({"range_length": None}, "interface.range_length"),
    ({"work_of_adhesion": -0.1}, "interface.work_of_adhesion"),
    ({"work_of_adhesion": 0.0}, "interface.work_of_adhesion"),
    ({"range_length": "1 nm"}, "interface.range_length"),
    ({"range_length": 1e40}, "interface.range_length"),
    ({"tangential_ratio": 0.3}, "interface.tangential_ratio"),
])
def test_scene_keys_are_validated_with_errors_naming_the_key(change, key):
    d = {k: v for k, v in {**LJ_INTERFACE, **change}.items() if v is not None}
    with pytest.raises(SceneError, match=key.replace(".", r"\.")):
        scene_from_dict({"interface": d})


def test_the_walls_keys_belong_to_it_alone_and_coupled_unknowns_are_refused():
    with pytest.raises(SceneError, match="range_length"):
        scene_from_dict({"interface": {"law": "cohesive", "range_length": Z0}})
    with pytest.raises(SceneError, match="solver.unknowns"):
        scene_from_dict({"interface": LJ_INTERFACE, "solver": {"unknowns": "coupled"}})


def test_the_scene_round_trips_through_toml(tmp_path):
    scene = scene_from_dict({"interface": LJ_INTERFACE})
    path = tmp_path / "scene.toml"
    path.write_text(scene_to_toml(scene))
    again = load_scene(path)
    assert again.interface == scene.interface
    assert laws.law_from_scene(again) == Lj93Wall(W, Z0)


def test_gfmd_run_solves_a_sinusoid_with_the_wall_through_the_normal_path(tmp_path):
    """`gfmd run` on a scene.toml: every step converged by the NCG (the chain of a normal law with a potential),
    the wall named in meta.json, tension (p̄ < 0) out of contact and compression at the end."""
    from gfmd_contact.cli import main

    scene = scene_from_dict({"surface": {"kind": "sinusoid", "length": 100e-9, "nodes": 128, "amplitude": 2e-9},
                             "interface": LJ_INTERFACE,
                             "loading": {"initial_separation": 1e-9, "final_penetration": 2e-9, "steps": 12}})
    (tmp_path / "scene.toml").write_text(scene_to_toml(scene))
    main(["run", str(tmp_path / "scene.toml"), "--out", str(tmp_path / "out"), "--no-plot", "--quiet"])
    meta = json.loads((tmp_path / "out" / "meta.json").read_text())
    assert meta["all_converged"] and meta["model"].startswith("LJ 9-3 wall")
    rows = (tmp_path / "out" / "curve.csv").read_text().splitlines()
    head = rows[0].split(",")
    p = [float(r.split(",")[head.index("p")]) for r in rows[1:]]
    algorithms = {r.split(",")[head.index("algorithm")] for r in rows[1:]}
    assert algorithms == {"ncg"}
    assert p[0] < 0 < p[-1]


@pytest.fixture(scope="module")
def pull_off():
    """{λ: [e(N), e(2N)]}: (F_GFMD − F_MD)/|F_MD| of the cylinder of `verification.studies.md_pulloff` with the
    wall mapped to Dugdale by w and σ0 = its peak traction (z0 = 2.7 x_p⁴ w/σ0), at two N per λ."""
    from gfmd_contact.core import cycle as cyc
    from gfmd_contact.core.loading import step_branches
    from reference.analytic import maugis_dugdale as MD
    from verification import analytic_cases as ac
    from verification.scenes import cylinder
    from verification.studies import md_pulloff as mp

    e_star = mp.e_star()
    out = {}
    for lam, nodes in ((0.3, (64, 128)), (1.0, (128, 256)), (3.0, (512, 1024))):
        sigma0 = lam / float(MD.maugis_parameter(1.0, mp.RADIUS, e_star, mp.WORK))
        z0 = 2.7 * X_PEAK**4 * mp.WORK / sigma0
        f_md = MD.pull_off_load(mp.RADIUS, e_star, mp.WORK, sigma0)
        errors = []
        for n in nodes:
            s = cylinder(n, mp.RADIUS, mp.LENGTH, law="lj93", **{"interface.work_of_adhesion": mp.WORK,
                                                                 "interface.range_length": z0})
            s = s.replace(**{"loading.path": list(mp.PATH), "loading.steps": list(mp.STEPS), "output.field_steps": 0})
            assert Lj93Wall(mp.WORK, z0).peak_traction == pytest.approx(sigma0, rel=1e-12)
            result, _ = ac.run(s)
            d, p, a = (np.asarray(result.curve[c], float) for c in ("delta", "p", "a_rel"))
            (row,) = cyc.cycle_observables(d, p, a, *step_branches(s.loading))
            errors.append((row["pull_off_pressure"] * mp.LENGTH - f_md) / abs(f_md))
        out[lam] = errors
    return out


def test_maugis_dugdale_pull_off_law_shape_error_falls_towards_jkr(pull_off):
    """Resolved (e(2N) within a tenth of e of e(N)), the law-shape error of the 9-3 wall against its Dugdale map
    falls as λ grows towards the JKR limit, where the pull-off does not depend on the law (as seed Eq. 3's,
    verification/test_md_pulloff.py)."""
    for lam, (coarse, fine) in pull_off.items():
        assert abs(fine - coarse) < 0.1 * abs(fine), (lam, coarse, fine)
    e = [abs(pull_off[lam][1]) for lam in sorted(pull_off)]
    assert e[0] > e[1] > e[2], pull_off


def test_gfmd_and_the_fe_agree_on_a_cycle_and_converge_together():
    """GFMD and the FE cell (`reference.fem`, which has no LJ 9-3 wall of its own and takes it through the law
    protocol, `reference.fem.law.LawZone`) on the closed load–unload cycle of `verification.studies.fe_cycle`
    (cohesive sinusoid on a bonded layer) with the wall at w = 1 J/m², z0 = 5 nm: both converge at every step and
    max |p̄_FE − p̄_GFMD| / E* falls with N faster than second order (the FE's P2 discretization; measured 3.0e-5,
    4.9e-6, 7.6e-7 at N = 64, 128, 256)."""
    from verification.runs import run_fe_and_gfmd
    from verification.studies import fe_cycle as fc

    differences = []
    for n in (64, 128):
        s = fc.scene(n).replace(**{"interface.law": "lj93", "interface.work_of_adhesion": 1.0,
                                   "interface.range_length": 5e-9})
        fe, gfmd, _, _ = run_fe_and_gfmd(s)
        assert fe.all_converged and gfmd.all_converged, (fe.messages[:3], gfmd.messages[:3])
        assert "law protocol" in fe.model
        p_fe, p_gfmd = (np.asarray(r.curve["p"], float) for r in (fe, gfmd))
        differences.append(float(np.max(np.abs(p_fe - p_gfmd))) / s.material.contact_modulus)
    assert differences[1] < differences[0] / 4, differences


def test_gfmd_and_the_3d_fe_agree_on_an_egg_box_and_converge_together():
    """2+1-D: GFMD and the 3-D FE (`reference.fem3d`, the wall through the law protocol, `reference.fem3d.law.LawZone`)
    on the egg-box of `verification.studies.fem3d_gfmd` with the wall at that study's w = φn and z0 = δn = 2 nm: both
    converge, and max |Δp̄| / max |p̄| falls with N at least as Q1's O(l²) (measured 3.3e-2, 5.0e-3 at N = 16, 32)."""
    from gfmd_contact.app.methods import run_realization
    from verification.studies import fem3d_gfmd as fg

    differences = []
    for n in (16, 32):
        runs = []
        for method in ("gfmd", "fe"):
            s = fg.scene("egg-box", "cohesive", n, method=method)
            s = s.replace(**{"interface.law": "lj93", "interface.work_of_adhesion": s.work_normal,
                             "interface.range_length": 2e-9})
            runs.append(run_realization(s) if method == "gfmd" else fg.run_fe3d(s))
        gfmd, fe = runs
        assert gfmd.all_converged and fe.all_converged and "law protocol" in fe.model
        p_g, p_f = (np.asarray(r.curve["p"], float) for r in runs)
        differences.append(float(np.max(np.abs(p_f - p_g)) / np.max(np.abs(p_g))))
    assert differences[1] < differences[0] / 4, differences
