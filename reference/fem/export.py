"""VTU / PVD export of FE fields (meshio): displacement and stress per recorded load step.

Units: SI (see `gfmd_contact.core.conventions`): coordinates and displacement in m, stress in Pa,
the PVD time value is the indenter displacement δ = U − δ0 in m.

The input is a `Result` of `reference.fem.run_realization` (cohesive or hard
wall, dense or sparse): its diagnostics "problem" is the FE problem and
"solutions"[k] the vector of its surface unknowns at step k, which
`problem.solve_interior` extends to every DOF; both FE paths store that.

One `fe_step<k>.vtu` per recorded step k (diagnostics "solutions") and a ParaView
collection `fe.pvd` that lists them in step order. Cells: "triangle" for P1,
"triangle6" (VTK quadratic triangle: 3 vertices, then the midpoints of the edges
01, 12, 20) for P2, so the P2 displacement is written at every node. Data:

* point "displacement" (u_x, u_z, 0) at every written node;
* cell "stress" (σ_xx, σ_zz, σ_xz) at the element centroid (mean over the
  element's quadrature points; plane strain, σ_yy not written);
* point "stress": the mean of the cell stresses of the elements sharing the
  node (a recovery for plotting, not a FE quantity).
"""

from __future__ import annotations

from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

SERIES_NAME = "fe.pvd"


def _problem(result):
    prob = getattr(result, "diagnostics", {}).get("problem")
    if prob is None or not hasattr(prob, "cell"):
        raise ValueError("export_vtu needs a Result from reference.fem.run_realization (it carries the FE problem); "
                         f"got method {getattr(result, 'method', type(result).__name__)!r}")
    return prob


def _nodes_and_cells(cell):
    """(points (n, 2) in m, connectivity, meshio cell type, vector DOF index (2, n) per written node)."""
    mesh, basis = cell.mesh, cell.basis
    if cell.order == 1:
        return mesh.p.T, mesh.t.T, "triangle", basis.nodal_dofs
    midpoints = 0.5 * (mesh.p[:, mesh.facets[0]] + mesh.p[:, mesh.facets[1]])
    points = np.hstack([mesh.p, midpoints]).T
    nv = mesh.p.shape[1]
    cells = np.vstack([mesh.t, nv + mesh.t2f]).T  # t2f rows: edges 01, 12, 02 = VTK's 01, 12, 20
    dofs = np.hstack([basis.nodal_dofs, basis.facet_dofs])
    return points, cells, "triangle6", dofs


def _cell_stress(cell, full):
    """(n_elements, 3) plane-strain stress (σ_xx, σ_zz, σ_xz) in Pa at the element centroids."""
    from skfem.models.elasticity import lame_parameters

    lam, mu = lame_parameters(cell.youngs_modulus, cell.poisson_ratio)
    grad = cell.basis.interpolate(full).grad  # (2, 2, n_elem, n_qp)
    exx, ezz = grad[0, 0].mean(axis=1), grad[1, 1].mean(axis=1)
    exz = 0.5 * (grad[0, 1] + grad[1, 0]).mean(axis=1)
    tr = exx + ezz
    return np.vstack([lam * tr + 2 * mu * exx, lam * tr + 2 * mu * ezz, 2 * mu * exz]).T


def step_mesh(result, step):
    """`meshio.Mesh` of recorded step `step` of an FE `Result` (module docstring)."""
    import meshio

    prob = _problem(result)
    solutions = result.diagnostics.get("solutions", {})
    if step not in solutions:
        raise ValueError(f"step {step!r} has no stored FE solution; recorded steps: {sorted(solutions)} "
                         "(scene.output.field_steps chooses them)")
    cell = prob.cell
    full = cell.full(prob.solve_interior(solutions[step]))
    points, cells, kind, dofs = _nodes_and_cells(cell)
    disp = np.zeros((points.shape[0], 3))
    disp[:, 0], disp[:, 1] = full[dofs[0]], full[dofs[1]]
    stress = _cell_stress(cell, full)
    count = np.bincount(cells.ravel(), minlength=points.shape[0])
    nodal = np.zeros((points.shape[0], 3))
    for j in range(cells.shape[1]):
        np.add.at(nodal, cells[:, j], stress)
    nodal /= np.maximum(count, 1)[:, None]
    xyz = np.hstack([points, np.zeros((points.shape[0], 1))])
    return meshio.Mesh(xyz, [(kind, cells)], point_data={"displacement": disp, "stress": nodal},
                       cell_data={"stress": [stress]})


def write_series(directory, entries):
    """Write the ParaView collection `<directory>/fe.pvd` for entries [(δ in m, vtu file name)]."""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">', "  <Collection>"]
    lines += [f'    <DataSet timestep="{time!r}" group="" part="0" file={quoteattr(name)}/>' for time, name in entries]
    lines += ["  </Collection>", "</VTKFile>", ""]
    path = Path(directory) / SERIES_NAME
    path.write_text("\n".join(lines))
    return path


def export_vtu(result, directory, steps=None):
    """Write `<directory>/fe_step<k>.vtu` for the recorded steps (default: all) and `fe.pvd`.

    result: a `Result` of `reference.fem.run_realization`; steps: iterable of step
    indices among the result's diagnostics "solutions". Returns the list of VTU paths (step order);
    the PVD collection lists the same files with time value δ (m).
    """
    _problem(result)
    chosen = sorted(result.diagnostics.get("solutions", {}) if steps is None else steps)
    if not chosen:
        raise ValueError("nothing to export: the result has no stored FE solutions (scene.output.field_steps = 0)")
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    deltas = dict(zip(np.asarray(result.curve["step"]).astype(int).tolist(), result.curve["delta"]))
    paths, entries = [], []
    for k in chosen:
        mesh = step_mesh(result, k)
        path = directory / f"fe_step{k}.vtu"
        mesh.write(path)
        paths.append(path)
        entries.append((float(deltas[k]), path.name))
    write_series(directory, entries)
    return paths
