"""Same iterates bit for bit: record every GFMD step of short ramps, or compare two recordings.

Usage:
    python benchmarks/iterates_equal.py record DIR      # one .npz per case into DIR
    python benchmarks/iterates_equal.py compare BASE NEW  # np.array_equal on every array

Every law (hard wall, normal cohesive, cohesive wall, coupled) on both bodies (half-plane and a
finite layer D = L/4), each with the integrators and fallbacks `gfmd.chains.relax` can run: the
hard wall's dual CGs and their hand-over to the primal CG, FIRE and Verlet; the cohesive
NCG, its FIRE fallback (a budget of 3 NCG iterations), FIRE and Verlet; the cohesive wall's FIRE
and Verlet; the coupled law's FIRE, its Newton–Krylov fallback (a budget of 20 FIRE iterations)
and Verlet, with the Newton–Krylov stage failing (0 iterations) or its states rejected as not locally
stable (the stability test patched to say so), both ending in Verlet (a FIRE budget of 20), and the
coupled chains "frictionless-first" and FIRE alone (Settings.coupled = "fire"). Each
case runs the load ramp of `gfmd.loading.run_realization` (N = 512, 6 steps of 1 nm, 5 nm for the
hard wall) and records every call of `gfmd.loading.relax` (retries included): the state u_hat,
the fields, iterations, residual, converged and FFT pairs, and the curve.
The algorithm labels (`Relaxed.method`) are compared as text and reported, not required equal
(the refactor of issue 22 names the algorithm where it used to leave the label empty).
Wall times are never compared. `compare` compares the cases both recordings hold and names the others
(a case of a chain added or removed since the base was recorded). Set GFMD_FFT and GFMD_JIT alike for both recordings.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import gfmd.loading as gl  # noqa: E402
from gfmd_contact.core.scene import default_scene  # noqa: E402
from gfmd.solver import Settings  # noqa: E402

NODES = 512
LENGTH = 1.28e-6
LAYER = LENGTH / 4
SCALARS = ("iterations", "residual", "converged", "fft_pairs")
ARRAYS = ("u_hat", "u_z", "u_x", "gap", "t_z", "t_x")


def scene(law, thickness, **extra):
    deep = law == "hard-wall"  # 5 nm steps: the contact set grows past the dual CG's limits
    kw = {"surface.nodes": NODES, "surface.length": LENGTH, "surface.rolloff_wavelength": LENGTH / 8,
          "surface.rollon_wavelength": 4 * LENGTH / NODES, "surface.realizations": 1, "interface.law": law,
          "interface.length_normal": 0.5e-9, "loading.final_penetration": 30e-9 if deep else 6e-9, "loading.steps": 6,
          "output.field_steps": 1, **extra}
    if thickness is not None:
        kw["material.thickness"] = thickness
    return default_scene().replace(**kw)


COUPLED = {"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3, "interface.phi_n_star": 0.05}
#: name: (law, scene extras, Settings keywords)
CASES = {
    "hard-wall-dual": ("hard-wall", {}, {}),
    "hard-wall-dual-handover": ("hard-wall", {}, {"dual_contact_limit": 0.02}),
    "hard-wall-dual-primal": ("hard-wall", {}, {"dual_contact_limit": 0.002}),
    "hard-wall-band": ("hard-wall", {}, {"dual_coarse_block": 0}),
    "hard-wall-band-handover": ("hard-wall", {}, {"dual_coarse_block": 0, "dual_contact_limit": 0.02}),
    "hard-wall-fire": ("hard-wall", {}, {"hard_wall": "fire"}),
    "hard-wall-verlet": ("hard-wall", {}, {"method": "verlet"}),
    "cohesive-ncg": ("cohesive", {}, {}),
    "cohesive-ncg-fallback": ("cohesive", {}, {"max_iterations": 3000, "_patch": {"NCG_BUDGET": 3}}),
    "cohesive-fire": ("cohesive", {}, {"cohesive": "fire"}),
    "cohesive-verlet": ("cohesive", {}, {"method": "verlet"}),
    "cohesive-wall-fire": ("cohesive-wall", {}, {}),
    "cohesive-wall-verlet": ("cohesive-wall", {}, {"method": "verlet"}),
    "coupled-fire": ("cohesive", COUPLED, {}),
    "coupled-newton": ("cohesive", COUPLED, {"max_iterations": 40}),
    "coupled-newton-fails": ("cohesive", COUPLED, {"_patch": {"COUPLED_FIRE_BUDGET": 20,
                                                              "COUPLED_NEWTON_ITERATIONS": 0}}),
    "coupled-newton-rejected": ("cohesive", COUPLED, {"_patch": {"COUPLED_FIRE_BUDGET": 20,
                                                                 "coupled_stability": lambda *a: -1.0}}),
    "coupled-verlet": ("cohesive", COUPLED, {"method": "verlet"}),
    "coupled-frictionless-first": ("cohesive", COUPLED, {"coupled": "frictionless-first"}),
    "coupled-fire-only": ("cohesive", COUPLED, {"coupled": "fire"}),
}
BODIES = {"half-plane": None, "layer": LAYER}


#: module-level names a case patches: before issue 22 in gfmd.solver, after it in the module that owns them
PATCHABLE = {"NCG_BUDGET": ("gfmd.algorithms.ncg", "gfmd.solver"),
             "COUPLED_NEWTON_ITERATIONS": ("gfmd.algorithms.coupled_newton", "gfmd.solver"),
             "COUPLED_FIRE_BUDGET": ("gfmd.chains", "gfmd.solver"),
             "coupled_stability": ("gfmd.chains", "gfmd.solver:_coupled_stability")}


def _patch(name, value):
    """Set the module attribute `name` wherever this version of the code keeps it; returns an undo."""
    import importlib
    for where in PATCHABLE[name]:
        module_name, _, attr = where.partition(":")
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue
        attr = attr or name
        if hasattr(module, attr):
            old = getattr(module, attr)
            setattr(module, attr, value)
            return lambda: setattr(module, attr, old)
    raise RuntimeError(f"{name} not found")


def run_case(law, extra, keywords, thickness):
    sc = scene(law, thickness, **extra)
    keywords = dict(keywords)
    patches = keywords.pop("_patch", {})
    settings = Settings(**{"tolerance": sc.solver.tolerance, "max_iterations": sc.solver.max_iterations,
                           **keywords})
    calls = []
    original = gl.relax

    def recording(*args, **kwargs):
        r = original(*args, **kwargs)
        calls.append(r)
        return r

    gl.relax = recording
    undo = [_patch(name, value) for name, value in patches.items()]
    try:
        result = gl.run_realization(sc, 0, settings=settings)
    finally:
        gl.relax = original
        for u in undo:
            u()
    out = {}
    for i, r in enumerate(calls):
        for a in ARRAYS:
            out[f"{i}/{a}"] = np.asarray(getattr(r, a))
        for s in SCALARS:
            out[f"{i}/{s}"] = np.asarray(getattr(r, s))
        out[f"{i}/method"] = np.asarray(r.method)
    for c, v in result.curve.items():
        if c != "wall_s":
            out[f"curve/{c}"] = np.asarray(v)
    return out


def record(folder):
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    for body, thickness in BODIES.items():
        for name, (law, extra, keywords) in CASES.items():
            out = run_case(law, extra, keywords, thickness)
            calls = len({k.split("/")[0] for k in out if not k.startswith("curve/")})
            methods = sorted({str(out[k]) for k in out if k.endswith("/method")})
            np.savez(folder / f"{body}__{name}.npz", **out)
            its = int(np.sum(out["curve/iterations"]))
            print(f"{body:10s} {name:26s} relax calls {calls:3d}  iterations {its:7d}  "
                  f"converged {int(np.sum(out['curve/converged']))}/{out['curve/converged'].size}  methods {methods}",
                  flush=True)


def _equal(x, y):
    """Bitwise equal (NaN where NaN: g_r of a step without contact)."""
    return np.array_equal(x, y, equal_nan=np.issubdtype(x.dtype, np.inexact))


def compare(base, new):
    base, new = Path(base), Path(new)
    rows, ok = [], True
    names = {p.name for p in base.glob("*.npz")} & {p.name for p in new.glob("*.npz")}
    for path in sorted(base / name for name in names):
        a, b = np.load(path), np.load(new / path.name)
        keys = [k for k in a.files if not k.endswith("/method")]
        same = set(a.files) == set(b.files) and all(_equal(a[k], b[k]) for k in keys)
        labels = sorted({(str(a[k]), str(b[k])) for k in a.files if k.endswith("/method") and k in b.files})
        ok &= same
        calls = len({k.split("/")[0] for k in a.files if not k.startswith("curve/")})
        its = int(np.sum(a["curve/iterations"]))
        rows.append(f"| {path.stem.replace('__', ' | ')} | {calls} | {its} | {len(keys)} | "
                    f"{'bitwise equal' if same else 'DIFFERENT'} | "
                    + ", ".join(f"{x or '∅'}→{y or '∅'}" if x != y else (x or '∅') for x, y in labels) + " |")
    print("| body | case | steps solved (relax calls) | iterations | arrays | iterates | label (base→new) |\n"
          "|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    for folder, other in ((base, new), (new, base)):  # cases of one recording only (a chain added or removed)
        missing = sorted(p.stem for p in folder.glob("*.npz") if p.name not in names)
        if missing:
            print(f"only in {folder} (not compared): {', '.join(missing)}")
    return ok and bool(names)


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "record":
        record(sys.argv[2])
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(0 if compare(sys.argv[2], sys.argv[3]) else 1)
    else:
        sys.exit(__doc__)
