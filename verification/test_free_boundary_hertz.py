"""GFMD on a free boundary (`surface.boundary = "free"`, Hockney padding) vs the exact non-periodic solutions.

Studies, scenes and metrics: `verification.studies.free_hertz_cylinder` (1+1-D, force control),
`verification.studies.free_hertz_sphere` (2+1-D, displacement control, the far-field approach δ − s) and
`verification.studies.free_pulloff_2d` (cohesive sphere pull-off vs Maugis–Dugdale at λ = 0.3); their errors and
orders are in verification/data/free_hertz_cylinder.json, free_hertz_sphere.json, free_pulloff_2d.json.

Tolerances (the rules; the numbers are the stored studies'):
* Hertz: finest-N error ≤ stored finest-N error + the stored last successive difference (one N-doubling of
  discretisation error at that level; a re-run differs by round-off only); observed orders ≥ MIN_ORDER: 1.5 where
  2 is expected (the second moment a(P); P(δ) of the sphere), 0.7 where 1 is (the node count a_count, the rms
  pressure of the cylinder: the contact edge cuts the lattice). Stored: cylinder 1.00 / 1.76 / 1.00, sphere
  1.85 / 2.38 / 1.03. No image term: the references are the free (non-periodic) Hertz solutions.
* Pull-off: |e(N_ci) − e_∞| ≤ 2 × the stored successive differences from N_ci on + 4-digit rounding (the rule of
  verification/test_md_pulloff_2d.py); the free law-shape limit e_∞ within twice the periodic study's measured
  image part (its cell check) of the periodic limit at the same λ: removing the images moves e by no more.
* Free vs periodic (small cylinder, periodic cell 8 L of 8 N nodes, same spacing and load): the pressure fields
  differ by no more than the sum of their errors against Hertz (each measured in the test).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reference.analytic import hertz as H
from verification import analytic_cases as ac
from verification import measured
from verification.plots import profile_plot, table_plot
from verification.studies import free_hertz_cylinder as fc
from verification.studies import free_hertz_sphere as fs
from verification.studies import free_pulloff_2d as fp
from verification.studies import md_pulloff_2d as mp

CASES = {fc: ("analytic/free-hertz-cylinder", ("gfmd-free", "analytic-hertz"),
              {"p(x)": 0.7, "a(P)": 1.5, "a_count(P)": 0.7},
              {"p(x)": "rms |p − p_H|/p0 (free Hertz)", "a(P)": "max |a − a_H(P)|/a_H (second moment)",
               "a_count(P)": "max |a_n − a_H|/a_H (node count)"}, "1+1-D, force control, a ≤ L/8"),
         fs: ("analytic/free-hertz-sphere-2d", ("gfmd-free", "analytic-hertz-sphere"),
              {"P(δ)": 1.5, "a(P)": 1.5, "a_count(P)": 0.7},
              {"P(δ)": "max |P − P_H(δ − s)|/P_H (far-field approach)", "a(P)": "max |a − a_H(P)|/a_H (second moment)",
               "a_count(P)": "max |a_n − a_H|/a_H (node count)"}, "2+1-D, displacement control, a ≤ L/8")}


def _bounds(study, subset):
    errors, _ = study.measured_errors(subset)
    return {m: errors[m][-1] + abs(errors[m][-2] - errors[m][-1]) for m in errors}


def _study(study, subset, verification_record, tag):
    case, methods, min_order, labels, notes = CASES[study]
    nodes = np.array(study.NODES[subset])
    st = study.study(nodes)
    ac.print_orders(tag, "N", nodes, st["errors"], st["orders"])
    fields = st["data"][-1][2]
    e = measured.entry(study.NAME, subset)
    plots = [profile_plot(fields["x"], {"GFMD free (nodes)": fields["p"], "Hertz (no images)": fields["ph"]},
                          xlabel="r / a_Hertz", ylabel="p / p0", title=f"pressure at the last load, N = {nodes[-1]}")]
    ac.record_n_study(verification_record, case=case, methods=methods, nodes=nodes, length=study.LENGTH,
                      errors=st["errors"], orders=st["orders"], labels=labels, bounds=_bounds(study, subset),
                      min_order=min_order, wall=st["wall_s"], plots=plots, notes=notes,
                      tolerance_source=(f"verification/data/{study.NAME}.json entry {subset!r} ({e['code_version']}, "
                                        f"{e['date']}): stored finest-N error + its last successive difference"),
                      resolution={"boundary": "free (Hockney padding to 2N)"})


@pytest.mark.parametrize("study", [fc, fs], ids=["cylinder", "sphere"])
def test_free_hertz_convergence(study, verification_record):
    _study(study, "ci", verification_record, "CI")


@pytest.mark.slow
@pytest.mark.parametrize("study", [fc, fs], ids=["cylinder", "sphere"])
def test_free_hertz_convergence_fine(study, verification_record):
    _study(study, "full", verification_record, "slow")


def _pull_off_band(s):
    i = s["nodes"].index(s["ci_nodes"])
    rounding = 0.5 * 10.0 ** (math.floor(math.log10(abs(s["limit"]))) - (measured.SIGNIFICANT_DIGITS - 1))
    return 2.0 * sum(s["differences"][i:]) + rounding


def test_free_sphere_pull_off(verification_record):
    s = fp.stored()
    x = fp.measure(s["ci_nodes"])
    band = _pull_off_band(s)
    periodic = mp.stored(fp.LAMBDA)["limit"]
    cell = measured.entry(mp.NAME, "cell")["values"]
    images = 2.0 * abs(cell["errors"][1] - cell["errors"][0])
    rec = verification_record(
        case=f"analytic/free-maugis-dugdale-sphere-pull-off-2d/lambda-{fp.LAMBDA:g}",
        metric="(P_pull-off − P_MD)/|P_MD| at the CI N − stored Richardson limit", value=float(x["error"] - s["limit"]),
        tolerance=band, methods=("gfmd-free", "analytic-maugis-dugdale-sphere"),
        tolerance_source=("verification/data/free_pulloff_2d.json: 2 × the stored successive differences from the CI "
                          "N on + 4-digit rounding"),
        resolution={"N": s["ci_nodes"], "N_study": s["nodes"], "lambda": fp.LAMBDA, "order": s["order"],
                    "boundary": "free (Hockney padding to 2N)"},
        wall_s=x["wall_s"],
        plots=[table_plot(["N", "P/P_u", "e"], [list(r) for r in zip(s["nodes"], s["P_over_P_u"], s["errors"])],
                          title=f"free pull-off, λ = {fp.LAMBDA:g}; periodic limit e_∞ = {periodic}")],
        notes=(f"e = {x['error']:.5f}, free limit e_∞ = {s['limit']:.5f} (law shape), periodic limit {periodic:.5f}; "
               f"|Δ| ≤ {images:.2e} (twice the periodic cell check's image part)"))
    assert rec.passed, (x["error"], s)
    assert abs(s["limit"] - periodic) <= images, (s["limit"], periodic, images)


def _cylinder_pressure(nodes, length, boundary, load):
    sc = fc.scene(nodes).replace(**{"surface.length": length, "surface.boundary": boundary,
                                    "loading.path": [0.0, load / length]})
    result, _ = ac.run(sc)
    x, p, _, p_mean, _ = ac.step_fields(result, fc.STEPS)
    return x, p, p_mean * length


def test_free_agrees_with_periodic_in_a_large_cell(verification_record):
    """A cylinder of a = L/8 on the free region (N = 128) and alone in a periodic cell 8 L of 8 N nodes."""
    n, factor = 128, 8
    e_star = fc.scene(n).material.contact_modulus
    load = H.load(fc.A_MAX, fc.RADIUS, e_star)
    x, p_free, f_free = _cylinder_pressure(n, fc.LENGTH, "free", load)
    xp, p_per, f_per = _cylinder_pressure(factor * n, factor * fc.LENGTH, "periodic", load)
    tiny = 1e-6 * fc.LENGTH / n
    inside = (xp > x[0] - tiny) & (xp < x[-1] + tiny)
    p_per = p_per[inside]
    assert p_per.shape == p_free.shape and np.allclose(xp[inside], x)
    p0 = float(H.peak_pressure(load, fc.RADIUS, e_star))

    def rms(v):
        return float(np.sqrt(np.mean(v ** 2))) / p0

    diff = rms(p_free - p_per)
    e_free = rms(p_free - H.pressure(x, f_free, fc.RADIUS, e_star))
    e_per = rms(p_per - H.pressure(x, f_per, fc.RADIUS, e_star))
    rec = verification_record(
        case="cross-check/free-vs-periodic-large-cell", metric="rms |p_free − p_periodic|/p0", value=diff,
        tolerance=e_free + e_per, methods=("gfmd-free", "gfmd"),
        tolerance_source="the two runs' own rms pressure errors against Hertz, summed (measured in this test)",
        resolution={"N": n, "periodic_N": factor * n, "periodic_L_over_L": factor, "a_over_L": 1 / 8},
        plots=[profile_plot(x / fc.A_MAX, {"free": p_free / p0, "periodic 8 L": p_per / p0}, xlabel="x / a",
                            ylabel="p / p0", title="free region vs periodic large cell")],
        notes=f"errors against Hertz: free {e_free:.2e}, periodic {e_per:.2e}; loads {f_free:.6g}, {f_per:.6g} N/m")
    assert rec.passed, (diff, e_free, e_per)
