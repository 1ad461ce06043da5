"""GFMD 2+1-D vs the 3-D FE (reference.fem3d) node by node, and the embedded sinusoid 3-D FE vs 1+1-D FE.

Scene (both methods, the same inputs): a periodic L × L cell, L = 1 µm, N × N nodes, a bonded layer
D = L (both solve the same body), E = 70 GPa, ν = 0.3; surfaces
* "egg-box": h = A cos(2πx/L) cos(2πy/L), A = 20 nm;
* "rough":   a band-limited self-affine surface, H = 0.8: the modes 1 ≤ |q|L/2π ≤ 4 with amplitude
             ∝ |q|^−(1+H) and phases from seed 7, h_rms = 10 nm, written on each N × N grid as a
             surface.kind = "file" height map, so every N samples the same continuum surface and
             refining N refines the discretisation only.
Laws: hard wall, and the normal CZ (seed Eq. 3, φn* = 0.01, δn = 2 nm). δ from −2 nm to 20 nm in
6 steps (partial contact). GFMD: solver.tolerance 1e-10; FE: Q1 on the mesh family of
tests/test_fem3d_stiffness.py (N/2 layers graded with total growth 8 down to D: its mode error vs the
layer formula is measured there, verification/data/mesh/fem3d_stiffness.json, O(l²)), tolerance 1e-10.

Metrics (max over the steps): p: max_k |p̄_FE − p̄_GFMD| / max_k |p̄_GFMD|; a: max_k |Δa_rel| (nodes/N²);
g: max_k |Δḡ_r| / max_k ḡ_r; uz: ‖u_z^FE − u_z^GFMD‖₂/‖u_z^GFMD‖₂ and tn: ‖t_n^FE − t_n^GFMD‖₂/‖t_n^GFMD‖₂
over the saved steps, each / max_k ‖·^GFMD‖₂ (a step out of contact has small fields). The FE's surface stiffness differs from GFMD's exact layer kernel by its
discretisation error, O(l²) per mode (the data file above), so the differences should fall as N^−2
where the contact set is resolved (u_z, p̄); t_n and a_rel carry the contact edge (order ≤ 2).

Embedded sinusoid: h = A cos(2πx/L) on N × 4 nodes through the 3-D FE vs the same profile on N nodes
through the 1+1-D FE (reference.fem, P2): p̄ and a_rel per step, and t_n along x.

    python -m verification.studies.fem3d_gfmd [--write] [--full]

N = 16, 32 (--full adds 64, a few minutes); `--write` stores verification/data/fem3d_gfmd.json.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from gfmd_contact.core.scene import scene_from_dict
from verification import measured
from verification.metrics import curve_difference, max_abs_difference, observed_orders

NAME = "fem3d_gfmd"
KEY = "convergence"
L, E, NU, D = 1e-6, 70e9, 0.3, 1e-6
GROWTH = 8.0
SURFACES = ("egg-box", "rough")
LAWS = ("hard-wall", "cohesive")
NODES = (16, 32)
FULL_NODES = (16, 32, 64)
METRICS = ("p", "a", "g", "uz", "tn")
_CACHE: dict = {}
_DIR = Path(tempfile.mkdtemp(prefix="fem3d_gfmd_"))


def rough_heights(n, hurst=0.8, h_rms=10e-9, seed=7, qmax=4):
    """The band-limited self-affine surface (module docstring) sampled on n × n nodes (m)."""
    rng = np.random.default_rng(seed)
    x = np.arange(n) / n
    h = np.zeros((n, n))
    for m in range(-qmax, qmax + 1):
        for k in range(0, qmax + 1):
            if (k == 0 and m <= 0) or not 0 < np.hypot(m, k) <= qmax:
                continue
            amp = np.hypot(m, k) ** -(1 + hurst)
            phase = rng.uniform(0, 2 * np.pi)
            h += amp * np.cos(2 * np.pi * (m * x[:, None] + k * x[None, :]) + phase)
    return h * h_rms / np.sqrt(np.mean(h**2))


def scene(surface, law, n, ny=None, method="gfmd"):
    s = {"nodes": n, "length": L, "realizations": 1}
    if ny != 0:  # ny = 0: the 1+1-D profile
        s.update(nodes_y=ny or n, length_y=L)
    if surface == "egg-box":
        s.update(kind="egg-box", amplitude=20e-9)
    elif surface == "sinusoid":
        s.update(kind="sinusoid", amplitude=20e-9)
    else:
        path = _DIR / f"rough{n}.npy"
        np.save(path, rough_heights(n))
        s.update(kind="file", path=str(path), facing="valleys")  # the generated heights as they are
    return scene_from_dict({"surface": s, "material": {"youngs_modulus": E, "poisson_ratio": NU, "thickness": D},
                            "interface": {"law": law, "phi_n_star": 0.01, "length_normal": 2e-9},
                            "loading": {"initial_separation": 2e-9, "final_penetration": 20e-9, "steps": 6},
                            "solver": {"tolerance": 1e-10}, "output": {"field_steps": 3, "workers": 1},
                            "method": {"name": method}}, name=f"{surface}-{law}-{n}")


def family(n):
    """(layers, top) of the FE mesh family whose mode error verification/data/mesh/fem3d_stiffness.json measures."""
    layers = n // 2
    ratio = GROWTH ** (1 / layers)
    return {"layers": layers, "top": D * (ratio - 1) / (GROWTH - 1)}


def run_fe3d(sc):
    from reference.fem3d.ramp import run_realization

    return run_realization(sc, 0, mesh_kw=family(sc.surface.nodes), tolerance=1e-10)


def field_scaled(result, reference, name):
    """max over the saved steps k of ‖f_k − f_k^ref‖₂ / max_k ‖f_k^ref‖₂ (a step out of contact has small fields)."""
    scale = max(float(np.linalg.norm(reference.fields[k][name])) for k in reference.fields)
    return max(float(np.linalg.norm(result.fields[k][name] - reference.fields[k][name])) for k in reference.fields) / scale


def compare(surface, law, n):
    """GFMD vs 3-D FE on scene(surface, law, n): {metric: difference, fe_s, gfmd_s, rf, rg}, once per process."""
    key = (surface, law, n)
    if key not in _CACHE:
        from gfmd_contact.app.methods import run_realization

        t0 = time.perf_counter()
        rg = run_realization(scene(surface, law, n))
        t1 = time.perf_counter()
        rf = run_fe3d(scene(surface, law, n, method="fe"))
        t2 = time.perf_counter()
        assert rg.all_converged and rf.all_converged, f"{key}: a step did not converge"
        out = {"p": curve_difference(rf, rg, "p"), "a": max_abs_difference(rf, rg, "a_rel"),
               "g": float(np.nanmax(np.abs(np.asarray(rf.curve["g_r"]) - np.asarray(rg.curve["g_r"])))
                          / np.nanmax(rg.curve["g_r"])),
               "uz": field_scaled(rf, rg, "u_z"), "tn": field_scaled(rf, rg, "t_n"),
               "gfmd_s": t1 - t0, "fe_s": t2 - t1, "rf": rf, "rg": rg}
        _CACHE[key] = out
        print(f"{surface} {law} N={n}: " + "  ".join(f"{m} {out[m]:.3g}" for m in METRICS)
              + f"  GFMD {out['gfmd_s']:.1f} s  FE {out['fe_s']:.1f} s", flush=True)
    return _CACHE[key]


def compare_embedded(n, law="hard-wall"):
    """The 1-D sinusoid embedded in 2-D: 3-D FE (N × 4) vs 1+1-D FE P2 (N): p, a_rel, t_n along x."""
    key = ("embedded", law, n)
    if key not in _CACHE:
        from reference.fem import run_realization as run_fe2d

        r3 = run_fe3d(scene("sinusoid", law, n, ny=4, method="fe"))
        two = scene("sinusoid", law, n, ny=0, method="fe")
        r2 = run_fe2d(two, 0, order=2, tolerance=1e-10)
        assert r3.all_converged and r2.all_converged
        scale = max(float(np.linalg.norm(r2.fields[k]["t_n"])) for k in r2.fields)
        tn = max(float(np.linalg.norm(r3.fields[k]["t_n"][:, 0] - r2.fields[k]["t_n"])) for k in r2.fields) / scale
        spread = max(float(np.ptp(r3.fields[k]["t_n"], axis=1).max()) for k in r3.fields)
        out = {"p": curve_difference(r3, r2, "p"), "a": max_abs_difference(r3, r2, "a_rel"), "tn": tn,
               "y_spread": spread / max(float(np.abs(r3.fields[k]["t_n"]).max()) for k in r3.fields)}
        _CACHE[key] = out
        print(f"embedded sinusoid {law} N={n}: " + "  ".join(f"{m} {out[m]:.3g}" for m in ("p", "a", "tn", "y_spread")),
              flush=True)
    return _CACHE[key]


def stored(surface, law, metric):
    """{"N": [...], metric: [...]} stored for (surface, law)."""
    v = measured.value(NAME, KEY, f"{surface}/{law}")
    return v["N"], v[metric]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store verification/data/fem3d_gfmd.json")
    ap.add_argument("--full", action="store_true", help="add N = 64 (a few minutes)")
    args = ap.parse_args(argv)
    nodes = FULL_NODES if args.full else NODES
    t0 = time.perf_counter()
    values = {}
    for surface in SURFACES:
        for law in LAWS:
            outs = [compare(surface, law, n) for n in nodes]
            v = {"N": list(nodes), **{m: [float(o[m]) for o in outs] for m in METRICS if m != "a"},
                 "a_node_count": [measured.node_count(o["a"], n * n) for o, n in zip(outs, nodes)]}
            v["order"] = {m: observed_orders(nodes, v[m]) for m in ("p", "uz", "tn")}
            v["fe_s"] = [o["fe_s"] for o in outs]
            v["gfmd_s"] = [o["gfmd_s"] for o in outs]
            values[f"{surface}/{law}"] = v
    for law in LAWS:
        outs = [compare_embedded(n, law) for n in nodes]
        values[f"embedded/{law}"] = {"N": list(nodes), **{m: [float(o[m]) for o in outs] for m in ("p", "tn", "y_spread")},
                                     "a_node_count": [measured.node_count(o["a"], n) for o, n in zip(outs, nodes)]}
        values[f"embedded/{law}"]["order"] = {m: observed_orders(nodes, values[f"embedded/{law}"][m]) for m in ("p", "tn")}
    if args.write:
        print(measured.write(NAME, {KEY: measured.make_entry(
            values, scene="verification.studies.fem3d_gfmd.scene(surface, law, N)", wall_s=time.perf_counter() - t0,
            fe_mesh="N/2 Q1 layers, total growth 8, D = L (verification/data/mesh/fem3d_stiffness.json)")},
            description="GFMD 2+1-D vs 3-D FE (Q1) node by node, egg-box and band-limited self-affine, hard wall and "
                        "normal CZ, N = 16, 32 (64 with --full); embedded sinusoid 3-D FE vs 1+1-D FE P2"))


if __name__ == "__main__":
    main()
