"""GFMD pull-off of a cohesive cylinder on a load–unload cycle vs Maugis–Dugdale over λ (Baney & Hui 1997).

Study, scene, mapping and metric: `verification.studies.md_pulloff` (λ = 0.3, 1, 3, 10; displacement control
along [−1, 2, −0.8, −3] nm; pull-off = the run's own most tensile p̄ on unloading × L; e = (F − F_MD)/|F_MD|).
Its N studies are in verification/data/md_pulloff.json (regenerate: `python -m verification.studies.md_pulloff
--write`).

Asserted per λ, re-running the CI N (the second level of the study's N list, ≈ 20 s in all):
* |e_CI − e_finest,stored| ≤ 2 × Σ stored |e(N) − e(2N)| from the CI N on (the measured discretization error
  there) + half a unit of the stored e's 4th digit + REPRO (machine-to-machine round-off of a FIRE solution at
  1e-10 × p_ref, 1e-6; the study's own N-to-N change at converged N is ≤ 1e-11);
* e > 0 for λ ≤ 3 and e decreasing with λ: the exponential law is less adhesive than its Dugdale map (σ0 = peak
  traction, w = φn) and the law-shape error vanishes towards the JKR limit (reference-formulas §4.2 table).
The law-shape error itself (e_∞ = +10.8%, +7.0%, +0.96%, +0.006% at λ = 0.3, 1, 3, 10) is a property of the
exponential law, not of the resolution: at fixed λ the problem in units ℓ, F_u is fixed, so it does not shrink
as δn → 0; it is checked against the independent exponential-law table of §4.2 in the report.
A 1% change in w moves e by ≈ 0.7% (≥ 20 × every band); a wrong λ mapping by ≫ that.
"""

from __future__ import annotations

import math

import pytest

from verification import measured
from verification.plots import convergence_plot, curve_plot, table_plot
from verification.studies import md_pulloff as mp

METHODS = ("gfmd-fire", "analytic-maugis-dugdale")
CASE = "analytic/maugis-dugdale-cylinder-pull-off"
FACTOR = 2.0
REPRO = 1e-6


def band(lam):
    """(stored finest-N error, tolerance) from verification/data/md_pulloff.json at lam."""
    s = mp.stored(lam)
    i = s["N"].index(s["ci_nodes"])
    disc = sum(s["differences"][i:])
    last = s["errors"][-1]
    rounding = 0.5 * 10.0 ** (math.floor(math.log10(abs(last))) - (measured.SIGNIFICANT_DIGITS - 1))
    return last, FACTOR * disc + rounding + REPRO


@pytest.fixture(scope="module")
def ci_runs():
    return {lam: mp.measure(mp.CI_NODES[lam], lam) for lam in mp.LAMBDAS}


@pytest.mark.parametrize("lam", mp.LAMBDAS)
def test_md_pull_off(lam, ci_runs, verification_record):
    x = ci_runs[lam]
    e = x["error"]
    last, tol = band(lam)
    s = mp.stored(lam)
    e_info = measured.entry(mp.NAME, "ci")
    h = [mp.LENGTH / n for n in s["N"]]
    plots = [
        curve_plot(list(mp.LAMBDAS), {"GFMD (CI N)": [ci_runs[m]["F"] / ci_runs[m]["F_u"] for m in mp.LAMBDAS],
                                      "Maugis–Dugdale": [ci_runs[m]["F_md"] / ci_runs[m]["F_u"] for m in mp.LAMBDAS]},
                   xlabel="Maugis λ (σ0 = φn/(eδn), w = φn)", ylabel="pull-off F / F_u",
                   title="pull-off per unit length vs λ (exponential law vs its Dugdale map)"),
        convergence_plot(h[:-1], [max(d, mp.FLOOR) for d in s["differences"]], order=s["order"],
                         xlabel="node spacing l (m)", ylabel="|e(N) − e(2N)|",
                         title=f"λ = {lam:g}: successive differences (stored study)"),
        table_plot(["N", "F/F_u", "e = (F − F_MD)/|F_MD|"],
                   [[n, f, er] for n, f, er in zip(s["N"], s["F_over_F_u"], s["errors"])],
                   title=f"λ = {lam:g}: MD F/F_u = {s['F_md_over_F_u']}, exponential-law table (§4.2, L = 8R) "
                         f"{s['exponential_table_F_over_F_u']}, L = 1, 2, 8 R: e = {s['cell_errors']}"),
    ]
    rec = verification_record(
        case=f"{CASE}/lambda-{lam:g}", metric="(F_pull-off − F_MD)/|F_MD| at the CI N", value=float(e),
        tolerance=tol, methods=METHODS,
        tolerance_source=(f"verification/data/md_pulloff.json ({e_info['code_version']}, {e_info['date']}): stored "
                          f"e at N = {s['N'][-1]} = {last} ± ({FACTOR:g}× the measured discretization error from "
                          f"N = {s['ci_nodes']} + 4-digit rounding + {REPRO:g})"),
        resolution={"N": mp.CI_NODES[lam], "N_study": s["N"], "lambda": lam, "delta_n_m": mp.delta_n(lam),
                    "observed_order_log2": s["order"], "stored_limit": s["limit"]},
        wall_s=x["wall_s"], plots=plots, passed=bool(abs(e - last) <= tol),
        notes=(f"F/F_u = {x['F'] / x['F_u']:.5f} (MD {x['F_md'] / x['F_u']:.5f}); displacement control, min p̄ on "
               f"unloading (sampling error {x['sampling']:.1e} F_u); law-shape error, not resolution: it does not "
               "vanish as δn → 0 at fixed λ"))
    assert rec.passed, (lam, e, last, tol)


