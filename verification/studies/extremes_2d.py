"""Stability at the extremes in 2+1-D (the 1+1-D cells: `verification.studies.extremes`): near full
contact, strong adhesion φn* = 0.15 … 1, small δn, δ0 in the law's range, the refused coupled law.

Base scene: `verification.scenes.extremes_base` made a surface — self-affine (C^iso ∝ |q|^−2(1+H) in seed
Eq. 4's bands), 128 × 128
nodes on L = Ly = 64 nm (l = 0.5 nm, δn = 2 l), H = 0.8, h_rms = 2 nm, λr = 16 nm, λs,H = 2 nm, seed 1, half-space
ν = 0.45, normal-only CZ φn* = 0.15, δn = 1 nm, δ0 = 8 δn, δ from −8 nm to 4 nm in 24 steps, FIRE at 1e-8 p_ref.
Each cell (CELLS) changes a few keys. A cell runs through the one ramp (`gfmd_contact.app.methods.run_realization`) and
is classified as in 1+1-D (`extremes.run_cell`): ok (every step converged, no warning), warn (converged, a scene
check fired), refused (ValueError naming the key), fail (a step did not converge — reported in the result's
messages — or a NaN). Also recorded: the ramp's notes (e.g. the early stop at the full-contact limit), the final
a_rel and p̄, iterations and the largest residual.

    python -m verification.studies.extremes_2d [--write]

`--write` stores every cell in verification/data/extremes_2d.json (entry per cell), which
verification/test_extremes_2d.py compares its re-run with (status, and the checks that must fire).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core.model import warnings_in
from verification import measured
from verification.scenes import extremes_base
from verification.studies.extremes import names_a_key, verdict

NAME = "extremes_2d"
BASE_2D = {"surface.nodes": 128, "surface.nodes_y": 128, "surface.length": 64e-9, "surface.rolloff_wavelength": 16e-9,
           "surface.rollon_wavelength": 2e-9, "surface.h_rms": 2e-9}
DN = 1e-9
_FIELDS = ("u_z", "gap", "t_n")


def _nodes(ratio):
    n = int(round(BASE_2D["surface.length"] / (DN / ratio)))
    return {"surface.nodes": n, "surface.nodes_y": n}


def _deep(final, steps):
    return {"loading.final_penetration": final, "loading.steps": steps}


#: label -> (overrides of the 2-D base, slow)
CELLS = {
    "base (φn* = 0.15, δn = 2 l)": ({}, False),
    "φn* = 0.01": ({"interface.phi_n_star": 0.01}, False),
    "φn* = 1": ({"interface.phi_n_star": 1.0}, False),
    "δn/l = 1": (_nodes(1), False),
    "δn/l = 4": (_nodes(4), False),
    "small δn = 0.25 nm (= l/2), φn* = 0.15": ({"interface.length_normal": 0.25e-9, "loading.initial_separation": 2e-9,
                                               "loading.steps": 48}, False),
    "small δn = 0.1 nm (= l/5), φn* = 0.15": ({"interface.length_normal": 0.1e-9, "loading.initial_separation": 1e-9,
                                              "loading.steps": 50}, False),
    "δ0 = 0": ({"loading.initial_separation": 0.0, "loading.steps": 8}, False),
    "δ0 = 2 δn": ({"loading.initial_separation": 2e-9, "loading.steps": 12}, False),
    "near full contact, CZ φn* = 0.15": (_deep(12e-9, 40), False),
    "near full contact, CZ φn* = 1": ({"interface.phi_n_star": 1.0, **_deep(12e-9, 40)}, False),
    "near full contact, hard wall": ({"interface.law": "hard-wall", "loading.initial_separation": 0.0,
                                      **_deep(12e-9, 48)}, False),
    "coupled law (c = 0.5)": ({"interface.tangential_ratio": 0.5}, False),
}


def scene(overrides):
    return extremes_base(**{**BASE_2D, **overrides})


def run_cell(overrides):
    """One cell through the ramp: status, message and numbers (never raises for a refused scene)."""
    from gfmd_contact.app.methods import run_realization
    t0 = time.perf_counter()
    try:
        sc = scene(overrides)
        result = run_realization(sc)
    except ValueError as exc:  # SceneError, ModelCheckError, full-contact refusal
        return {"status": "refused", "message": f"refused: {exc}", "names_key": names_a_key(str(exc)), "nan": False,
                "reported": True, "residual_ok": True, "steps": 0, "iterations": 0, "residual": float("nan"),
                "notes": [], "a_rel_final": float("nan"), "p_final": float("nan"), "wall_s": time.perf_counter() - t0}
    wall = time.perf_counter() - t0
    c = result.curve
    arrays = [np.asarray(c[k], float) for k in ("p", "a_rel", "residual", "U", "delta")]
    arrays += [np.asarray(f[k], float) for f in result.fields.values() for k in _FIELDS if k in f]
    nan = not all(np.all(np.isfinite(a)) for a in arrays)
    conv = np.asarray(c["converged"], bool)
    residual = np.asarray(c["residual"], float)
    warnings = warnings_in(result.reasons)
    out = {"nan": nan, "steps": int(conv.size), "converged_steps": int(conv.sum()),
           "reported": bool(conv.all() or len(result.messages) >= int((~conv).sum())),
           "residual_ok": bool(np.all(residual[conv] < sc.solver.tolerance)), "iterations": int(np.sum(c["iterations"])),
           "residual": float(np.max(residual)), "notes": [str(n) for n in result.notes],
           "a_rel_final": float(c["a_rel"][-1]), "p_final": float(c["p"][-1]), "wall_s": wall,
           "warnings": warnings, "names_key": True}
    numbers = (f"{conv.sum()}/{conv.size} steps, max residual {out['residual']:.2g} p_ref, {out['iterations']} "
               f"iterations, final a_rel {out['a_rel_final']:.4f}, {wall:.2f} s")
    out.update(verdict(nan, conv, result.messages, warnings, numbers))
    return out


_CACHE = {}


def cell(label):
    if label not in _CACHE:
        _CACHE[label] = run_cell(CELLS[label][0])
    return _CACHE[label]


def stored(label):
    return measured.entry(NAME, label)["values"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the cells in verification/data/extremes_2d.json")
    args = ap.parse_args(argv)
    entries = {}
    for label, (overrides, _) in CELLS.items():
        out = cell(label)
        print(f"{label}: {out['status']}: {out['message'][:200]} notes {out['notes'][:1]}", flush=True)
        keep = ("status", "message", "steps", "iterations", "residual", "a_rel_final", "p_final", "notes", "wall_s")
        entries[label] = measured.make_entry({k: out[k] for k in keep if k in out},
                                             scene="verification.studies.extremes_2d.scene(overrides)",
                                             overrides=overrides)
    if args.write:
        print(measured.write(NAME, entries, description="2+1-D stability cells around a cohesive self-affine surface "
                                                        "(128², φn* = 0.15, δn = 2 l): status, residuals, notes"))


if __name__ == "__main__":
    main()
