"""The coupled chains' local-stability test of a converged state (`gfmd.chains`): the tangent's eigenvalues nearest 0.

A coupled equilibrium is kept only where it is locally stable: every eigenvalue of the tangent J = K + D
(`gfmd.problem.coupled_operators`; D the nodal 2×2 law tangent, ∂f/∂u = −J) has Re λ > 0 — the FE reference's test
(`reference.fem.solver.locally_stable`, W⁻¹J with uniform nodal weights here) restricted to the eigenvalues that a
fold or a slip instability sends through 0. Shift-invert Arnoldi (ARPACK: scipy's eigs) on J⁻¹ finds them; each
solve J x = b is the coupled Newton's (`gfmd.coupled_krylov.newton_step`: GMRES right-preconditioned by K⁻¹ balanced
by the coarse space on the stiff nodes, one FFT pair per product, `gfmd.gmres`) to a relative tolerance
STABILITY_RTOL.

`SOLVER` = "scipy" runs each solve with the earlier solver: scipy's GMRES (restart STABILITY_GMRES_RESTART, its
Gram–Schmidt a Python loop over 2N-vectors) preconditioned by the FIRE mass M⁻¹ alone, about 8× slower at 2^17
(docs/design/solvers.md). Each solve
builds the Newton's coarse space anew (≈ 0.02 s at 2^17, 1 % of the test: not worth a second entry point).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigs, gmres

from .coupled_krylov import newton_step
from .fft import Fft
from .problem import coupled_operators, stiffness_operator

#: eigenvalues of the tangent nearest 0 that `coupled_stability` computes (shift-invert Arnoldi)
COUPLED_STABILITY_EIGENVALUES = 6
#: each solve of the shift-invert operator: GMRES to this relative tolerance, with this restart and at most this
#: many cycles
STABILITY_RTOL = 1e-8
STABILITY_GMRES_RESTART = 120
STABILITY_GMRES_CYCLES = 20
#: "newton": the coupled Newton's two-level GMRES (`gfmd.coupled_krylov.newton_step`); "scipy": scipy's GMRES
#: preconditioned by M⁻¹ (the earlier test)
SOLVER = "newton"


def coupled_stability(model, law, z_ind, u_hat):
    """Smallest Re λ (Pa/m) among the COUPLED_STABILITY_EIGENVALUES eigenvalues nearest 0 of the tangent J = K + D at
    u_hat (None if Arnoldi found none): module docstring."""
    fft = Fft(model.nodes, grid=model.grid)
    u = fft.irfft(u_hat)
    a_op, m_op, project = coupled_operators(model, law, z_ind, u, fft)
    shape = (model.components, model.nodes)
    if SOLVER == "newton":
        solve = _newton_solve(model, law, z_ind, u, fft, project, shape)
    elif SOLVER == "scipy":
        def solve(b):
            x, _ = gmres(a_op, project(b.reshape(shape)).ravel(), M=m_op, rtol=STABILITY_RTOL,
                         restart=STABILITY_GMRES_RESTART, maxiter=STABILITY_GMRES_CYCLES)
            return x
    else:
        raise ValueError(f"gfmd.coupled_stability.SOLVER = {SOLVER!r}: expected 'newton' or 'scipy'")
    inverse = LinearOperator(a_op.shape, matvec=solve, dtype=float)
    k = COUPLED_STABILITY_EIGENVALUES
    try:
        mu = eigs(inverse, k=k, which="LM", return_eigenvectors=False, tol=1e-4, maxiter=100 * k)
    except ArpackNoConvergence as exc:
        mu = exc.eigenvalues
    mu = np.asarray(mu)
    mu = mu[np.isfinite(mu) & (np.abs(mu) > 0)]
    return float(np.min((1.0 / mu).real)) if mu.size else None


def _newton_solve(model, law, z_ind, u, fft, project, shape):
    """b ↦ J⁻¹ b on the nodes (b made mean-free where the half-plane clamps the mean) by `newton_step`."""
    stiff = stiffness_operator(model)
    clamp = model.half_plane

    def solve(b):
        f = np.ascontiguousarray(project(b.reshape(shape)))
        f_hat = fft.rfft(f)
        if clamp:
            f_hat[:, 0] = 0.0
        du_hat, _ = newton_step(model, law, z_ind, u, f_hat, stiff, fft, STABILITY_RTOL, STABILITY_GMRES_RESTART,
                                STABILITY_GMRES_CYCLES, f)
        return fft.irfft(du_hat).ravel()

    return solve
