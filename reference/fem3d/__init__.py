"""3-D finite-element reference for the periodic 2+1-D cell.

Units: SI (see `gfmd_contact.core.conventions`). An independent cross-check of GFMD in 2+1-D: it shares only
the inputs (heights on the Nx × Ny grid, the cell, material, law parameters, displacements) and
uses no code of the core it checks (no `gfmd_contact.core.laws`, `gfmd_contact.core.observables`, `gfmd_contact.core.kernels`,
`gfmd_contact.core.loading`; tests/test_architecture.py holds this), nor `reference.fem`:

* `mesh`        hexahedral mesh (skfem.MeshHex1.init_tensor), surface nodes = the scene's grid,
                geometric grading in depth
* `assembly`    Q1 elasticity (skfem.models.elasticity), periodic projection, bonded base,
                condensation on u_z of the surface by the lateral Fourier block diagonalisation
                of the FE matrix (exact; checked against a sparse direct solve)
* `law`         the normal cohesive zone of seed Eq. 3 and the contact gap Δtol
* `hardwall`    primal–dual active set on the condensed surface
* `cohesive`    Newton with shifted (positive definite) tangent and line search
* `observables` p, a_rel, ḡ_r, ḡ (seed Eqs. 5–6 over the four neighbours, SPEC2D)
* `run`         `solve_cell(heights, Lx, Ly, E, ν, D, displacements, law=...)`, `from_scene`
* `export`      VTU (meshio) of a step: displacement at every vertex
"""

from .export import export_vtu
from .run import Fe3dResult, from_scene, solve_cell

__all__ = ["Fe3dResult", "export_vtu", "from_scene", "solve_cell"]
