"""GFMD load–unload cycle of the cohesive sinusoid vs Johnson's (1995) JKR-wavy solution (reference-formulas
§4.3) under displacement control: branches, snap-in, snap-off, pull-off and hysteresis, errors vs δn.

Scene: that of `verification.studies.jkr_sinusoid` (h = −h0 cos(2πx/λ), h0 = 10 nm, λ = L = 1 µm, half-plane
E = 70 GPa, ν = 0.45, exponential CZ law with φn = w fixed at Johnson's α = 0.3; δn lowered at fixed w so
that the cohesive-zone length d/λ = 0.04 … 0.005), loaded along `loading.path` = [−0.6 h0, 0.6 h0, −0.6 h0]
with 120 steps out and 480 back (Δδ = 0.01 h0 loading, 0.0025 h0 unloading).

Analytic cycle (this module's own code from `reference.analytic.jkr_sinusoid`): the indenter's mean height
above the mean plane is h0 − δ (gfmd_contact.core.conventions; ⟨h⟩ − min h = h0), so on a half-plane the mean gap is
ḡ = h0 − δ and the attached branch is δ(a) = h0 − ḡ(a), p̄(a). Loading: no contact (p̄ = 0) up to δ = 0
(ḡ(0⁺) = h0), there a jump into the branch at the a_in > a_off with ḡ(a_in) = h0; unloading follows the
branch down to the maximum of ḡ(a) at a_off (δ_off = h0 − ḡ(a_off)), where contact snaps off. Pull-off
(most tensile p̄ on unloading) = min p̄(a) over a ∈ [a_off, a_max]; hysteresis W = ∮ p̄ dδ =
∫_{a_off}^{a_in} p̄(a) ḡ'(a) da > 0 (the area between the branches, J/m²).

Force control (`gfmd_contact.core.force`, loads `FORCE_PATH` × p*): the pull-off load, the midpoint between the last
load carried and the first that detached the body (±ΔP/2 = 2.5e-4 p*), against min p̄(a) (Johnson's
load-controlled pull-off).

GFMD numbers: the run's own `gfmd_contact.core.cycle` observables from its curve (pull-off, snap-off δ from the
jump-out, jump-in δ from the jump-in, W by the trapezoid rule) and the branch error max |p̄ − p̄_J(δ)|/p*
over the attached steps with δ ≥ δ_off (loading after the jump-in, unloading before the snap-off).
Errors are scaled by p* (pressures), h0 (δ) and W_J (hysteresis); rate = least-squares slope of log error vs
log δn.

    python -m verification.studies.jkr_cycle [--write]

`--write` stores the errors in verification/data/jkr_cycle.json (entry "ci", N = 2048), which
verification/test_jkr_cycle.py reads.
"""

from __future__ import annotations

import argparse
import functools

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq, minimize_scalar

from gfmd_contact.core import cycle as cyc
from gfmd_contact.core.loading import step_branches
from reference.analytic import jkr_sinusoid as J
from reference.analytic import westergaard as W
from verification import analytic_cases as ac
from verification import measured
from verification.scenes import sinusoid
from verification.studies import jkr_sinusoid as js

NAME = "jkr_cycle"
H0, LENGTH, ALPHA = js.H0, js.LENGTH, js.ALPHA
START, TOP = -0.6 * H0, 0.6 * H0
STEPS = (120, 480)
D_REL = (0.04, 0.02, 0.01, 0.005)
NODES = {"ci": 2048}
METRICS = ("pull-off", "snap-off δ", "jump-in δ", "hysteresis", "loading branch", "unloading branch",
           "pull-off (force control)")
#: force control (gfmd_contact.core.force): loads 0 → 0.2 p* → −0.085 p* → −0.105 p* in 4, 8 and 40 steps (ΔP = 5e-4 p*
#: near pull-off); the pull-off load is the midpoint of the last load carried and the first that detached
FORCE_PATH, FORCE_STEPS = (0.0, 0.2, -0.085, -0.105), (4, 8, 40)


def _g(a):
    return J.mean_gap(a, H0, LENGTH, js.e_star(), js.work())


def _p(a):
    return J.mean_pressure(a, H0, LENGTH, js.e_star(), js.work())


def _delta(a, compliance=0.0):
    """Indenter displacement δ (m) on the attached branch at half-width a: h0 − ḡ(a) + C p̄(a), C the
    mean-mode compliance of the body (0 for the half-plane: its mean displacement is clamped)."""
    return H0 - _g(a) + compliance * _p(a)


