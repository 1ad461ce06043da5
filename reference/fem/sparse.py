"""Sparse Newton for the FE surface problem: the full reduced system, SuperLU (large N).

Units: SI (see `gfmd_contact.core.conventions`). `SurfaceProblem` condenses the linear
interior onto the surface with a dense Schur complement S and factors a dense
tangent every Newton iteration: for P2 at N = 4096 (8192 surface points) that is
a 8192² matrix (0.5 GB) and ~4·10¹¹ flops per factorization.
`SparseSurfaceProblem` solves the same equations with the same algorithms
(Newton, backtracking, trust-region energy descent, pseudo-transient continuation,
inherited unchanged) but
never forms S:

* unknowns: the same surface vector u (component-major, as in `SurfaceProblem`);
* S u = K_ss u − K_si K_ii⁻¹ K_is u, with K_r = Pᵀ K P the reduced stiffness and
  K_ii its interior block, factored once (SuperLU) — a `LinearOperator`;
* tangent: the full reduced matrix J_r = K_r + E B Eᵀ, where B is the law's
  surface part (diagonal for the normal law, 2×2 blocks per point for the
  coupled law, `SurfaceProblem.surface_tangent`) and E scatters surface
  unknowns into the reduced DOFs. Solving J_r [x; du] = [0; b] gives exactly
  (S + B) du = b, the dense Newton step; J_r is factored with SuperLU
  (`scipy.sparse.linalg.splu`, symmetric mode) per solve, or, with
  `lagged=True`, reused as a GMRES preconditioner for later tangents until
  GMRES needs more than `GMRES_RESTART` iterations;
* stability (`stable`): the criterion of `solver.locally_stable` without dense
  matrices. sym(J_r) has the inertia of K_ii (positive definite) plus that of
  its Schur complement sym(S + B), so sym(S + B) is positive definite iff all
  pivots of an unpivoted (symmetric-mode, diagonal-pivot) LU of sym(J_r) are
  positive (Sylvester's law of inertia). Coupled law, when sym(S + B) is not
  positive definite: all eigenvalues of W⁻¹(S + B) with Re λ ≤ 0 lie in a box
  given by Bendixson's theorem (`_bendixson_box`); ARPACK (shift-invert left of
  the box, through a factored shifted J_r) finds the eigenvalues nearest the box
  until they provably include every eigenvalue in it (RuntimeError if that
  needs more than STABILITY_EIGENVALUES_MAX of them).

`choose_linear("auto", N, components)` (used by `solver.run_realization(linear=...)`)
picks dense while N·components ≤ DENSE_MAX_NODES = 2048 (components = 2 for the
coupled law, whose dense system is twice as large) and sparse above. Measured
(docs/design/performance.md, normal law, s per load step, dense /
sparse): P2 0.98 / 3.1 at N = 1024, 5.6 / 6.6 at 2048, 34 / 16 at 4096; P1
0.16 / 0.48, 1.05 / 0.97, 6.0 / 2.3: break-even at N = 2048, where dense also
needs slightly more memory (P2: 1.3 GB vs 1.2 GB; 3.2 vs 2.3 GB at 4096).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .solver import SurfaceProblem

DENSE_MAX_NODES = 2048  # "auto": dense while N × components ≤ this (measured break-even), sparse above
GMRES_RESTART = 30  # lagged mode: GMRES iterations allowed before refactoring
GMRES_RTOL = 1e-12  # lagged mode: relative residual of the linear solve
STABILITY_EIGENVALUES = 6  # coupled law: first count of eigenvalues of W⁻¹J computed (×4 until conclusive)
STABILITY_EIGENVALUES_MAX = 384  # coupled law: give up (RuntimeError) beyond this count
DIAGONAL_PIVOT_THRESHOLD = 0.01  # SuperLU: keep the diagonal pivot unless < 1 % of the column's largest


LINEAR_CHOICES = ("auto", "dense", "sparse", "sparse-lagged")


def choose_linear(linear, nodes, components=1):
    """'dense', 'sparse' or 'sparse-lagged' for `linear` (one of LINEAR_CHOICES), N top nodes and the
    number of displacement components solved at the surface (1: normal law, 2: coupled law)."""
    if linear not in LINEAR_CHOICES:
        raise ValueError(f"linear = {linear!r}: one of {', '.join(map(repr, LINEAR_CHOICES))}")
    if linear == "auto":
        return "dense" if nodes * components <= DENSE_MAX_NODES else "sparse"
    return linear


def make_problem(linear, scene, h, order=2, mesh_kw=None, quadrature="nodal", tangential=None):
    """The surface problem of `scene` with heights h (m) for the linear-solver choice `linear`.

    quadrature="gauss" (`SurfaceProblem`) is implemented on the dense path only: ValueError otherwise.
    tangential: u_x solved (default: wherever c > 0; `gfmd_contact.core.model` decides in run_realization).
    """
    if tangential is None:
        tangential = scene.interface.tangential_ratio > 0
    kind = choose_linear(linear, scene.surface.nodes, 2 if tangential else 1)
    if kind == "dense":
        return SurfaceProblem(scene, h, order=order, mesh_kw=mesh_kw, quadrature=quadrature, tangential=tangential)
    if quadrature != "nodal":
        raise ValueError(f"quadrature = {quadrature!r} needs linear='dense' (the sparse path, here {kind!r} from "
                         f"linear={linear!r}, assumes the nodal quadrature's block-diagonal law tangent)")
    return SparseSurfaceProblem(scene, h, order=order, mesh_kw=mesh_kw, lagged=kind == "sparse-lagged",
                                tangential=tangential)


def _factor(matrix, diag_pivot_thresh=DIAGONAL_PIVOT_THRESHOLD):
    """SuperLU factorization (symmetric mode, minimum degree on A + Aᵀ); singular → LinAlgError.

    The tangents are structurally symmetric (symmetric for the normal law), so
    SuperLU's symmetric mode with a small diagonal-pivot threshold keeps the
    fill of a symmetric ordering (P2, N = 4096: 3.7·10⁷ nonzeros in L + U,
    factor 2.5 s, vs 6.4·10⁷ and 3.8 s with the default COLAMD, measured).
    """
    try:
        return spla.splu(matrix, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=diag_pivot_thresh,
                         options={"SymmetricMode": True})
    except RuntimeError as exc:  # "Factor is exactly singular"
        raise scipy.linalg.LinAlgError(f"sparse tangent is singular: {exc}") from exc


def positive_definite(symmetric_matrix):
    """True if the sparse symmetric matrix is positive definite (signs of unpivoted LU pivots)."""
    try:
        lu = _factor(symmetric_matrix.tocsc(), diag_pivot_thresh=0.0)
    except scipy.linalg.LinAlgError:
        return False
    if not np.array_equal(lu.perm_r, lu.perm_c):  # a zero diagonal pivot was skipped: not definite
        return False
    pivots = lu.U.diagonal()
    return bool(np.all(np.isfinite(pivots)) and np.all(pivots > 0))


class SparseSurfaceProblem(SurfaceProblem):
    """`SurfaceProblem` with sparse linear algebra on the full reduced system (module docstring).

    lagged: reuse the last SuperLU factorization as a GMRES preconditioner.
    `stats` counts factorizations, direct solves and GMRES iterations.
    """

    linear_solver = "SuperLU on the full reduced system"

    def __init__(self, scene, h, order=2, mesh_kw=None, lagged=False, tangential=None):
        self.lagged = lagged
        self._lu = None  # (matrix, SuperLU) of the last factored tangent
        self.stats = {"factorizations": 0, "direct_solves": 0, "gmres_solves": 0, "gmres_iterations": 0}
        if lagged:
            self.linear_solver += " (lagged factorization + GMRES)"
        super().__init__(scene, h, order=order, mesh_kw=mesh_kw, tangential=tangential)

    def condense(self, comps):
        """(S as a LinearOperator, solve_interior) without forming S; sets the reduced-system blocks."""
        cell = self.cell
        kr = cell.reduced_stiffness.tocsr()
        n = kr.shape[0]
        s_idx = np.concatenate([cell.surface_dofs[("x", "z").index(c)] for c in comps])
        interior = np.ones(n, bool)
        interior[s_idx] = False
        i_idx = np.flatnonzero(interior)
        k_ii = kr[i_idx][:, i_idx].tocsc()
        k_is = kr[i_idx][:, s_idx].tocsr()
        k_si = kr[s_idx][:, i_idx].tocsr()
        k_ss = kr[s_idx][:, s_idx].tocsr()
        lu_ii = _factor(k_ii)
        self.reduced = kr.tocsc()
        self.surface_index = s_idx

        def apply_schur(u):
            return k_ss @ u - k_si @ lu_ii.solve(k_is @ u)

        def solve_interior(u_s):
            full = np.zeros(n)
            full[s_idx] = u_s
            full[i_idx] = -lu_ii.solve(k_is @ u_s)
            return full

        schur = spla.LinearOperator((s_idx.size, s_idx.size), matvec=apply_schur, dtype=float)
        return schur, solve_interior

    def _scatter(self, rows, cols, values):
        """Surface entries (unknowns' indexing) as a sparse matrix on the reduced DOFs."""
        n = self.reduced.shape[0]
        s = self.surface_index
        return sp.csc_matrix((values, (s[rows], s[cols])), shape=(n, n))

    def jacobian(self, u, z_ind, shift=None):
        """Full reduced tangent J_r = K_r + E B Eᵀ (+ E diag(shift) Eᵀ), sparse (Pa)."""
        rows, cols, values = self.surface_tangent(u, z_ind)
        if shift is not None:
            diag = np.arange(self.surface_index.size)
            rows, cols = np.concatenate([rows, diag]), np.concatenate([cols, diag])
            values = np.concatenate([values, np.broadcast_to(shift, diag.shape)])
        return (self.reduced + self._scatter(rows, cols, values)).tocsc()

    def _full_rhs(self, rhs):
        b = np.zeros(self.reduced.shape[0])
        b[self.surface_index] = rhs
        return b

    def solve_linear(self, J, rhs):
        """(S + B) du = rhs through J_r [x; du] = [0; rhs]; LinAlgError if J_r is singular."""
        b = self._full_rhs(rhs)
        if not np.all(np.isfinite(J.data)):
            raise scipy.linalg.LinAlgError("sparse tangent has non-finite entries")
        if self.lagged and self._lu is not None and self._lu[0] is not J:
            x = self._gmres(J, b)
            if x is not None:
                return x[self.surface_index]
        if self._lu is None or self._lu[0] is not J:
            self._lu = (J, _factor(J))
            self.stats["factorizations"] += 1
        self.stats["direct_solves"] += 1
        x = self._lu[1].solve(b)
        if not np.all(np.isfinite(x)):
            raise scipy.linalg.LinAlgError("sparse solve produced non-finite values (singular tangent)")
        return x[self.surface_index]

    def _gmres(self, J, b):
        """GMRES on J x = b preconditioned by the last factorization; None if it does not converge."""
        lu = self._lu[1]
        precond = spla.LinearOperator(J.shape, matvec=lu.solve, dtype=float)
        count = [0]

        def callback(_):
            count[0] += 1

        x, info = spla.gmres(J, b, M=precond, rtol=GMRES_RTOL, atol=0.0, restart=GMRES_RESTART, maxiter=1,
                             callback=callback, callback_type="pr_norm")
        self.stats["gmres_iterations"] += count[0]
        if info != 0 or not np.all(np.isfinite(x)):
            return None
        self.stats["gmres_solves"] += 1
        return x

    def stable(self, u, z_ind):
        """Local stability of the equilibrium u, sparse version of `solver.locally_stable` (module docstring)."""
        J = self.jacobian(u, z_ind)
        if not self.tangential:
            return positive_definite(J)
        if positive_definite(0.5 * (J + J.T)):
            return True
        return self._eigenvalues_positive(u, z_ind)

    def _bendixson_box(self, u, z_ind):
        """(β, ρ): every eigenvalue λ of W⁻¹(S + B) has Re λ > β and |Im λ| ≤ ρ (Pa/m).

        Bendixson: Re λ lies within the spectrum of the symmetric part of
        A = W^-½(S + B)W^-½ and |Im λ| within that of its skew part. S is symmetric
        positive definite and B is block-diagonal (2×2 per surface point, both
        components weighted by the same w), so Re λ > min eig of the blocks' symmetric
        parts / w and |Im λ| ≤ max |B_xz − B_zx| / (2w).
        """
        rows, cols, values = self.surface_tangent(u, z_ind)
        ns = self.ns
        block = np.zeros((ns, 2, 2))
        block[rows % ns, rows // ns, cols // ns] = values / self.wt[rows]
        sym = 0.5 * (block + block.transpose(0, 2, 1))
        beta = float(np.min(np.linalg.eigvalsh(sym)))
        rho = float(np.max(np.abs(block[:, 0, 1] - block[:, 1, 0]))) / 2
        return beta, rho

    def _eigenvalues_positive(self, u, z_ind):
        """Coupled law: every eigenvalue of W⁻¹(S + B) has Re λ > 0 (module docstring).

        Eigenvalues with Re λ ≤ 0 lie in the box β ≤ Re λ ≤ 0, |Im λ| ≤ ρ
        (`_bendixson_box`); ARPACK in shift-invert mode at σ < β returns the
        eigenvalues nearest σ, and once the farthest of them lies outside the disc
        around σ that covers the box, no eigenvalue in the box was missed.
        """
        beta, rho = self._bendixson_box(u, z_ind)
        if beta >= 0:
            return True
        sigma = 1.01 * beta
        radius = float(np.hypot(sigma, rho))
        try:
            lu = _factor(self.jacobian(u, z_ind, shift=-sigma * self.wt))
        except scipy.linalg.LinAlgError:
            return False  # σ is an eigenvalue, Re σ < 0
        s, wt = self.surface_index, self.wt
        n_s = s.size

        def shifted_inverse_times_w(v):  # (S + B − σW)⁻¹ W v: eigenvalues 1/(λ − σ)
            return lu.solve(self._full_rhs(wt * v))[s]

        op = spla.LinearOperator((n_s, n_s), matvec=shifted_inverse_times_w, dtype=float)
        k = STABILITY_EIGENVALUES
        while True:
            k = min(k, n_s - 2)
            mu = spla.eigs(op, k=k, which="LM", return_eigenvectors=False, tol=1e-10)
            lam = sigma + 1.0 / mu
            if not np.all(np.isfinite(lam)) or np.any(lam.real <= 0):
                return False
            if np.max(np.abs(lam - sigma)) > radius:
                return True  # every eigenvalue in the box is nearer σ than the ones found
            if k >= min(STABILITY_EIGENVALUES_MAX, n_s - 2):
                raise RuntimeError(
                    f"stability check inconclusive: the {k} eigenvalues of W⁻¹J nearest σ = {sigma:.3g} Pa/m have "
                    f"Re λ > 0 but do not cover the box Re λ ≥ {beta:.3g}, |Im λ| ≤ {rho:.3g} Pa/m; "
                    "use linear='dense' for this scene")
            k *= 4
