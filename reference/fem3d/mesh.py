"""Hexahedral mesh of one periodic Lx × Ly cell of a bonded layer, graded in depth (numpy + skfem).

Units: SI (see `contact.conventions`). The cell is 0 ≤ x ≤ Lx, 0 ≤ y ≤ Ly, −D ≤ z ≤ 0. The top
layer of vertices is the scene's Nx × Ny grid, node (i, j) at (i Lx/Nx, j Ly/Ny, 0) (SPEC2D),
plus the periodic images x = Lx and y = Ly (tied to x = 0, y = 0 by `reference.fem3d.assembly`).
The lateral spacing is uniform at every depth, so the mesh is invariant under a shift by one node
in x or y (the surface stiffness is doubly circulant, which `assembly.Cell3D` uses). In z the
layer thicknesses grow geometrically from `top` (default: the finer lateral spacing) so that
`layers` of them fill D exactly (`graded_depths`).
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


def box_mesh(nodes_x, nodes_y, length_x, length_y, depth, layers=None, top=None):
    """(`skfem.MeshHex1`, top (Nx, Ny) vertex indices of the scene's nodes, z levels).

    The vertices of `skfem.MeshHex1.init_tensor` on x_i = i Lx/Nx (i = 0 … Nx), y_j = j Ly/Ny,
    z from `graded_depths(D, layers, top)`; top defaults to min(Lx/Nx, Ly/Ny).
    """
    from skfem import MeshHex1

    for key, n in (("nodes_x", nodes_x), ("nodes_y", nodes_y)):
        if int(n) != n or n < 2:
            raise ValueError(f"{key} = {n!r}: the 3-D FE needs at least 2 surface nodes per direction")
    for key, v in (("length_x", length_x), ("length_y", length_y)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{key} = {v!r}: must be a finite positive period (m)")
    nodes_x, nodes_y = int(nodes_x), int(nodes_y)
    if top is None:
        top = min(length_x / nodes_x, length_y / nodes_y)
    x = np.linspace(0.0, length_x, nodes_x + 1)
    y = np.linspace(0.0, length_y, nodes_y + 1)
    z = graded_depths(depth, layers, top)[::-1]  # ascending for init_tensor
    mesh = MeshHex1.init_tensor(x, y, z)
    p = mesh.p
    tol = 1e-9 * min(length_x / nodes_x, length_y / nodes_y, top)
    on_top = np.flatnonzero(np.abs(p[2]) < tol)
    i = np.rint(p[0, on_top] / (length_x / nodes_x)).astype(int)
    j = np.rint(p[1, on_top] / (length_y / nodes_y)).astype(int)
    keep = (i < nodes_x) & (j < nodes_y)
    grid = -np.ones((nodes_x, nodes_y), int)
    grid[i[keep], j[keep]] = on_top[keep]
    if np.any(grid < 0):
        raise RuntimeError("top mesh vertices do not cover the Nx × Ny node grid")
    return mesh, grid, z[::-1]
