"""The stickiness numbers of `gfmd_contact.core.stickiness` against a second route to the same value (no GFMD run).

* Maugis λ (cylinder): the scenes of `verification.studies.md_pulloff` are built at λ = 0.3, 1, 3, 10 through the
  Maugis–Dugdale reference's own mapping (`reference.analytic.maugis_dugdale`, δn from λ), and the suite
  verifies their GFMD pull-off against Maugis–Dugdale at that λ (verification/test_md_pulloff.py). The number
  `gfmd scene --check` prints for each scene (law's peak traction and work, the scene's R and E*) must be that λ.
* Johnson α (sinusoid): the scene of `verification.studies.jkr_cycle` is built at Johnson's α = 0.3
  (`reference.analytic.jkr_sinusoid`; its cycle is verified against Johnson's); the printed α must be 0.3.
* Persson–Tosatti θ: an energy identity. The same sinusoid given as a measured profile (surface.kind = "file")
  gets θ = U_el/(wL) from the spectrum and the model's kernel (½ Σ k(q)|ĥ_q|²); for a sinusoid Johnson's
  closed form gives U_el/L = πE*h0²/(4λ), i.e. θ = 1/(2πα²) with the α of the sinusoid scene.

Tolerance: round-off of each route (a dozen floating-point operations and one FFT of N points on the other):
(2 log2 N + 12) ε relative; measured ≤ 5 ε. A factor slip in any of the three numbers (e.g. θ without its ½,
verification/mutations.py "persson-tosatti-half") is an O(1) error.
"""

from __future__ import annotations

import math

import numpy as np

from gfmd_contact.core import stickiness, surfaces
from verification.plots import table_plot
from verification.studies import jkr_cycle as jc
from verification.studies import md_pulloff as mp

CASE = "stickiness/numbers-vs-references"
METHODS = ("gfmd-stickiness", "analytic-references")
EPS = np.finfo(float).eps
NODES = 256  # any N: the numbers do not depend on it (the sinusoid's spectrum is exact on every grid)


def _numbers(scene):
    return {d.key: d.value for d in stickiness.diagnostics(scene)}


def _pairs(tmp_path):
    """[(name, printed value, reference value, scene)] of the three stickiness numbers."""
    out = [(f"Maugis λ, md_pulloff scene at λ = {lam:g}", _numbers(mp.scene(NODES, lam))["maugis_lambda"], lam,
            mp.scene(NODES, lam)) for lam in mp.LAMBDAS]
    sinus = jc.scene(NODES, jc.D_REL[0])
    alpha = _numbers(sinus)["johnson_alpha"]
    out.append(("Johnson α, jkr_cycle scene", alpha, jc.ALPHA, sinus))
    path = tmp_path / "sinusoid.npy"
    np.save(path, surfaces.profile(sinus.surface, 0))
    measured = sinus.replace(**{"surface.kind": "file", "surface.path": str(path),
                                "surface.facing": "valleys"})  # the profile's heights as they are
    out.append(("Persson–Tosatti θ, the sinusoid as a file vs 1/(2πα²)", _numbers(measured)["persson_tosatti"],
                1.0 / (2.0 * math.pi * alpha**2), measured))
    return out


def test_stickiness_numbers_equal_their_references(tmp_path, verification_record):
    tol = (2 * math.log2(NODES) + 12) * EPS
    rows, failed = [], []
    pairs = _pairs(tmp_path)
    for name, value, reference, scene in pairs:
        rel = abs(value / reference - 1.0)
        rows.append([name, f"{value:.15g}", f"{reference:.15g}", f"{rel:.3g}"])
        verification_record(
            case=CASE, metric=f"|printed/reference − 1| ({name})", value=rel, tolerance=tol, methods=METHODS,
            tolerance_source="round-off of both routes: (2 log2 N + 12) ε relative", resolution={"N": NODES},
            scene=scene, plots=[table_plot(["number", "printed (stickiness)", "reference route", "relative Δ"], rows,
                                           title="stickiness numbers vs the references' scenes")]
            if len(rows) == len(pairs) else [])
        if rel > tol:
            failed.append(rows[-1])
    assert not failed, failed
