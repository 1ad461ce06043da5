"""Graded triangle mesh of one periodic cell of a bonded layer (numpy only).

Units: SI (see `gfmd_contact.core.conventions`). The cell is −L/2 ≤ x ≤ L/2, −D ≤ z ≤ 0.
The top row holds the N GFMD nodes x_j = (j − N/2) l, l = L/N, plus the
periodic image x = L/2 of node 0. Going down, rows are spaced like the local
horizontal spacing h; every `rows_per_level` rows the horizontal resolution is
halved (transition strip: 3 triangles per coarse segment), until the spacing
reaches `max_spacing` (default D/2, never coarser than L/4). The vertex count
is therefore ~ N·2·rows_per_level + O(D/h_max) rows, linear in N.

Right-edge nodes (x = L/2) are geometric copies of left-edge nodes; the
periodic identification is done on the DOFs by `reference.fem.assembly`.

Every row has at least `min_segments` (default 32) segments, a multiple of 2,
and the diagonals alternate per segment, so the mesh is invariant under a
shift by 2 coarsest segments, L/(min_segments/2): `shift_period(...)` gives
that count m, which `Cell.schur` uses (block-circulant surface stiffness).
"""

from __future__ import annotations

import numpy as np


def _row_plan(nodes, length, depth, rows_per_level, max_spacing, min_segments):
    """List of (z, n_segments) from the top (z = 0) to the base (z = −D)."""
    n = nodes
    h = length / nodes
    rows = [(0.0, n)]
    z = 0.0
    count = 0
    while True:
        if (count >= rows_per_level and n % 2 == 0 and n // 2 >= min_segments
                and 2 * h <= max_spacing):
            n //= 2
            h *= 2
            count = 0
        if z - 1.3 * h <= -depth:  # last row (thickness in (0.15 h, 1.3 h]) lands on the base
            rows.append((-depth, n))
            return rows
        z -= h
        rows.append((z, n))
        count += 1


def graded_cell(nodes, length, depth, rows_per_level=4, max_spacing=None, min_segments=32):
    """Vertices p (2, n_v) and triangles t (3, n_t) of the graded periodic cell.

    nodes: N top nodes (even); length: L (m); depth: D (m).
    Returns (p, t, top) where top[j] is the vertex index of GFMD node j
    (x_j = (j − N/2) l), j = 0 … N−1.
    """
    if nodes < 4 or nodes % 2:
        raise ValueError(f"nodes = {nodes}: the FE mesh needs an even number of top nodes ≥ 4")
    if not (np.isfinite(depth) and depth > 0):
        raise ValueError(f"depth = {depth!r}: must be a finite positive thickness (m)")
    if max_spacing is None:
        max_spacing = depth / 2
    max_spacing = max(max_spacing, length / nodes)
    min_segments = min(min_segments, nodes)
    plan = _row_plan(nodes, length, depth, rows_per_level, max_spacing, min_segments)
    # enforce strictly decreasing z (the fix-up above may create equal rows)
    zs = [r[0] for r in plan]
    if any(b >= a for a, b in zip(zs, zs[1:])):
        raise RuntimeError(f"mesh row plan not monotone: {zs}")
    x0 = -length / 2
    points = []
    row_index = []
    start = 0
    for z, n in plan:
        x = x0 + np.arange(n + 1) * (length / n)
        points.append(np.vstack([x, np.full(n + 1, z)]))
        row_index.append(start + np.arange(n + 1))
        start += n + 1
    p = np.hstack(points)
    tris = []
    for (z_a, n_a), (z_b, n_b), ia, ib in zip(plan, plan[1:], row_index, row_index[1:]):
        if n_a == n_b:
            a0, a1, b0, b1 = ia[:-1], ia[1:], ib[:-1], ib[1:]
            # alternate the diagonal so the mesh has no preferred direction
            k = np.arange(n_a)
            even = k % 2 == 0
            tris.append(np.where(even, np.vstack([a0, b0, b1]), np.vstack([a0, b0, a1])))
            tris.append(np.where(even, np.vstack([a0, b1, a1]), np.vstack([a1, b0, b1])))
        elif n_a == 2 * n_b:
            k = np.arange(n_b)
            l0, m, r0 = ia[2 * k], ia[2 * k + 1], ia[2 * k + 2]
            b0, b1 = ib[k], ib[k + 1]
            tris.append(np.vstack([l0, b0, m]))
            tris.append(np.vstack([m, b0, b1]))
            tris.append(np.vstack([m, b1, r0]))
        else:
            raise RuntimeError("unsupported row transition")
    t = np.hstack(tris)
    # counter-clockwise orientation
    a, b, c = p[:, t[0]], p[:, t[1]], p[:, t[2]]
    area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    flip = area2 < 0
    t[1, flip], t[2, flip] = t[2, flip], t[1, flip].copy()
    top = row_index[0][:-1]
    return p, t, top


def shift_period(nodes, min_segments=32):
    """m such that the mesh is invariant under x → x + L/m (see module docstring)."""
    return max(1, min(min_segments, nodes) // 2)


def make_mesh(nodes, length, depth, **kw):
    """`skfem.MeshTri` of the graded cell and the top-vertex indices of the GFMD nodes."""
    from skfem import MeshTri

    p, t, top = graded_cell(nodes, length, depth, **kw)
    return MeshTri(p, t), top
