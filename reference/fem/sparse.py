"""Sparse Newton for the FE surface problem: the full reduced system, SuperLU (issue #4, large N).

Units: SI (see `gfmd.conventions`). `SurfaceProblem` condenses the linear
interior onto the surface with a dense Schur complement S and factors a dense
tangent every Newton iteration: for P2 at N = 4096 (8192 surface points) that is
a 8192² matrix (0.5 GB) and ~4·10¹¹ flops per factorization.
`SparseSurfaceProblem` solves the same equations with the same algorithms
(Newton, backtracking, pseudo-transient continuation, inherited unchanged) but
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
  positive definite: the `STABILITY_EIGENVALUES` eigenvalues of W⁻¹(S + B)
  nearest to 0 (ARPACK, shift-invert at 0 through the factored J_r) must have
  positive real parts — exact for a real eigenvalue crossing 0 (fold), but a
  complex pair crossing the imaginary axis far from 0 would be missed
  (the dense path computes all eigenvalues).

`choose_linear("auto", N)` (used by `solver.run_realization(linear=...)`) picks dense for N ≤ DENSE_MAX_NODES and sparse above
(at N = 1024, P2, a dense Newton iteration costs less than a sparse one;
benchmarks/results/bench_fe_vs_gfmd.md).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .solver import SurfaceProblem

DENSE_MAX_NODES = 1024  # "auto": dense condensation up to this N, sparse above
GMRES_RESTART = 30  # lagged mode: GMRES iterations allowed before refactoring
GMRES_RTOL = 1e-12  # lagged mode: relative residual of the linear solve
STABILITY_EIGENVALUES = 6  # coupled law: eigenvalues of W⁻¹J checked near 0
DIAGONAL_PIVOT_THRESHOLD = 0.01  # SuperLU: keep the diagonal pivot unless < 1 % of the column's largest


LINEAR_CHOICES = ("auto", "dense", "sparse", "sparse-lagged")


def choose_linear(linear, nodes):
    """'dense', 'sparse' or 'sparse-lagged' for `linear` (one of LINEAR_CHOICES) and N top nodes."""
    if linear not in LINEAR_CHOICES:
        raise ValueError(f"linear = {linear!r}: one of {', '.join(map(repr, LINEAR_CHOICES))}")
    if linear == "auto":
        return "dense" if nodes <= DENSE_MAX_NODES else "sparse"
    return linear


def make_problem(linear, scene, h, order=2, mesh_kw=None):
    """The surface problem of `scene` with heights h (m) for the linear-solver choice `linear`."""
    kind = choose_linear(linear, scene.surface.nodes)
    if kind == "dense":
        return SurfaceProblem(scene, h, order=order, mesh_kw=mesh_kw)
    return SparseSurfaceProblem(scene, h, order=order, mesh_kw=mesh_kw, lagged=kind == "sparse-lagged")


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

    def __init__(self, scene, h, order=2, mesh_kw=None, lagged=False):
        self.lagged = lagged
        self._lu = None  # (matrix, SuperLU) of the last factored tangent
        self.stats = {"factorizations": 0, "direct_solves": 0, "gmres_solves": 0, "gmres_iterations": 0}
        if lagged:
            self.linear_solver += " (lagged factorization + GMRES)"
        super().__init__(scene, h, order=order, mesh_kw=mesh_kw)

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
        return self._eigenvalues_near_zero_positive(J)

    def _eigenvalues_near_zero_positive(self, J):
        """Coupled law: the eigenvalues of W⁻¹(S + B) nearest 0 all have Re λ > 0."""
        try:
            lu = _factor(J)
        except scipy.linalg.LinAlgError:
            return False  # λ = 0
        s, wt = self.surface_index, self.wt
        n_s = s.size

        def inverse_times_w(v):  # (S + B)⁻¹ W v, whose eigenvalues are 1/λ
            return lu.solve(self._full_rhs(wt * v))[s]

        op = spla.LinearOperator((n_s, n_s), matvec=inverse_times_w, dtype=float)
        k = min(STABILITY_EIGENVALUES, n_s - 2)
        mu = spla.eigs(op, k=k, which="LM", return_eigenvectors=False, tol=1e-10)
        return bool(np.all(np.isfinite(mu)) and np.all((1.0 / mu).real > 0.0))
