"""Depth grading of the hexahedral mesh of one periodic Lx × Ly cell of a bonded layer (numpy).

Units: SI (see `gfmd_contact.core.conventions`). The cell is 0 ≤ x ≤ Lx, 0 ≤ y ≤ Ly, −D ≤ z ≤ 0; the mesh is
`skfem.MeshHex1.init_tensor` on x_i = i Lx/Nx (i = 0 … Nx), y_j = j Ly/Ny and the z levels below
(`reference.fem3d.assembly.periodic_cell`): the top vertices are the scene's Nx × Ny grid, node (i, j)
at (i Lx/Nx, j Ly/Ny, 0) (SPEC2D), plus the periodic images x = Lx, y = Ly. The lateral spacing is
uniform at every depth, so the mesh is invariant under a shift by one node in x or y. In z the layer
thicknesses grow geometrically from `top` so that `layers` of them fill D exactly (`graded_depths`).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

#: default growth ratio of successive layer thicknesses when `layers` is not given
DEFAULT_GROWTH = 1.2


def graded_depths(depth, layers=None, top=None, growth=DEFAULT_GROWTH):
    """z coordinates (0 = surface first, down to −D) of a geometric grading with first thickness `top`.

    layers: number of element layers (default: as many as a growth ratio `growth` needs); the ratio r
    of successive thicknesses solves top·(r^n − 1)/(r − 1) = D (uniform if top·n ≥ D).
    """
    if not (np.isfinite(depth) and depth > 0):
        raise ValueError(f"thickness = {depth!r}: must be a finite positive layer thickness D (m)")
    if top is None or not top > 0:
        raise ValueError(f"top = {top!r}: the first layer thickness must be positive (m)")
    if layers is None:
        layers = 1 if top >= depth else int(np.ceil(np.log1p(depth * (growth - 1) / top) / np.log(growth)))
    layers = int(layers)
    if layers < 1:
        raise ValueError(f"layers = {layers}: at least one element layer")
    if top * layers >= depth:
        ratio = 1.0
    else:
        ratio = brentq(lambda r: top * (r**layers - 1) / (r - 1) - depth, 1 + 1e-12, 1e3, xtol=1e-14)
    thickness = top * ratio ** np.arange(layers) if ratio > 1 else np.full(layers, depth / layers)
    z = -np.concatenate([[0.0], np.cumsum(thickness)])
    z[-1] = -depth
    return z
