"""GFMD free boundary with the coupled law (seed Eq. 2, u_x and u_z solved, the padded 2×2 kernel) vs the periodic
solver in ever larger cells.

Scene: a parabolic cylinder R = 1 µm on the region L = 1 µm of N = 128 nodes, ν = 0.3, exponential coupled CZ
(φn* = 1e-3, δn = δt = 2 l, c = 0.5), force control to 1 N/m. The periodic runs hold the same indenter on the region
of a cell k L (k N nodes) and none outside it (the heights there raised beyond the law's reach, as the free cell
does: `gfmd_contact.core.free_boundary.far_gap`), as `surface.kind = "file"` heights. Fields are compared
normalised by their own mean pressure over the region (the force search meets the load to 1e-4 only).

Tolerance, measured in the test for p and t_t (rms over the region / the free peak): |free − periodic(16 L)| ≤
e_free + e_periodic + images, e = rms of each solver's N-node field against its 2N run on the same nodes, images =
|periodic(8 L) − periodic(16 L)| (what doubling the cell still changes). A sign error in the kernel's coupling
moves t_t by its own size.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core import free_boundary
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import scene_from_dict
from verification.runs import run_gfmd

LENGTH, RADIUS, NODES, LOAD = 1e-6, 1e-6, 128, 1.0
DN = 2 * LENGTH / NODES


def _scene(nodes, cells, boundary, path=None):
    surface = ({"kind": "cylinder", "radius": RADIUS} if path is None else {"kind": "file", "path": str(path),
                                                                             "facing": "valleys"})
    return scene_from_dict({
        "surface": {**surface, "nodes": cells * nodes, "length": cells * LENGTH, "boundary": boundary},
        "material": {"youngs_modulus": 1e9, "poisson_ratio": 0.3},
        "interface": {"law": "cohesive", "phi_n_star": 1e-3, "length_normal": DN, "tangential_ratio": 0.5,
                      "length_tangential": DN},
        "loading": {"control": "force", "initial_separation": 10 * DN, "path": [0.0, LOAD / (cells * LENGTH)],
                    "steps": 2},
        "solver": {"tolerance": 1e-10}, "output": {"field_steps": 2}})


def _fields(result, nodes, cells):
    """(p, t_t) on the region (node N/2 of the region at node k N/2 of the cell), / the region's mean pressure."""
    f = result.fields[max(result.fields)]
    mid = cells * nodes // 2
    cut = slice(mid - nodes // 2, mid + nodes - nodes // 2)
    p, t = -np.asarray(f["t_n"])[cut], np.asarray(f["t_t"])[cut]
    return p / p.mean(), t / p.mean()


def _run(nodes, cells, tmp_path):
    if cells == 0:
        return _fields(run_gfmd(_scene(nodes, 1, "free"))[0], nodes, 1)
    j = np.arange(cells * nodes)
    mid = cells * nodes // 2
    h = ((j - mid) * LENGTH / nodes) ** 2 / (2 * RADIUS)
    inside = (j >= mid - nodes // 2) & (j < mid + nodes - nodes // 2)  # the region, as `_fields` cuts it
    far = free_boundary.far_gap(build_model(_scene(nodes, 1, "free")).law, cells * LENGTH)
    h[~inside] = h[inside].max() + far
    path = tmp_path / f"h_{nodes}_{cells}.npy"
    np.save(path, h)
    return _fields(run_gfmd(_scene(nodes, cells, "periodic", path))[0], nodes, cells)


def test_free_coupled_law_agrees_with_large_periodic_cells(tmp_path, verification_record):
    free, free2 = _run(NODES, 0, tmp_path), _run(2 * NODES, 0, tmp_path)
    p8, p16, p16_2 = _run(NODES, 8, tmp_path), _run(NODES, 16, tmp_path), _run(2 * NODES, 16, tmp_path)
    scale = float(np.max(free[0]))

    def rms(a, b):
        return float(np.sqrt(np.mean((a - b) ** 2))) / scale

    for i, name in enumerate(("p", "t_t")):
        diff = rms(free[i], p16[i])
        bound = rms(free[i], free2[i][::2]) + rms(p16[i], p16_2[i][::2]) + rms(p8[i], p16[i])
        rec = verification_record(
            case=f"cross-check/free-coupled-vs-periodic-large-cell/{name}",
            metric=f"rms |{name}_free − {name}_16L| / max p",
            value=diff, tolerance=bound, methods=("gfmd-free", "gfmd"),
            tolerance_source="measured in the test: each solver's N vs 2N difference + periodic 8 L vs 16 L",
            resolution={"N": NODES, "cells": [8, 16], "nu": 0.3, "tangential_ratio": 0.5})
        assert rec.passed, (name, diff, bound)
