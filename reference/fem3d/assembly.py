"""Linear elasticity of the periodic bonded 3-D cell: scikit-fem assembly, periodicity, condensation.

Units: SI (see `gfmd_contact.core.conventions`). Only scikit-fem, numpy and scipy: no elastic kernel of the
core (the FE is what checks them). Trilinear hexahedra (`skfem.ElementHex1`, vector), stiffness of
`skfem.models.elasticity.linear_elasticity`. Periodicity: the DOFs of the image vertices x = Lx and
y = Ly are eliminated onto those of x = 0, y = 0 by an explicit 0/1 projection P (K_r = Pᵀ K P), as
`reference.fem.assembly` does in 2-D; the base z = −D is bonded (u = 0, its DOFs removed). Reduced
DOF of component c (x, y, z) at vertex (i, j, k), k the layer counted from the top (k = 0 surface):
3((k Nx + i) Ny + j) + c.

The lateral spacing is uniform, so K_r is block circulant in (i, j): the row of vertex (i, j, k)
is the row of (0, 0, k) shifted. Its stencil (couplings to i ± 1, j ± 1 and the layers k, k ± 1)
does not depend on Nx, Ny ≥ 3, so it is assembled once on a 3 × 3 cell with the same spacings
(`stencil`), and K_r is block diagonal in the lateral Fourier modes (m, n) (exact, the FE's own
matrix): K̂(m, n)[(k,c), (k',c')] = Σ K_r[(0,0,k,c), (i',j',k',c')] e^{2πi(m i'/Nx + n j'/Ny)},
one 3n_z × 3n_z Hermitian block per mode. Normal-only surface (frictionless interface,
t_x = t_y = 0): the surface u_x, u_y are free and condensed with the interior, per mode

    Ŝ(m, n) = K̂_ss − K̂_si K̂_ii⁻¹ K̂_is,   s = (k = 0, c = z)   (N/m),

and the dense surface stiffness S (N/m per m of u_z, Nx·Ny square) is the doubly circulant matrix
of the column s(i, j) = ifft2(Ŝ) (`Cell3D.stiffness`). `direct_surface_column` computes the same
column from the full sparse matrix (SuperLU) for the check (tests/test_fem3d_stiffness.py).
The boundary term's nodal weights W are the FacetBasis load vector of the constant 1 on the top
facets (= the node area lx·ly on this uniform grid: nodal quadrature, GFMD's node collocation).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from skfem import Basis, ElementHex1, ElementVector, FacetBasis, LinearForm, MeshHex1, asm
from skfem.models.elasticity import lame_parameters, linear_elasticity

from .mesh import graded_depths

#: lateral Fourier modes condensed per batch (bounds the memory of the batched dense solves)
MODES_PER_BATCH = 512


def _check_material(youngs_modulus, poisson_ratio):
    if not (np.isfinite(youngs_modulus) and youngs_modulus > 0):
        raise ValueError(f"youngs_modulus = {youngs_modulus!r}: must be a positive Young's modulus (Pa)")
    if not -1.0 < poisson_ratio < 0.5:
        raise ValueError(f"poisson_ratio = {poisson_ratio!r}: must lie in (−1, 0.5) (a compressible solid)")


def periodic_cell(shape, spacing, z_levels, youngs_modulus, poisson_ratio):
    """(mesh, basis, K, P): the sparse FE system of an Nx × Ny periodic cell (module docstring).

    shape: (Nx, Ny); spacing: (lx, ly) (m); z_levels: vertex layers, 0 first, down to −D (m).
    """
    nx, ny = shape
    nz = len(z_levels) - 1
    mesh = MeshHex1.init_tensor(np.arange(nx + 1) * spacing[0], np.arange(ny + 1) * spacing[1], z_levels[::-1])
    basis = Basis(mesh, ElementVector(ElementHex1()))
    K = asm(linear_elasticity(*lame_parameters(youngs_modulus, poisson_ratio)), basis).tocsr()
    i = np.rint(mesh.p[0] / spacing[0]).astype(int) % nx
    j = np.rint(mesh.p[1] / spacing[1]).astype(int) % ny
    k = np.argmin(np.abs(mesh.p[2][:, None] - np.asarray(z_levels)[None, :]), axis=1)
    vertex = np.where(k < nz, (k * nx + i) * ny + j, -1)  # reduced vertex; −1 on the bonded base
    rows = np.concatenate([basis.nodal_dofs[c, vertex >= 0] for c in range(3)])
    cols = np.concatenate([3 * vertex[vertex >= 0] + c for c in range(3)])
    P = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(basis.N, 3 * nz * nx * ny))
    return mesh, basis, K, P


def stencil(spacing, z_levels, youngs_modulus, poisson_ratio):
    """Rows of K_r for the vertices (0, 0, k) on a 3 × 3 cell: (rows (3n_z, 3·9·n_z) dense, di, dj, k', c')."""
    _, _, K, P = periodic_cell((3, 3), spacing, z_levels, youngs_modulus, poisson_ratio)
    kr = (P.T @ K @ P).tocsr()
    nz = len(z_levels) - 1
    own = 3 * (np.arange(nz)[:, None] * 9) + np.arange(3)[None, :]  # DOFs of (0, 0, k), c
    rows = kr[own.ravel()].toarray()
    col = np.arange(kr.shape[1])
    vert, comp = col // 3, col % 3
    layer, i, j = vert // 9, (vert // 3) % 3, vert % 3
    return rows, np.where(i == 2, -1, i), np.where(j == 2, -1, j), layer, comp


@dataclass
class Cell3D:
    """The condensed periodic cell (module docstring). Surface arrays are (Nx, Ny) or flattened C order."""

    shape: tuple  # (Nx, Ny)
    lengths: tuple  # (Lx, Ly) (m)
    depth: float  # D (m)
    youngs_modulus: float
    poisson_ratio: float
    z_levels: np.ndarray  # vertex layers, 0 first (m)
    mode_stiffness: np.ndarray  # Ŝ(m, n) (N/m), (Nx, Ny), real
    interior_response: np.ndarray  # K̂_ii⁻¹ K̂_is per mode, (Nx, Ny, 3n_z − 1) complex
    weights: np.ndarray  # (Nx·Ny,) nodal quadrature weights (m²)
    _cache: dict = field(default_factory=dict, repr=False)

    @property
    def spacing(self):
        return (self.lengths[0] / self.shape[0], self.lengths[1] / self.shape[1])

    @property
    def layers(self):
        return len(self.z_levels) - 1

    @property
    def dofs(self):
        """Unknowns of the reduced FE system (periodic, base removed): 3·Nx·Ny·n_z."""
        return 3 * self.shape[0] * self.shape[1] * self.layers

    def surface_column(self):
        """Column of S for node (0, 0), shaped (Nx, Ny) (N/m): s = ifft2(Ŝ)."""
        return np.fft.ifft2(self.mode_stiffness).real

    def stiffness(self):
        """Dense S (Nx·Ny square, N/m), doubly circulant from `surface_column`."""
        if "S" not in self._cache:
            col = self.surface_column()
            nx, ny = self.shape
            i, j = np.divmod(np.arange(nx * ny), ny)
            s = col[(i[:, None] - i[None, :]) % nx, (j[:, None] - j[None, :]) % ny]
            self._cache["S"] = 0.5 * (s + s.T)
        return self._cache["S"]

    def displacement_field(self, u_z):
        """u (3, n_z + 1, Nx, Ny) (m) at every vertex layer (the base last, 0) for surface u_z (Nx, Ny):
        the linear interior, x̂ = −K̂_ii⁻¹ K̂_is û_z per mode."""
        nx, ny = self.shape
        uz_hat = np.fft.fft2(np.asarray(u_z, dtype=float).reshape(nx, ny))
        rest = -self.interior_response * uz_hat[..., None]  # (Nx, Ny, 3nz − 1): the unknowns other than s
        full_hat = np.concatenate([rest[..., :2], uz_hat[..., None], rest[..., 2:]], axis=-1)
        full = np.fft.ifft2(full_hat, axes=(0, 1)).real.reshape(nx, ny, self.layers, 3)
        u = np.zeros((3, self.layers + 1, nx, ny))
        u[:, :-1] = full.transpose(3, 2, 0, 1)
        return u


def build_cell(nodes_x, nodes_y, length_x, length_y, depth, youngs_modulus, poisson_ratio, layers=None, top=None):
    """Assemble and condense the periodic bonded cell: Nx × Ny surface nodes, periods Lx, Ly, thickness D (m).

    layers / top: depth grading (`reference.fem3d.mesh.graded_depths`; top defaults to min(lx, ly)).
    """
    _check_material(youngs_modulus, poisson_ratio)
    for key, n in (("nodes_x", nodes_x), ("nodes_y", nodes_y)):
        if int(n) != n or n < 2:
            raise ValueError(f"{key} = {n!r}: the 3-D FE needs at least 2 surface nodes per direction")
    for key, v in (("length_x", length_x), ("length_y", length_y)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{key} = {v!r}: must be a finite positive period (m)")
    nx, ny = int(nodes_x), int(nodes_y)
    spacing = (length_x / nx, length_y / ny)
    z_levels = graded_depths(depth, layers, min(spacing) if top is None else top)
    nz = len(z_levels) - 1
    rows, di, dj, layer, comp = stencil(spacing, z_levels, youngs_modulus, poisson_ratio)
    m = np.fft.fftfreq(nx) * nx
    n = np.fft.fftfreq(ny) * ny
    target = 3 * layer + comp  # the (k', c') index of each stencil column
    s_index = 2  # (k = 0, c = z)
    others = np.delete(np.arange(3 * nz), s_index)
    modes = np.stack(np.meshgrid(m, n, indexing="ij"), -1).reshape(-1, 2)
    mode_stiffness = np.empty(nx * ny)
    response = np.empty((nx * ny, 3 * nz - 1), complex)
    used = np.flatnonzero(np.any(rows != 0, axis=0))
    for start in range(0, modes.shape[0], MODES_PER_BATCH):
        mm = modes[start:start + MODES_PER_BATCH]
        phase = np.exp(2j * np.pi * (mm[:, :1] * di[used] / nx + mm[:, 1:] * dj[used] / ny))  # (b, cols)
        block = np.zeros((mm.shape[0], 3 * nz, 3 * nz), complex)
        for col_pos, col in enumerate(used):
            block[:, :, target[col]] += phase[:, col_pos, None] * rows[None, :, col]
        k_ii = block[:, others][:, :, others]
        k_is = block[:, others, s_index]
        x = np.linalg.solve(k_ii, k_is[..., None])[..., 0]
        schur = block[:, s_index, s_index] - np.einsum("bi,bi->b", block[:, s_index, others], x)
        mode_stiffness[start:start + mm.shape[0]] = schur.real
        response[start:start + mm.shape[0]] = x
    return Cell3D(shape=(nx, ny), lengths=(float(length_x), float(length_y)), depth=float(depth),
                  youngs_modulus=float(youngs_modulus), poisson_ratio=float(poisson_ratio), z_levels=z_levels,
                  mode_stiffness=mode_stiffness.reshape(nx, ny), interior_response=response.reshape(nx, ny, -1),
                  weights=surface_weights((nx, ny), spacing, z_levels))


def surface_weights(shape, spacing, z_levels):
    """Nodal weights W (m²) of the top nodes: FacetBasis load vector of 1 on a cell of this spacing, folded."""
    nx, ny = shape
    small = (min(nx, 3), min(ny, 3))
    mesh = MeshHex1.init_tensor(np.arange(small[0] + 1) * spacing[0], np.arange(small[1] + 1) * spacing[1],
                                np.asarray(z_levels[:2])[::-1])
    tol = 1e-9 * abs(z_levels[1])
    fb = FacetBasis(mesh, ElementHex1(), facets=mesh.facets_satisfying(lambda x: np.abs(x[2]) < tol))
    ones = asm(LinearForm(lambda v, w: v), fb)
    top = np.abs(mesh.p[2]) < tol
    i = np.rint(mesh.p[0, top] / spacing[0]).astype(int) % small[0]
    j = np.rint(mesh.p[1, top] / spacing[1]).astype(int) % small[1]
    w = np.zeros(small)
    np.add.at(w, (i, j), ones[top])
    if not np.allclose(w, w.flat[0], rtol=1e-12):
        raise RuntimeError("top nodal weights are not uniform on a uniform grid")
    return np.full(nx * ny, w.flat[0])


def direct_surface_column(nodes_x, nodes_y, length_x, length_y, z_levels, youngs_modulus, poisson_ratio):
    """Column (0, 0) of S from the full sparse system (SuperLU), (Nx, Ny) (N/m): the check of `build_cell`."""
    nx, ny = nodes_x, nodes_y
    _, _, K, P = periodic_cell((nx, ny), (length_x / nx, length_y / ny), z_levels, youngs_modulus, poisson_ratio)
    kr = (P.T @ K @ P).tocsc()
    s_idx = 3 * np.arange(nx * ny) + 2  # u_z of layer k = 0
    mask = np.ones(kr.shape[0], bool)
    mask[s_idx] = False
    k_ii = kr[mask][:, mask].tocsc()
    k_is0 = kr[mask][:, [s_idx[0]]].toarray().ravel()
    x = spla.splu(k_ii).solve(k_is0)
    col = kr[s_idx][:, [s_idx[0]]].toarray().ravel() - kr[s_idx][:, mask] @ x
    return col.reshape(nx, ny)