@functools.cache
def analytic(compliance=0.0):
    """Johnson's displacement-controlled cycle: {a_off, delta_off, a_in, pull_off, hysteresis, p_star} (SI).

    compliance: C (m/Pa), the mean displacement per mean pressure of the body (a layer's uniaxial strain,
    `layer_compliance`), in series with Johnson's half-plane response of the non-mean modes: δ(a) =
    h0 − ḡ(a) + C p̄(a); snap-off at the minimum of δ(a), jump-in where δ(a) = 0 (the first touch is at
    δ = 0 with p̄ = 0), W = −∫_{a_off}^{a_in} p̄(a) δ'(a) da."""
    r = minimize_scalar(lambda a: _delta(a, compliance), bounds=(1e-6 * LENGTH, 0.3 * LENGTH), method="bounded",
                        options={"xatol": 1e-15})
    a_off = float(r.x)
    a_in = brentq(lambda a: _delta(a, compliance), a_off, _branch_end(a_off, compliance, 0.49), xtol=1e-16)
    a_max = branch_half_width(TOP, a_off, compliance)
    po = minimize_scalar(_p, bounds=(a_off, a_max), method="bounded", options={"xatol": 1e-15})
    eps = 1e-7 * LENGTH
    w = quad(lambda a: -_p(a) * (_delta(a + eps, compliance) - _delta(a - eps, compliance)) / (2 * eps),
             a_off, a_in, limit=200)[0]
    return {"a_off": a_off, "delta_off": _delta(a_off, compliance), "a_in": a_in, "pull_off": float(po.fun),
            "hysteresis": w, "p_star": W.full_contact_pressure(H0, LENGTH, js.e_star())}


def layer_compliance(material):
    """C = D (1 + ν)(1 − 2ν) / (E (1 − ν)) (m/Pa): the mean surface displacement per mean pressure of a
    bonded periodic layer of depth D (uniaxial strain, plane strain); a scene's `material`."""
    nu = material.poisson_ratio
    return material.thickness * (1 + nu) * (1 - 2 * nu) / (material.youngs_modulus * (1 - nu))


def branch_half_width(delta, a_off, compliance=0.0):
    """a on the attached branch (a > a_off) with δ(a) = δ (m)."""
    return brentq(lambda a: _delta(a, compliance) - delta, a_off, _branch_end(a_off, compliance, 0.4999), xtol=1e-16)


@functools.cache
def _branch_end(a_off, compliance, fraction):
    """Upper bracket of the attached branch: `fraction`·λ for the half-plane; with a compliance C > 0 the a
    of the largest δ(a) below 0.49 λ (δ(a) rises from a_off to there; Johnson's p̄(a) falls near full
    contact, where C p̄ would bend δ back)."""
    if compliance == 0.0:
        return fraction * LENGTH
    r = minimize_scalar(lambda a: -_delta(a, compliance), bounds=(a_off, 0.49 * LENGTH), method="bounded",
                        options={"xatol": 1e-15})
    return float(r.x)


def scene(nodes, d_rel):
    s = sinusoid(nodes, H0, LENGTH, law="cohesive", **{
        "interface.work_normal": js.work(), "interface.length_normal": js.delta_n(d_rel)})
    return s.replace(**{"loading.path": [START, TOP, START], "loading.steps": list(STEPS), "output.field_steps": 0})


def measure(nodes, d_rel):
    """(errors {metric}, numbers {GFMD observables}, curve (δ/h0, p̄/p*, branch), δn, wall s)."""
    s = scene(nodes, d_rel)
    result, wall = ac.run(s)
    errors, numbers, curve = cycle_errors(result, s, d_rel)
    p_off, half, wall_f = force_pull_off(nodes, d_rel)
    ref, ps = analytic(), analytic()["p_star"]
    errors["pull-off (force control)"] = abs(p_off - ref["pull_off"]) / ps
    numbers["force_pull_off_over_p_star"], numbers["force_pull_off_half_width"] = p_off / ps, half / ps
    return errors, numbers, curve, js.delta_n(d_rel), wall + wall_f


