"""VTU export (meshio) of a 3-D FE step: the hexahedral mesh with the displacement at every vertex.

Units: SI (see `gfmd_contact.core.conventions`). Points: the vertices (i lx, j ly, z_k) for i ≤ Nx, j ≤ Ny
(the periodic images x = Lx, y = Ly repeat x = 0, y = 0), cells "hexahedron" (VTK vertex order),
point data "displacement" (u_x, u_y, u_z) (m) from `assembly.Cell3D.displacement_field`, and on the
surface nodes "gap" (m) and "t_n" (Pa) (zero below the surface).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def step_mesh(result, step):
    """`meshio.Mesh` of step `step` of an `Fe3dResult`."""
    import meshio

    if not 0 <= step < len(result.states):
        raise ValueError(f"step {step!r}: the result has steps 0 … {len(result.states) - 1}")
    cell = result.cell
    nx, ny = cell.shape
    lx, ly = cell.spacing
    nz = cell.layers
    u = cell.displacement_field(result.states[step])  # (3, nz + 1, nx, ny)
    i, j = np.arange(nx + 1), np.arange(ny + 1)
    kk, ii, jj = np.meshgrid(np.arange(nz + 1), i, j, indexing="ij")  # (nz+1, nx+1, ny+1)
    points = np.stack([ii * lx, jj * ly, cell.z_levels[kk]], -1).reshape(-1, 3)
    disp = u[:, kk, ii % nx, jj % ny].reshape(3, -1).T
    index = np.arange(points.shape[0]).reshape(nz + 1, nx + 1, ny + 1)
    a = index[1:, :-1, :-1]  # bottom face of each element (deeper layer), then the top face
    bottom = [a, index[1:, 1:, :-1], index[1:, 1:, 1:], index[1:, :-1, 1:]]
    topf = [index[:-1, :-1, :-1], index[:-1, 1:, :-1], index[:-1, 1:, 1:], index[:-1, :-1, 1:]]
    hexa = np.stack([c.ravel() for c in bottom + topf], -1)
    surface = np.zeros((2, points.shape[0]))
    f = result.fields[step]
    top = index[0].ravel()
    surface[0, top] = f["gap"][ii[0] % nx, jj[0] % ny].ravel()
    surface[1, top] = f["t_n"][ii[0] % nx, jj[0] % ny].ravel()
    return meshio.Mesh(points, [("hexahedron", hexa)],
                       point_data={"displacement": disp, "gap": surface[0], "t_n": surface[1]})


def export_vtu(result, directory, steps=None):
    """Write `<directory>/fe3d_step<k>.vtu` for the steps (default all); returns the paths."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    chosen = range(len(result.states)) if steps is None else steps
    paths = []
    for k in chosen:
        path = directory / f"fe3d_step{k}.vtu"
        step_mesh(result, k).write(path)
        paths.append(path)
    return paths
