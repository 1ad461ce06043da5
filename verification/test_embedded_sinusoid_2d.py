"""The 1-D sinusoid embedded in 2+1-D equals the 1+1-D run through the whole ramp (one of the
analytic cases; `reference.analytic.embedded_sinusoid`: the 2-D means ARE the 1-D ones).

Scenes: `verification.scenes.sinusoid` (1+1-D, N = 128, L = 1 µm, A = 10 nm, default half-plane) and
`verification.scenes.embedded_sinusoid` (the same with nodes_y = 16, length_y = L/4), each run by the one ramp
(`gfmd.loading.run_realization`, FIRE at 1e-10 p_ref): hard wall, δ 0 → 12 nm in 12 steps (full contact, where the
ramp stops, at 9 nm), and the normal CZ (φn* = 0.15, δn = 2 nm), δ from −4 nm to 10 nm in 20 steps, through the
jump into contact and full contact. Only the scene is shared: the two runs are separate user runs.

curve.csv columns compared per step (the bounds are round-off / solver-tolerance arguments, not fits):
* U, δ: the same path arithmetic ⇒ equal exactly;
* p̄: two converged states of the same problem (max|f| < τ p_ref) differ in traction by at most
  k_max |Δu| + 2τ p_ref, |Δu| ≤ 2τ p_ref √N / k_min (k_min = πE*/L, K ≥ k_min on the clamped half-space;
  tests/test_gfmd_2d.py), N the 2-D node count (the larger bound);
* ḡ, ḡ_r: |Δḡ| ≤ |Δu|; ḡ_r (gradients of h only, over contact nodes) equal up to 4 N ε relative when the same
  nodes are in contact;
* a_rel: at most one column may flip at each of the two contact edges: |Δa_rel| ≤ 2/N.
The measured differences (≈ 5e-14 and 9e-12 of p̄ for hard wall and CZ) are recorded; a y-dependent kernel error
(e.g. |q| built from q_x only, or Ly for Lx) changes p̄ by O(1).
"""

from __future__ import annotations

import numpy as np
import pytest

from gfmd_contact.core.model import build_model
from verification import analytic_cases as ac
from verification.plots import curve_plot
from verification.scenes import embedded_sinusoid, sinusoid

METHODS = ("gfmd-1+1-D", "gfmd-2+1-D")
CASE = "analytic/embedded-sinusoid-2d"
EPS = np.finfo(float).eps
NODES, NODES_Y = 128, 16
LENGTH, AMPLITUDE = 1e-6, 10e-9
CASES = {"hard-wall": dict(law="hard-wall", steps=12, final=12e-9, initial=0.0),
         "cohesive": dict(law="cohesive", steps=20, final=10e-9, initial=4e-9,
                          **{"interface.phi_n_star": 0.15, "interface.length_normal": 2e-9})}


def bounds(scene):
    """(|Δu|_max, |Δt|_max) between two converged states of the scene's 2-D problem (module doc)."""
    m = build_model(scene)
    k_min = np.pi * m.contact_modulus / m.length
    k_max = float(np.max(np.real(m.k_zz)))
    du = 2 * ac.ANALYTIC_TOLERANCE * m.reference_traction * np.sqrt(m.nodes) / k_min
    return du, k_max * du + 2 * ac.ANALYTIC_TOLERANCE * m.reference_traction


@pytest.mark.parametrize("law", CASES)
def test_embedded_sinusoid_equals_profile_run(law, verification_record):
    kw = CASES[law]
    s1 = sinusoid(NODES, AMPLITUDE, LENGTH, **kw)
    s2 = embedded_sinusoid(NODES, AMPLITUDE, LENGTH, NODES_Y, LENGTH / 4, **kw)
    r1, w1 = ac.run(s1)
    r2, w2 = ac.run(s2)
    c1 = {c: np.asarray(r1.curve[c], float) for c in ("U", "delta", "p", "a_rel", "g_r", "g")}
    c2 = {c: np.asarray(r2.curve[c], float) for c in c1}
    assert len(c1["p"]) == len(c2["p"]) == len(r1.curve["step"]), (len(c1["p"]), len(c2["p"]))
    du, dt = bounds(s2)
    same_contact = c1["a_rel"] == c2["a_rel"]
    gr = np.abs(c1["g_r"] - c2["g_r"])[same_contact & np.isfinite(c1["g_r"])]
    diffs = {"U": float(np.max(np.abs(c1["U"] - c2["U"]))), "δ": float(np.max(np.abs(c1["delta"] - c2["delta"]))),
             "p̄": float(np.max(np.abs(c1["p"] - c2["p"]))), "ḡ": float(np.max(np.abs(c1["g"] - c2["g"]))),
             "a_rel": float(np.max(np.abs(c1["a_rel"] - c2["a_rel"]))),
             "ḡ_r": float(np.max(gr / np.abs(c1["g_r"][same_contact & np.isfinite(c1["g_r"])]))) if gr.size else 0.0}
    tol = {"U": 0.0, "δ": 0.0, "p̄": dt, "ḡ": du, "a_rel": 2.0 / NODES, "ḡ_r": 4 * NODES * NODES_Y * EPS}
    plot = curve_plot(list(c1["delta"]), {"1+1-D p̄": list(c1["p"]), "2+1-D p̄ (embedded)": list(c2["p"])},
                      xlabel="δ (m)", ylabel="p̄ (Pa)", title=f"{law}: the embedded sinusoid vs the profile run")
    for col, value in diffs.items():
        rec = verification_record(
            case=f"{CASE}/{law}", metric=f"max over steps |Δ {col}| (curve.csv, 2+1-D − 1+1-D)", value=value,
            tolerance=tol[col], methods=METHODS,
            tolerance_source=("derived: exact for U, δ; converged-state bound (τ = 1e-10, k_min = πE*/L, k_max, √N) "
                              "for p̄ and ḡ; one column per contact edge for a_rel; 4Nε for ḡ_r"),
            resolution={"N": NODES, "N_y": NODES_Y, "L_y/L": 0.25, "steps": len(c1["p"]) - 1, "dimension": "2+1-D"},
            wall_s=w1 + w2, plots=[plot] if col == "p̄" else [],
            notes=(f"iterations 1+1-D {int(np.sum(r1.curve['iterations']))}, 2+1-D {int(np.sum(r2.curve['iterations']))}; "
                   f"max |p̄| {np.max(np.abs(c1['p'])):.4g} Pa"))
        assert value <= tol[col], (law, col, value, tol[col])