def test_md_pull_off_law_shape_error_falls_with_lambda(ci_runs):
    errors = [ci_runs[lam]["error"] for lam in mp.LAMBDAS]
    assert all(e > 0 for lam, e in zip(mp.LAMBDAS, errors) if lam <= 3.0), errors
    assert all(a > b for a, b in zip(errors, errors[1:])), errors


# ------------------------------------------------------------------ force control (gfmd_contact.core.force)
@pytest.fixture(scope="module")
def force_runs():
    return {lam: mp.measure_force(mp.CI_NODES[lam], lam) for lam in mp.FORCE_LAMBDAS}


@pytest.mark.parametrize("lam", mp.FORCE_LAMBDAS)
def test_force_controlled_pull_off_equals_the_displacement_controlled_minimum(lam, force_runs, ci_runs,
                                                                            verification_record):
    """Baney & Hui (1997): for the line contact the load-controlled pull-off is the extremum dF/da = 0 of
    F(a), the minimum of p̄ L that displacement control passes before it snaps off, so the two agree up to
    the force path's resolution. The detach load F_force is the first load of the fine segment (step Δ) not
    carried: the last load carried is ≥ F_min − tol and F_force = that − Δ < F_min + tol, i.e. F_force ∈
    (F_min − Δ − tol, F_min + tol); the displacement-controlled F_disp is the sampled minimum, F_min ≤ F_disp
    ≤ F_min + sampling. Hence |F_force − F_disp| ≤ Δ + tol + sampling (tol = the outer search's |p̄ − P|),
    and sharper, F_force − tol ≤ F_disp ≤ F_carried + sampling (F_carried: the most tensile p̄ carried)."""
    fx, dx = force_runs[lam], ci_runs[lam]
    f_md = abs(fx["F_md"])
    sampling = dx["sampling"] * dx["F_u"]
    slack = REPRO * f_md  # machine-to-machine round-off of the two FIRE solutions
    bound = (fx["step"] + fx["tolerance"] + sampling) / f_md + REPRO
    diff = (fx["F"] - dx["F"]) / f_md
    s = measured.entry(mp.NAME, "force")
    stored = s["values"][f"lambda={lam:g}"]
    rec = verification_record(
        case=f"{CASE}/force-control/lambda-{lam:g}", metric="(F_force − F_disp)/|F_MD| at the CI N", value=float(diff),
        tolerance=bound, methods=METHODS,
        tolerance_source=(f"derived: (load step Δ = {fx['step'] / f_md:.4g} |F_MD| + search tolerance "
                          f"{fx['tolerance'] / f_md:.2g} |F_MD| + displacement sampling {sampling / f_md:.2g} |F_MD|) + "
                          f"{REPRO:g}; stored study verification/data/md_pulloff.json 'force' ({s['date']})"),
        resolution={"N": mp.CI_NODES[lam], "lambda": lam, "force_path_over_F_md": list(mp.FORCE_PATH),
                    "force_steps": list(mp.FORCE_STEPS)},
        wall_s=fx["wall_s"], passed=bool(abs(diff) <= bound),
        notes=(f"force control: detached at F/F_u = {fx['F'] / fx['F_u']:.5f} (last carried p̄L {fx['F_carried'] / fx['F_u']:.5f}); "
               f"displacement control min p̄L {dx['F'] / dx['F_u']:.5f}; MD {fx['F_md'] / fx['F_u']:.5f}; "
               f"e_force = {fx['error']:.4f}, e_disp = {dx['error']:.5f} (law-shape error, same in both)"))
    assert rec.passed, (lam, diff, bound)
    assert fx["F"] - fx["tolerance"] - slack <= dx["F"] <= fx["F_carried"] + sampling + slack, (fx, dx)
    # the detach load lies on the load grid: the stored study's to its 4 digits
    assert abs(fx["error"] - stored["error_force"]) <= 0.5e-3 * fx["step"] / f_md + REPRO, (fx["error"], stored)
