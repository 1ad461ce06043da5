"""GFMD on a free half-plane vs the FE reference on a large periodic domain: one rough, non-periodic indenter.

Indenter (1+1-D, no period): h(x) = x²/(2R) + Σ a_i cos(2πx/λ_i + φ_i), R = 1 µm, three waves of incommensurate
wavelengths (173, 91, 47 nm; 1, 0.6, 0.3 nm), on the region L = 1 µm of N nodes; frictionless hard wall,
E = 70 GPa, ν = 0.45; heights as `surface.kind = "file"` (`surface.facing = "valleys"`: h as written).
* FE: the FE reference (`reference.fem`, P2) on a periodic cell K L of K N nodes (the same spacing) on a bonded
  layer D = K L, the same h on the whole cell (outside the region the parabola keeps it out of contact),
  displacement control in 2 steps to δ = 15 nm; its line loads F_k = p̄_k K L;
* GFMD free: `surface.boundary = "free"` on the region, force control at the FE's loads (p̄ = F_k/L).
Both again at 2N (their discretisation errors), and GFMD on the K-cell against the 2K-cell (D = 2K L) at the same
loads: how far the FE's finite cell is from the free body, measured without the free solver.

Metrics per load, over the region's nodes and / the FE's peak pressure: d_free = rms(p_free − p_FE); e_free, e_FE =
rms of each method's N-node pressure against its 2N run; d_trunc = rms(p_GFMD,K − p_GFMD,2K). Read by
verification/test_free_boundary_fe.py (d_free ≤ e_free + e_FE + d_trunc).

    python -m verification.studies.free_fe_rough [N]
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

from gfmd_contact.core.scene import scene_from_dict
from verification.runs import run_gfmd

NAME = "free_fe_rough"
LENGTH = 1e-6
RADIUS = 1e-6
CELLS = 8  # K: the FE cell is K L
WAVES = ((0.173e-6, 1.0e-9, 0.3), (0.091e-6, 0.6e-9, 1.1), (0.047e-6, 0.3e-9, 2.0))  # (λ, a, φ)
PENETRATION = 15e-9  # the FE's final δ
MATERIAL = {"youngs_modulus": 70e9, "poisson_ratio": 0.45}


def heights(x):
    """h(x) (m): the rough, non-periodic indenter."""
    return x**2 / (2 * RADIUS) + sum(a * np.cos(2 * np.pi * x / lam + phi) for lam, a, phi in WAVES)


def _scene(directory, nodes, length, boundary, sections):
    x = (np.arange(nodes) - nodes // 2) * length / nodes  # x = 0 at node N/2, as the analytic kinds centre
    path = Path(directory) / f"h_{nodes}_{length:.3g}.npy"
    np.save(path, heights(x))
    d = {"surface": {"kind": "file", "path": str(path), "nodes": nodes, "length": length, "boundary": boundary,
                     "facing": "valleys", "realizations": 1},
         "material": {**MATERIAL, "thickness": "inf"}, "interface": {"law": "hard-wall"}, "output": {"field_steps": 2},
         "solver": {"tolerance": 1e-10}}
    for section, values in sections.items():
        d.setdefault(section, {}).update(values)
    return scene_from_dict(d)


def _periodic(directory, nodes, cells, extra):
    return _scene(directory, cells * nodes, cells * LENGTH, "periodic",
                  {"material": {"thickness": cells * LENGTH}, **extra})


def _region(p, nodes, cells):
    """The region's nodes of a field on the K-cell (node N/2 of the region is node K N/2 of the cell)."""
    mid = cells * nodes // 2
    return p[mid - nodes // 2: mid + nodes - nodes // 2]


def _force(loads, length):
    return {"loading": {"control": "force", "initial_separation": 1e-9, "path": [0.0, *(f / length for f in loads)],
                        "steps": [1] * len(loads)}}


def _runs(directory, nodes):
    """(FE Result, GFMD free Result, FE loads (N/m)) at N region nodes: the FE on the K-cell, the free run at its
    loads."""
    from reference.fem.run import run_realization as fe_run

    ramp = {"loading": {"initial_separation": 1e-9, "final_penetration": PENETRATION, "steps": 2}}
    fe = fe_run(_periodic(directory, nodes, CELLS, {**ramp, "method": {"name": "fe"}}))
    loads = [float(fe.curve["p"][k]) * CELLS * LENGTH for k in (1, 2)]
    free, _ = run_gfmd(_scene(directory, nodes, LENGTH, "free", _force(loads, LENGTH)))
    return fe, free, loads


def _truncation(directory, nodes):
    """Per load: rms(p_K − p_2K) of GFMD on the K-cell and the 2K-cell (force control at the K run's loads)."""
    ramp = {"loading": {"initial_separation": 1e-9, "final_penetration": PENETRATION, "steps": 2}}
    per, _ = run_gfmd(_periodic(directory, nodes, CELLS, ramp))
    loads = [float(per.curve["p"][k]) * CELLS * LENGTH for k in (1, 2)]
    wide, _ = run_gfmd(_periodic(directory, nodes, 2 * CELLS, _force(loads, 2 * CELLS * LENGTH)))
    return [_rms(_region(_p(per, k), nodes, CELLS) - _region(_p(wide, k), nodes, 2 * CELLS)) for k in (1, 2)]


def _p(result, k):
    return -np.asarray(result.fields[k]["t_n"], float)


def _rms(v):
    return float(np.sqrt(np.mean(np.square(v))))


def measure(nodes):
    """Per load, / the FE's peak pressure: "d_free" rms(p_free − p_FE) at N; the discretisation errors "e_free",
    "e_fe" (rms of N against 2N on the N nodes); "d_trunc" (`_truncation`); and "loads" (N/m), "a_rel" (free, FE)."""
    with tempfile.TemporaryDirectory() as directory:
        fe, free, loads = _runs(directory, nodes)
        fe2, free2, _ = _runs(directory, 2 * nodes)
        trunc = _truncation(directory, nodes)
    out = {"d_free": [], "e_free": [], "e_fe": [], "d_trunc": [], "loads": loads, "a_rel": []}
    for i, k in enumerate((1, 2)):
        p_fe, p_free = _region(_p(fe, k), nodes, CELLS), _p(free, k)
        coarse = slice(0, None, 2)  # the N nodes among the 2N (x = 0 at node N/2 and at node N)
        scale = float(np.max(p_fe))
        out["d_free"].append(_rms(p_free - p_fe) / scale)
        out["e_free"].append(_rms(p_free - _p(free2, k)[coarse]) / scale)
        out["e_fe"].append(_rms(p_fe - _region(_p(fe2, k), 2 * nodes, CELLS)[coarse]) / scale)
        out["d_trunc"].append(trunc[i] / scale)
        out["a_rel"].append((float(np.mean(p_free > 0)), float(np.mean(p_fe > 0))))
    return out


def main(argv=None):
    nodes = int((argv or sys.argv[1:] or ["64"])[0])
    print(measure(nodes))


if __name__ == "__main__":
    main()
