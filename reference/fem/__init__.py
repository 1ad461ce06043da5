"""Plane-strain finite-element reference for the periodic bonded-layer cell.

Units: SI (see `gfmd_contact.core.conventions`). An independent cross-check of GFMD: it shares
the inputs (the scene, the profile heights of `gfmd_contact.core.surfaces`), the model choice
(`gfmd_contact.core.model`), the load ramp (`gfmd_contact.core.ramp`, load steps included) and the result
type with GFMD, and nothing it checks: the cohesive law (`law`), the indenter position
(`geometry`) and the observables p, a_rel, ḡ_r (`observables`) are its own code, and no
solver code is shared (tests/test_architecture.py holds this):

* `mesh`      graded triangle mesh (numpy → skfem.MeshTri), top nodes = GFMD nodes
* `assembly`  P1/P2 elasticity (skfem.models.elasticity), periodicity by an explicit
              projection K_r = Pᵀ K P (scikit-fem 12's MeshTri1DG.periodic breaks
              FacetBasis and skfem.utils.mpc mis-assembles periodic constraints),
              bonded base, dense condensation onto the top surface
* `solver`    Newton (dense condensed surface) + trust-region energy descent (normal law) or
              pseudo-transient continuation (coupled law) as fallback; load ramp
* `sparse`    the same Newton on the full reduced system (SuperLU), for large N
* `quadrature` Gauss–Legendre boundary term (run_realization(quadrature="gauss"); default nodal)
* `hardwall`  frictionless hard wall: primal–dual active set on the surface compliance
* `law`       the seed's CZ laws (Eqs. 2–3) and the contact gap Δtol, written from the paper
* `geometry`  z_ind = h − min h + δ0 − U at the FE surface points (Fourier interpolant of h)
* `observables` p, a_rel, ḡ_r, ḡ (seed Eqs. 5–6) from the FE's own fields (`Cell.observe`)
* `export`    VTU output (meshio): one file per recorded step + a PVD series

`run_realization(scene, realization=0, order=2, progress=None, linear="auto")` returns a
`gfmd_contact.core.result.Result` with method "fe-p2" / "fe-p1".
"""

from .export import export_vtu
from .run import run_realization

__all__ = ["export_vtu", "run_realization"]
