"""The 1-D sinusoid embedded along y in a non-square 2+1-D cell equals the 1+1-D run (the 2+1-D kernel's y axis).

verification/test_embedded_sinusoid_2d.py embeds the sinusoid along x; its 2+1-D solution has no y modes, so the
kernel's q_y is never exercised there, and the square cells of the other 2+1-D cases cannot tell Lx from Ly.
Here the profile varies along y only: h(x, y) = h_1D(y) on an Lx × Ly = L/4 × L cell of Nx × Ny = 16 × 128 nodes
(Lx ≠ Ly, Nx ≠ Ny, spacings L/64 and L/128), given as a measured surface (surface.kind = "file", the same
samples as the 1+1-D `verification.scenes.sinusoid`, N = 128, L = 1 µm, A = 10 nm). Hard wall, δ 0 → 12 nm in 12
steps (full contact at 9 nm), FIRE at 1e-10 p_ref. Every x column must carry the 1+1-D solution, so curve.csv
agrees with the 1+1-D run per step, within the bounds of the x-embedded case (same derivation):
U, δ exact; p̄ within k_max |Δu| + 2τ p_ref, |Δu| ≤ 2τ p_ref √N / k_min; a_rel within one row per contact edge
(2/Ny). A y wavenumber built from the wrong length (verification/mutations.py "kernel-ly-is-lx") changes p̄ by
O(1).
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core import surfaces
from verification import analytic_cases as ac
from verification.converged_bounds import state_bounds
from verification.plots import curve_plot
from verification.scenes import sinusoid

CASE = "analytic/embedded-sinusoid-2d-along-y"
METHODS = ("gfmd-1+1-D", "gfmd-2+1-D")
NODES, NODES_X = 128, 16
LENGTH, AMPLITUDE = 1e-6, 10e-9
KW = {"law": "hard-wall", "steps": 12, "final": 12e-9, "initial": 0.0}


def _scenes(tmp_path):
    s1 = sinusoid(NODES, AMPLITUDE, LENGTH, **KW)
    h = np.repeat(surfaces.profile(s1.surface, 0)[None, :], NODES_X, axis=0)  # axis 0 x, axis 1 y
    path = tmp_path / "sinusoid_along_y.npy"
    np.save(path, h)
    s2 = s1.replace(**{"surface.kind": "file", "surface.path": str(path), "surface.facing": "valleys",
                       "surface.nodes": NODES_X,
                       "surface.length": LENGTH / 4, "surface.nodes_y": NODES, "surface.length_y": LENGTH})
    return s1, s2


def test_sinusoid_along_y_equals_profile_run(tmp_path, verification_record):
    s1, s2 = _scenes(tmp_path)
    (r1, w1), (r2, w2) = ac.run(s1), ac.run(s2)
    c1 = {c: np.asarray(r1.curve[c], float) for c in ("U", "delta", "p", "a_rel")}
    c2 = {c: np.asarray(r2.curve[c], float) for c in c1}
    assert len(c1["p"]) == len(c2["p"]), (len(c1["p"]), len(c2["p"]))
    _, dp = state_bounds(s2, ac.ANALYTIC_TOLERANCE)
    diffs = {c: float(np.max(np.abs(c1[c] - c2[c]))) for c in c1}
    tol = {"U": 0.0, "delta": 0.0, "p": dp, "a_rel": 2.0 / NODES}
    plot = curve_plot(list(c1["delta"]), {"1+1-D p̄": list(c1["p"]), "2+1-D p̄ (along y)": list(c2["p"])},
                      xlabel="δ (m)", ylabel="p̄ (Pa)", title="the sinusoid along y of an L/4 × L cell vs the profile run")
    failed = []
    for col, value in diffs.items():
        verification_record(
            case=CASE, metric=f"max over steps |Δ {col}| (curve.csv, 2+1-D − 1+1-D)", value=value, tolerance=tol[col],
            methods=METHODS, wall_s=w1 + w2, scene=s2, plots=[plot] if col == "p" else [],
            tolerance_source=("derived: exact for U, δ; converged-state bound (τ = 1e-10, k_min, k_max, √N) for p̄; "
                              "one row per contact edge for a_rel"),
            resolution={"N_x": NODES_X, "N_y": NODES, "L_x/L_y": 0.25, "steps": len(c1["p"]) - 1,
                        "dimension": "2+1-D"},
            notes=f"max |p̄| {np.max(np.abs(c1['p'])):.4g} Pa")
        if value > tol[col]:
            failed.append((col, value, tol[col]))
    assert not failed, failed
