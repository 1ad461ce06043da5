"""Plane-strain elasticity of the periodic bonded cell: assembly, periodicity, condensation.

Units: SI (see `gfmd_contact.core.conventions`). Independent of the GFMD solver: only
scikit-fem, numpy and scipy. Periodicity is imposed by eliminating the DOFs on
the right edge x = L/2 onto their images on the left edge x = −L/2 with an
explicit 0/1 projection matrix P (K_r = Pᵀ K P); the base z = −D is bonded
(u = 0, DOFs removed). scikit-fem's own periodic meshes / mpc are not used
(see the package docstring for why).

The surface DOFs are the top-row DOFs (z = 0), ordered by x from −L/2:
P1: the N GFMD nodes; P2: N vertices and N facet midpoints interleaved
(x_k = −L/2 + k l/2, vertices at even k). `Cell.schur()` condenses the linear
interior onto the chosen surface components once (dense).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis, ElementTriP1, ElementTriP2, ElementVector, FacetBasis, LinearForm, asm
from skfem.models.elasticity import lame_parameters, linear_elasticity

from .mesh import make_mesh, shift_period

_ELEMENTS = {1: ElementTriP1, 2: ElementTriP2}


def _match(src, dst, tol):
    """Index into dst for each point of src (2, n) with the same z (points sorted by z)."""
    order = np.argsort(dst[1])
    pos = np.searchsorted(dst[1][order], src[1] - tol)
    idx = order[np.clip(pos, 0, len(order) - 1)]
    if np.any(np.abs(dst[1][idx] - src[1]) > tol):
        raise RuntimeError("periodic edges do not match: the mesh is not periodic")
    return idx


@dataclass
class Cell:
    """Assembled periodic cell (see module docstring)."""

    nodes: int
    length: float
    depth: float
    order: int
    youngs_modulus: float
    poisson_ratio: float
    mesh: object
    basis: object
    K: sp.csr_matrix  # full stiffness (Pa), all DOFs
    P: sp.csr_matrix  # full DOFs ← reduced DOFs (periodic image, bonded base removed)
    surface_x: np.ndarray  # x of the surface points (m), sorted
    surface_dofs: np.ndarray  # (2, n_s) reduced DOF index of (u_x, u_z) at each surface point
    weights: np.ndarray  # nodal quadrature weights of the surface points (m), FacetBasis load vector
    vertex_points: np.ndarray  # indices of the GFMD nodes among the surface points
    shifts: int = 1  # mesh invariant under x → x + L/shifts

    @property
    def reduced_stiffness(self):
        return (self.P.T @ self.K @ self.P).tocsc()

    def schur(self, components=("x", "z"), circulant=True):
        """Dense surface stiffness S (n_c·n_s square, N/m per m of displacement) for the components.

        Ordering: component-major, e.g. [u_x at all points, u_z at all points].
        circulant: use the mesh's shift invariance (x → x + L/m) and solve only
        for the first of m blocks of columns (exact up to round-off; tested
        against circulant=False in tests/test_fem_assembly.py).
        Returns (S, solve_interior) where solve_interior(u_s) gives the reduced
        full-DOF vector for surface displacements u_s (the linear interior).
        """
        comp = [("x", "z").index(c) for c in components]
        s_idx = np.concatenate([self.surface_dofs[c] for c in comp])
        kr = self.reduced_stiffness
        n = kr.shape[0]
        i_mask = np.ones(n, bool)
        i_mask[s_idx] = False
        i_idx = np.flatnonzero(i_mask)
        k_ii = kr[i_idx][:, i_idx].tocsc()
        k_is = kr[i_idx][:, s_idx].tocsc()  # solved in dense column chunks below
        k_ss = kr[s_idx][:, s_idx].toarray()
        lu = spla.splu(k_ii)
        k_si = kr[s_idx][:, i_idx].tocsr()
        n_s = self.surface_x.size
        m = self.shifts if circulant else 1
        if n_s % m:
            m = 1
        b = n_s // m  # surface points per shift block
        # columns of the first shift block of every component, then circulant copies
        cols = np.concatenate([np.arange(c * n_s, c * n_s + b) for c in range(len(comp))])
        block = k_ss[:, cols].copy()
        for j in range(0, cols.size, 128):  # chunked: never hold K_II⁻¹K_IS whole
            sel = cols[j:j + 128]
            block[:, j:j + 128] -= k_si @ lu.solve(k_is[:, sel].toarray())
        schur = np.empty_like(k_ss)
        nc = len(comp)
        for k in range(m):
            for c in range(nc):
                src = block[:, c * b:(c + 1) * b]  # (nc·n_s, b)
                # shift rows by k·b points within every component
                rolled = np.concatenate([np.roll(src[r * n_s:(r + 1) * n_s], k * b, axis=0) for r in range(nc)])
                schur[:, c * n_s + k * b:c * n_s + (k + 1) * b] = rolled
        schur = 0.5 * (schur + schur.T)  # symmetric up to round-off
        k_is_sparse = k_is.tocsr()

        def solve_interior(u_s):
            full = np.zeros(n)
            full[s_idx] = u_s
            full[i_idx] = -lu.solve(k_is_sparse @ u_s)
            return full

        return schur, solve_interior

    def full(self, reduced):
        """Full DOF vector (incl. right edge and base) from a reduced one."""
        return self.P @ reduced


def build_cell(nodes, length, depth, youngs_modulus, poisson_ratio, order=2, **mesh_kw):
    """Assemble the periodic bonded cell for N top nodes, period L, depth D (m), E (Pa), ν."""
    if order not in _ELEMENTS:
        raise ValueError(f"order = {order!r}: 1 (P1) or 2 (P2)")
    mesh, _top = make_mesh(nodes, length, depth, **mesh_kw)
    basis = Basis(mesh, ElementVector(_ELEMENTS[order]()))
    lam, mu = lame_parameters(youngs_modulus, poisson_ratio)
    K = asm(linear_elasticity(lam, mu), basis).tocsr()
    loc = basis.doflocs
    tol = 1e-9 * length
    comp_idx = basis.split_indices()  # [x dofs, z dofs]
    ndof = basis.N
    right = np.zeros(ndof, bool)
    partner = np.arange(ndof)
    for c in range(2):
        d = comp_idx[c]
        r = d[np.abs(loc[0, d] - length / 2) < tol]
        left = d[np.abs(loc[0, d] + length / 2) < tol]
        partner[r] = left[_match(loc[:, r], loc[:, left], tol)]
        right[r] = True
    base = np.abs(loc[1] + depth) < tol
    keep = ~right & ~base
    reduced_of = -np.ones(ndof, int)
    reduced_of[keep] = np.arange(keep.sum())
    target = reduced_of[partner]  # right edge → its left image; base (or image on base) → −1
    rows = np.flatnonzero(target >= 0)
    P = sp.csr_matrix((np.ones(rows.size), (rows, target[rows])), shape=(ndof, keep.sum()))
    # surface points: top DOFs of each component, sorted by x, right edge excluded
    dofs = []
    for c in range(2):
        d = comp_idx[c]
        d = d[(np.abs(loc[1, d]) < tol) & ~right[d]]
        d = d[np.argsort(loc[0, d])]
        dofs.append(d)
    xs = loc[0, dofs[1]]
    if not np.allclose(loc[0, dofs[0]], xs, atol=tol):
        raise RuntimeError("surface x and z DOFs are not co-located")
    surface_dofs = np.vstack([reduced_of[dofs[0]], reduced_of[dofs[1]]])
    # nodal quadrature weights: FacetBasis load vector of the constant 1 on the top facets
    top_facets = mesh.facets_satisfying(lambda x: np.abs(x[1]) < tol)
    fb = FacetBasis(mesh, _ELEMENTS[order](), facets=top_facets)
    ones = asm(LinearForm(lambda v, w: v), fb)
    scalar = Basis(mesh, _ELEMENTS[order]())
    sloc = scalar.doflocs
    # map scalar weights onto the surface points (fold the right-edge point onto x = −L/2)
    top_s = np.flatnonzero(np.abs(sloc[1]) < tol)
    w = np.zeros(xs.size)
    xs_key = np.where(np.abs(sloc[0, top_s] - length / 2) < tol, -length / 2, sloc[0, top_s])
    pos = np.searchsorted(xs, xs_key - tol)
    if np.any(np.abs(xs[np.clip(pos, 0, xs.size - 1)] - xs_key) > tol):
        raise RuntimeError("surface weights do not match the surface points")
    np.add.at(w, pos, ones[top_s])
    step = xs.size // nodes
    expected = (np.arange(nodes) - nodes // 2) * (length / nodes)
    vertex_points = np.arange(0, xs.size, step)
    # GFMD node j sits at x_j = (j − N/2) l; surface point 0 is x = −L/2 = x_0
    if not np.allclose(xs[vertex_points], expected, atol=tol):
        raise RuntimeError("top mesh vertices are not the GFMD nodes")
    return Cell(nodes=nodes, length=length, depth=depth, order=order, youngs_modulus=youngs_modulus,
                poisson_ratio=poisson_ratio, mesh=mesh, basis=basis, K=K, P=P, surface_x=xs,
                surface_dofs=surface_dofs, weights=w, vertex_points=vertex_points,
                shifts=shift_period(nodes, mesh_kw.get('min_segments', 32)))