def cycle_errors(result, s, d_rel, compliance=0.0):
    """(errors {the displacement-controlled metrics}, numbers, curve (δ/h0, p̄/p*, branch)) of one method's
    run of `scene`-like `s` against Johnson's cycle (with the body's mean compliance C, `analytic`), from the
    run's own curve and `gfmd_contact.core.cycle`. The jump-in error is |δ_jump-in − 0| / h0."""
    ref = analytic(compliance)
    d, p, a = (np.asarray(result.curve[c], float) for c in ("delta", "p", "a_rel"))
    branch, cycle = step_branches(s.loading)
    (row,) = cyc.cycle_observables(d, p, a, branch, cycle)
    ins = [e for e in row["events"] if e["kind"] == "jump-in" and e["branch"] == "loading"]
    outs = [e for e in row["events"] if e["kind"] == "jump-out" and e["branch"] == "unloading"]
    if len(ins) != 1 or len(outs) != 1:
        raise AssertionError(f"d/λ = {d_rel}: expected one jump-in and one jump-out, got {row['events']}")
    k_in, k_out = ins[0]["step"], outs[0]["step"]
    ps = ref["p_star"]
    branch_err = {}
    top = s.loading.segment_steps[0]
    for name, steps in (("loading branch", range(k_in, top + 1)), ("unloading branch", range(top, k_out))):
        errs = [abs(p[k] - _p(branch_half_width(d[k], ref["a_off"], compliance))) / ps for k in steps if d[k] >= ref["delta_off"]]
        branch_err[name] = max(errs)
    numbers = {"pull_off_over_p_star": row["pull_off_pressure"] / ps, "snap_off_delta_over_h0": row["snap_off_delta"] / H0,
               "jump_in_delta_over_h0": ins[0]["delta_after"] / H0, "hysteresis_J_per_m2": row["hysteresis"]}
    errors = {"pull-off": abs(row["pull_off_pressure"] - ref["pull_off"]) / ps,
              "snap-off δ": abs(row["snap_off_delta"] - ref["delta_off"]) / H0,
              "jump-in δ": abs(ins[0]["delta_after"]) / H0,
              "hysteresis": abs(row["hysteresis"] - ref["hysteresis"]) / ref["hysteresis"], **branch_err}
    return errors, numbers, (list(d / H0), list(p / ps), list(branch))


def force_pull_off(nodes, d_rel):
    """(pull-off load (Pa) under force control: midpoint of the last load carried and the first that detached,
    its half-width (Pa), wall s)."""
    ps = analytic()["p_star"]
    s = scene(nodes, d_rel).replace(**{"loading.control": "force", "loading.initial_separation": -START,
                                       "loading.path": [v * ps for v in FORCE_PATH], "loading.steps": list(FORCE_STEPS)})
    result, wall = ac.run(s)
    (out,) = [e for e in result.diagnostics.get("instabilities", []) if e.get("detached")]
    carried = float(result.curve["p"][out["step"] - 1])
    return 0.5 * (carried + out["load"]), 0.5 * abs(carried - out["load"]), wall


def study(nodes):
    data, errors, wall = ac.convergence_study(lambda dr: measure(nodes, dr), D_REL, METRICS)
    dns = np.array([x[3] for x in data])
    return {"nodes": int(nodes), "d_rel": list(D_REL), "delta_n": dns, "data": data, "errors": errors,
            "rates": ac.orders_in(dns, errors), "wall_s": wall}


def reference_numbers():
    ref = analytic()
    return {"pull_off_over_p_star": ref["pull_off"] / ref["p_star"], "snap_off_delta_over_h0": ref["delta_off"] / H0,
            "jump_in_delta_over_h0": 0.0, "hysteresis_J_per_m2": ref["hysteresis"],
            "a_off_over_lambda": ref["a_off"] / LENGTH, "a_in_over_lambda": ref["a_in"] / LENGTH}


def entry(st, subset):
    return measured.make_entry({"N": st["nodes"], "d_over_lambda": st["d_rel"], "delta_n_m": list(st["delta_n"]),
                                "errors": {m: list(e) for m, e in st["errors"].items()}, "rates": st["rates"],
                                "gfmd": [x[1] for x in st["data"]], "johnson": reference_numbers()},
                               scene=(f"verification.studies.jkr_cycle.scene({st['nodes']}, d/λ): sinusoid h0 = 10 nm, "
                                      f"λ = 1 µm, α = {ALPHA}, path [−0.6 h0, 0.6 h0, −0.6 h0], steps {list(STEPS)}"),
                               subset=subset, wall_s=st["wall_s"])


def measured_errors(subset="ci"):
    values = measured.entry(NAME, subset)["values"]
    return values["errors"], values["d_over_lambda"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the errors in verification/data/jkr_cycle.json")
    args = ap.parse_args(argv)
    st = study(NODES["ci"])
    ac.print_orders("ci", "δn", st["delta_n"], st["errors"], st["rates"])
    print("Johnson:", reference_numbers())
    for dr, x in zip(D_REL, st["data"]):
        print(f"d/λ = {dr}: GFMD {x[1]} ({x[4]:.1f} s)")
    print(f"{st['wall_s']:.1f} s")
    if args.write:
        print(measured.write(NAME, {"ci": entry(st, "ci")},
                             description="GFMD cohesive sinusoid load–unload cycle vs Johnson JKR-wavy under displacement "
                                         "control: errors of pull-off, snap-off, jump-in, hysteresis and both branches vs δn "
                                         "at fixed α = 0.3 (d/λ = 0.04 … 0.005), rates vs δn (least squares)"))


if __name__ == "__main__":
    main()
