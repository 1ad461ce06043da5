"""Model only what a scene requires: the reduced models against the full ones, measured.

Scene: `verification.scenes.extremes_base` (self-affine, H = 0.8, h_rms = 4 nm, L = 256 nm, N = 512,
φn* = 0.15, δn = 1 nm, δ0 = 8 nm) loaded further, δ to 8 nm (32 steps; 48 in (b)); FIRE, tolerance 1e-8;
p_ref = E*ḡ.

(a) The seed's claim ("compressibility and friction ... affect [the load-area relation] negligibly"):
    coupled law c = 0.5 (u_x, u_z; seed Eq. 2) against normal-only c = 0 (u_z; Eq. 3) at equal δ,
    ν = 0.45 and 0.3: max |Δa_rel| and max |Δp_r*| / max |p_r*|.
(a') Exactness of the reduction, `solver.unknowns = "coupled"` forcing the full model: ν = 1/2, c = 0.5
    (u_x ≡ 0 is exact) and c = 0, ν = 0.45 (the forced full model runs Eq. 2 with φt = 0, whose T_n still
    carries e^{−Δt²/δt²}: the difference measures that factor, not an error of the reduction).
(b) Half-plane against a layer on a rigid base, D = L/4 … 8L, at equal *effective* penetration
    δ_eff = δ − pD/M (the layer's uniform mode shifts the mean plane by ū = −pD/M); floor: the half-plane
    against itself on a grid shifted by half a step. Mean over the steps of |Δp|/p_ref and |Δa_rel|.

    python -m verification.studies.reduced_models [--write]

`--write` stores the numbers in verification/data/reduced_models.json (entry "ci"), which
test_reduced_models.py reads to set its bounds.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import gfmd.loading as gl
from gfmd_contact.core.kernels import constrained_modulus
from gfmd_contact.core.observables import reduced_pressure
from verification import measured
from verification.scenes import extremes_base

NAME = "reduced_models"
KEY = "ci"
N = 512
TOL = 1e-8
NUS_CLAIM = (0.45, 0.3)
FORCED = ((0.5, 0.5), (0.45, 0.0))  # (ν, c)
DEPTHS = (0.25, 0.5, 1, 2, 4, 8)  # D / L
STEPS_B = 48
_CACHE = {}


def run(steps=32, **overrides):
    """(scene, result, wall s) of extremes_base loaded to δ = 8 nm, once per process and arguments."""
    key = (steps, tuple(sorted(overrides.items())))
    if key not in _CACHE:
        sc = extremes_base(**{"loading.final_penetration": 8e-9, "loading.steps": steps, **overrides})
        t0 = time.perf_counter()
        result = gl.run_realization(sc)
        wall = time.perf_counter() - t0
        assert result.all_converged, result.messages
        _CACHE[key] = (sc, result, wall)
    return _CACHE[key]


def p_ref(sc, result):
    return sc.material.contact_modulus * float(result.curve["g"][0])


def reduced(sc, result):
    return reduced_pressure(result.curve["p"], result.curve["g_r"], sc.material.contact_modulus)


def relation_difference(a, b):
    """(max|Δa_rel|, max|Δp_r*| / max|p_r*|) at equal δ for two runs (sc, result, wall)."""
    pa, pb = reduced(*a[:2]), reduced(*b[:2])
    ok = np.isfinite(pa) & np.isfinite(pb)
    da = float(np.max(np.abs(a[1].curve["a_rel"] - b[1].curve["a_rel"])))
    return da, float(np.max(np.abs(pa - pb)[ok]) / np.max(np.abs(pb[ok])))


def seed_claim(nu):
    """(coupled run, normal run, max|Δa_rel|, max|Δp_r*|/max|p_r*|) at Poisson ratio nu."""
    normal = run(**{"material.poisson_ratio": nu})
    coupled = run(**{"material.poisson_ratio": nu, "interface.tangential_ratio": 0.5})
    return (coupled, normal, *relation_difference(coupled, normal))


def forced_full(nu, c):
    """(full run, auto run, max|Δp|/p_ref, max|Δa_rel|) with solver.unknowns = "coupled" forced."""
    auto = run(**{"material.poisson_ratio": nu, "interface.tangential_ratio": c})
    full = run(**{"material.poisson_ratio": nu, "interface.tangential_ratio": c, "solver.unknowns": "coupled"})
    scale = p_ref(*auto[:2])
    dp = float(np.max(np.abs(full[1].curve["p"] - auto[1].curve["p"]))) / scale
    da = float(np.max(np.abs(full[1].curve["a_rel"] - auto[1].curve["a_rel"])))
    return full, auto, dp, da


def against_half_plane(layer, half):
    """Mean |Δp|/p_ref and |Δa_rel| of a layer run against the half-plane run at δ_eff = δ − pD/M, and the
    largest shift ū/δn."""
    sc, r = layer[:2]
    p, a, d = (np.asarray(r.curve[k], float) for k in ("p", "a_rel", "delta"))
    if sc.material.half_plane:
        shift = np.zeros_like(p)
    else:
        shift = p * sc.material.thickness / constrained_modulus(sc.material.youngs_modulus, sc.material.poisson_ratio)
    d_eff = d - shift
    dh = np.asarray(half[1].curve["delta"], float)
    ok = (d_eff >= dh.min()) & (d_eff <= dh.max())
    ph = np.interp(d_eff[ok], dh, half[1].curve["p"])
    ah = np.interp(d_eff[ok], dh, half[1].curve["a_rel"])
    scale = p_ref(*half[:2])
    return (float(np.mean(np.abs(p[ok] - ph))) / scale, float(np.mean(np.abs(a[ok] - ah))),
            float(np.max(np.abs(shift))) / sc.interface.length_normal)


def half_plane_vs_layer(steps=STEPS_B):
    """{"half", "floor" (p, a), "layers" {D/L: run}, "out" {D/L: (p, a, ū/δn)}}."""
    half = run(steps)
    shifted = run(steps, **{"loading.initial_separation": 8e-9 + 0.5 * 16e-9 / steps})
    floor_p, floor_a, _ = against_half_plane(shifted, half)
    layers = {r: run(steps, **{"material.thickness": r * half[0].surface.length}) for r in DEPTHS}
    return {"half": half, "floor": (floor_p, floor_a), "layers": layers,
            "out": {r: against_half_plane(layers[r], half) for r in DEPTHS}}


def study():
    t0 = time.perf_counter()
    values = {"N": N, "seed_claim": {}, "forced_full": {}}
    for nu in NUS_CLAIM:
        coupled, normal, da, dp = seed_claim(nu)
        values["seed_claim"][f"{nu:g}"] = {"da_node_count": measured.node_count(da, N), "dp": dp,
                                            "wall_s": [coupled[2], normal[2]]}
    for nu, c in FORCED:
        full, auto, dp, da = forced_full(nu, c)
        values["forced_full"][f"nu={nu:g} c={c:g}"] = {"dp": dp, "da_node_count": measured.node_count(da, N),
                                                       "wall_s": [full[2], auto[2]]}
    hb = half_plane_vs_layer()
    fp, fa = hb["floor"]
    deep = [r for r in DEPTHS if r >= 1]
    values["half_plane"] = {"floor_p": fp, "floor_a": fa, "D/L": list(DEPTHS),
                            "p": [hb["out"][r][0] for r in DEPTHS], "a": [hb["out"][r][1] for r in DEPTHS],
                            "shift": [hb["out"][r][2] for r in DEPTHS],
                            "deep_p_over_floor": max(hb["out"][r][0] for r in deep) / fp,
                            "deep_a_over_floor": max(hb["out"][r][1] for r in deep) / fa,
                            "thin_p_over_floor": hb["out"][0.25][0] / fp}
    return values, time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--write", action="store_true", help="store the numbers in verification/data/reduced_models.json")
    args = ap.parse_args(argv)
    values, wall = study()
    print(values, f"{wall:.1f} s")
    if args.write:
        print(measured.write(NAME, {KEY: measured.make_entry(values, scene="verification.scenes.extremes_base, "
                                                             "loading.final_penetration = 8 nm", wall_s=wall)},
                             description="reduced vs full models: coupled vs normal-only law (seed claim), forced "
                                         "full unknowns vs reduced, half-plane vs layer at equal effective penetration"))


if __name__ == "__main__":
    main()
