"""The seed's claims on study tables (gfmd_contact.app.claims, gfmd_contact.app.study_report): each effect size and
verdict on a synthetic study directory (study.json, base_scene.toml, study.csv written here) where the
answer is known — κ of an exact a_rel = κ p_r* with known per-realization scatter, p(δ) that differs
from the hard wall by a known fraction, a_rel that grows by a known amount, ḡ_r/ḡ a known distance
from 1, a verdict that depends on δn — and the HTML report and CLI on it."""

import csv
import json
import math

import numpy as np
import pytest

from gfmd_contact.core.scene import default_scene, scene_to_toml
from gfmd_contact.app import claims as C
from gfmd_contact.cli import main
from gfmd_contact.app.study_report import claims_text, write_report

COLUMNS = C.COLUMNS
STEPS = 23
DELTA = np.linspace(-2e-9, 20e-9, STEPS)


def e_star(params):
    nu = params.get("material.poisson_ratio", 0.45)
    return 70e9 / (1 - nu**2)


def write_study(path, sets, curve, realizations=3):
    """A complete study directory: sets = [params]; curve(i, params, r) → {column: array over the steps}."""
    path.mkdir(parents=True, exist_ok=True)
    keys = list(dict.fromkeys(k for p in sets for k in p))
    axes = {k: list(dict.fromkeys(p[k] for p in sets)) for k in keys}
    tasks = [{"set": i, "parameters": p, "realization": r, "seed": 1 + r, "key": f"t{i}r{r}", "status": "run"}
             for i, p in enumerate(sets) for r in range(realizations)]
    (path / "study.json").write_text(json.dumps({"complete": True, "study": path.name, "axes": axes, "zip": {},
                                                 "tasks": tasks}))
    (path / "base_scene.toml").write_text(scene_to_toml(default_scene()))
    with open(path / "study.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["set"] + keys + ["realization", "seed", "task"] + list(COLUMNS))
        for t in tasks:
            c = curve(t["set"], sets[t["set"]], t["realization"])
            base = {"step": np.arange(STEPS), "U": DELTA + 8e-9, "delta": DELTA, "iterations": np.ones(STEPS),
                    "residual": np.zeros(STEPS), "converged": np.ones(STEPS), "wall_s": np.zeros(STEPS),
                    "g": np.full(STEPS, 0.5)}
            base.update(c)
            for k in range(STEPS):
                w.writerow([t["set"]] + [sets[t["set"]].get(key, "") for key in keys]
                           + [t["realization"], t["seed"], t["key"]] + [repr(float(base[col][k])) for col in COLUMNS])
    return path


def linear_curve(kappas, g_r=0.4):
    """a_rel = κ_r p_r*, p_r* = 0.1 max(δ, 0)/20 nm, ḡ_r constant."""
    def curve(i, params, r):
        x = 0.1 * np.maximum(DELTA, 0) / 20e-9
        return {"p": x * g_r * e_star(params), "a_rel": kappas[i][r] * x, "g_r": np.full(STEPS, g_r)}
    return curve


def by_id(results):
    return {r.id: r for r in results}


def test_kappa_mean_and_standard_error_from_the_realizations(tmp_path):
    kappas = {0: [1.70, 1.74, 1.78]}
    d = C.read_study_dir(write_study(tmp_path / "k", [{"interface.law": "hard-wall"}], linear_curve(kappas)))
    r = by_id(C.evaluate(d))["kappa"]
    m = r.measurements[0]
    assert m.value == pytest.approx(1.74, rel=1e-9)
    assert m.se == pytest.approx(np.std(kappas[0], ddof=1) / math.sqrt(3), rel=1e-6)
    assert m.n == 3 and r.verdict == C.REPRODUCED
    d = C.read_study_dir(write_study(tmp_path / "k2", [{"interface.law": "hard-wall"}],
                                     linear_curve({0: [2.29, 2.30, 2.31]})))
    assert by_id(C.evaluate(d))["kappa"].verdict == C.NOT_REPRODUCED


def test_kappa_independence_of_nu_is_the_relative_range(tmp_path):
    sets = [{"interface.law": "hard-wall", "material.poisson_ratio": nu} for nu in (0.1, 0.45)]
    kappas = {0: [1.75, 1.76, 1.74], 1: [2.10, 2.11, 2.09]}
    d = C.read_study_dir(write_study(tmp_path / "nu", sets, linear_curve(kappas)))
    r = by_id(C.evaluate(d))
    m = r["kappa-nu"].measurements[0]
    assert m.value == pytest.approx(0.35 / 1.925, rel=1e-6)
    assert r["kappa-nu"].verdict == C.NOT_REPRODUCED
    assert r["kappa-H"].verdict == C.NOT_IN_STUDY and r["eps-f"].verdict == C.NOT_IN_STUDY
    same = C.read_study_dir(write_study(tmp_path / "nu2", sets, linear_curve({0: kappas[0], 1: kappas[0]})))
    assert by_id(C.evaluate(same))["kappa-nu"].measurements[0].value == pytest.approx(0, abs=1e-9)
    assert by_id(C.evaluate(same))["kappa-nu"].verdict == C.REPRODUCED


def adhesion_study(tmp_path, name, p_factor, area_gain, gr_ratio, length_normal=None, branch=0.05):
    """Hard wall and φn* = 0.01, 0.15: p(δ) of the cohesive sets = p_factor × the hard wall's, a_rel + area_gain × φn*/0.15,
    ḡ_r/ḡ = gr_ratio for the cohesive sets; tensile steps (p < 0 before contact) with a_rel = branch."""
    sets = [{"interface.law": "hard-wall", "interface.phi_n_star": 0.15},
            {"interface.law": "cohesive", "interface.phi_n_star": 0.01},
            {"interface.law": "cohesive", "interface.phi_n_star": 0.15}]
    if length_normal is not None:
        sets = [{**s, "interface.length_normal": dn} for dn in length_normal for s in sets]

    def curve(i, params, r):
        es = e_star(params)
        pe = 0.02 * np.maximum(DELTA, 0) / 20e-9 * (1 + 0.05 * r)
        a = 0.1 * np.maximum(DELTA, 0) / 20e-9 * (1 + 0.05 * r)
        g = 0.5
        if params["interface.law"] == "hard-wall":
            return {"p": pe * es, "a_rel": a, "g_r": np.where(a > 0, 0.8, np.nan)}
        f = p_factor(params) if callable(p_factor) else p_factor
        p = f * pe * es
        p[DELTA < 0] = -1e-4 * es
        aa = a + area_gain * params["interface.phi_n_star"] / 0.15
        aa[DELTA < 0] = branch
        return {"p": p, "a_rel": aa, "g_r": np.full(STEPS, gr_ratio * g)}
    return C.read_study_dir(write_study(tmp_path / name, sets, curve))


def test_fig4_claims_on_known_differences(tmp_path):
    r = by_id(C.evaluate(adhesion_study(tmp_path, "a", p_factor=0.8, area_gain=0.2, gr_ratio=1.03)))
    p = r["pressure-delta"].measurements[0]
    assert p.value == pytest.approx(0.2, rel=1e-6)  # |0.8 − 1| of the hard wall's p/E* at δ = 20 nm
    assert r["pressure-delta"].verdict == C.NOT_REPRODUCED
    a = r["area-delta"].measurements[0]
    assert a.value == pytest.approx(0.2, rel=1e-6) and a.se == pytest.approx(0, abs=1e-12)  # paired: exact
    assert r["area-delta"].verdict == C.REPRODUCED
    g = r["gr-over-g"].measurements[0]
    assert g.value == pytest.approx(0.03, rel=1e-6) and r["gr-over-g"].verdict == C.REPRODUCED
    b = r["adhesive-branch"].measurements[0]
    assert b.value == pytest.approx(0.05) and r["adhesive-branch"].verdict == C.REPRODUCED
    r = by_id(C.evaluate(adhesion_study(tmp_path, "b", p_factor=1.0, area_gain=0.0, gr_ratio=1.5, branch=0.0)))
    assert r["pressure-delta"].measurements[0].value == pytest.approx(0, abs=1e-9)
    assert r["pressure-delta"].verdict == C.REPRODUCED
    assert r["area-delta"].verdict != C.REPRODUCED
    assert r["gr-over-g"].verdict == C.NOT_REPRODUCED
    assert r["adhesive-branch"].verdict == C.NOT_REPRODUCED


def test_a_verdict_that_differs_between_delta_n_values_depends_on_delta_n(tmp_path):
    d = adhesion_study(tmp_path, "dn", p_factor=lambda p: 0.5 if p["interface.length_normal"] > 5e-10 else 1.0,
                       area_gain=0.2, gr_ratio=1.0, length_normal=(0.25e-9, 1e-9))
    r = by_id(C.evaluate(d))
    assert r["pressure-delta"].verdict == C.DEPENDS
    assert sorted(m.context for m in r["pressure-delta"].measurements) == ["δn = 0.25 nm", "δn = 1 nm"]
    assert {m.verdict for m in r["pressure-delta"].measurements} == {C.REPRODUCED, C.NOT_REPRODUCED}
    assert r["area-delta"].verdict == C.REPRODUCED  # the same at both δn


def test_statistics_helpers():
    m, se, n = C.stats({0: 1.0, 1: 2.0, 2: 3.0})
    assert (m, n) == (2.0, 3) and se == pytest.approx(1 / math.sqrt(3))
    assert C.stats([4.0]) == (4.0, 0.0, 1)
    m, se, n = C.difference({0: 1.0, 1: 2.0}, {0: 0.5, 1: 1.5})
    assert (m, se, n) == (0.5, 0.0, 2)
    assert C.at_level([0, 1, 2, 3], [0, 10, 20, 30], 1.5) == pytest.approx(15)
    assert math.isnan(C.at_level([0, 1], [0, 1], 5))
    assert C.verdict_below(0.05, 0.01, 0.1) == C.REPRODUCED
    assert C.verdict_below(0.09, 0.01, 0.1) == C.INCONCLUSIVE
    assert C.verdict_positive(-0.1, 0.01) == C.NOT_REPRODUCED


def test_report_html_and_cli(tmp_path, capsys):
    d = adhesion_study(tmp_path, "rep", p_factor=0.8, area_gain=0.2, gr_ratio=1.03)
    d2 = C.read_study_dir(write_study(tmp_path / "k", [{"interface.law": "hard-wall"}],
                                      linear_curve({0: [1.70, 1.74, 1.78]})))
    path = write_report([d.path, d2.path], figures=False)
    page = path.read_text()
    assert path == d.path / "report.html"
    for text in ("Fig. 2", "Fig. 4a", "not in this study", "Effect sizes and verdicts: definitions",
                 "1.74 ± 0.023", C.NOT_REPRODUCED):
        assert text in page, text
    lines = claims_text([d.path, d2.path])
    assert any("kappa" in x and "k " in x + " " and "reproduced" in x for x in lines)
    assert main(["study", "report", str(d2.path)]) == 0
    out = capsys.readouterr()
    assert "data:image/png;base64," in (d2.path / "report.html").read_text()
    assert "kappa" in out.out
    assert main(["study", "report", str(tmp_path)]) == 2
    assert "not a study directory" in capsys.readouterr().err


def test_what_is_no_study_raises_the_error_claims_exports(tmp_path):
    """claims.StudyDirError (named in study_report's docstring) is the error read_study_dir raises."""
    with pytest.raises(C.StudyDirError, match="not a study directory"):
        C.read_study_dir(tmp_path)
