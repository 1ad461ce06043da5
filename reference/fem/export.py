"""VTU export of FE fields (meshio): displacement and stress per recorded step.

Units: SI (see `gfmd.conventions`): displacement in m, stress in Pa.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np


def export_vtu(result, directory, steps=None):
    """Write `<directory>/fe_step<k>.vtu` for the recorded steps of an FE `Result`.

    Point data: displacement (u_x, u_z) at the mesh vertices; cell data: stress
    (σ_xx, σ_zz, σ_xz) at the triangle centroids (plane strain). Returns the paths.
    """
    import meshio
    from skfem.models.elasticity import lame_parameters

    prob = getattr(result, "problem", None)
    if prob is None:
        raise ValueError("export_vtu needs a Result from reference.fem.run_realization")
    cell = prob.cell
    basis = cell.basis
    lam, mu = lame_parameters(cell.youngs_modulus, cell.poisson_ratio)
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in sorted(result.solutions if steps is None else steps):
        full = cell.full(prob.solve_interior(result.solutions[k]))
        ux = full[basis.split_indices()[0]]
        uz = full[basis.split_indices()[1]]
        nv = cell.mesh.p.shape[1]
        disp = np.zeros((nv, 3))
        # vertex DOFs come first in scikit-fem's numbering of each component
        disp[:, 0], disp[:, 1] = ux[:nv], uz[:nv]
        # stress at the centroids from the displacement gradient
        grad = basis.interpolate(full).grad  # (2, 2, n_elem, n_qp)
        exx, ezz = grad[0, 0].mean(axis=1), grad[1, 1].mean(axis=1)
        exz = 0.5 * (grad[0, 1] + grad[1, 0]).mean(axis=1)
        tr = exx + ezz
        stress = np.vstack([lam * tr + 2 * mu * exx, lam * tr + 2 * mu * ezz, 2 * mu * exz]).T
        points = np.vstack([cell.mesh.p, np.zeros(nv)]).T
        mesh = meshio.Mesh(points, [("triangle", cell.mesh.t.T)], point_data={"displacement": disp},
                           cell_data={"stress_xx_zz_xz": [stress]})
        path = directory / f"fe_step{k}.vtu"
        mesh.write(path)
        paths.append(path)
    return paths
