"""The coupled law's linearised balance (seed Eq. 2) solved by GMRES (`gfmd.gmres`), shared by the algorithms that
take Newton-type steps on it: `gfmd.algorithms.coupled_newton` (K + D, `newton_direction`: the two-level
preconditioner of `gfmd.coupled_preconditioner` on the nodes, δu and K δu nodal; `newton_step`, its spectrum,
for `gfmd.coupled_stability`) and `gfmd.algorithms.coupled_ptc` (σM + K + D, σ = 1/Δτ, `spectral_step`:
K⁻¹-type on the spectrum). Not an algorithm itself (no `solve`): each algorithm passes its stiffness operator.
"""

from __future__ import annotations

import numpy as np

from scipy.sparse.linalg import LinearOperator, gmres

from gfmd_contact.core import laws

from . import coupled_preconditioner
from . import gmres as gfmd_gmres
from .coupled_kernels import coupled_kernels, divided_blocks
from .fft import Fft, spectral_weights
from .problem import stiffness_operator

#: GMRES: restart length and the most restart cycles of one solve
GMRES_RESTART = 60
GMRES_CYCLES = 5
#: which GMRES solves the spectral step: "gfmd" (`gfmd.gmres`: modified Gram–Schmidt in one fused pass, a float32
#: basis at the Newton steps' tolerances; measured, docs/design/performance.md) or "scipy"
#: (`scipy.sparse.linalg.gmres`, the earlier solver)
GMRES = "gfmd"
#: inexact Newton's forcing rule (`forcing`): GMRES's relative tolerance
#: min(FORCING, max(η, FORCING_MIN, 0.3 tolerance / residual))
FORCING = 0.1
FORCING_MIN = 1e-3
#: η: Eisenstat & Walker's choice 2 (SIAM J. Sci. Comput. 17, 16 (1996), Eq. 2.6), η_k = γ (‖F_k‖/‖F_k−1‖)^α,
#: η_0 = FORCING; their safeguard (η_k ≥ γ η_k−1^α where that exceeds 0.1) never binds under η ≤ FORCING = 0.1
EW_GAMMA = 0.9
EW_ALPHA = 2.0


def eisenstat_walker(residual, previous=None):
    """η of the next GMRES solve from this and the previous Newton residual (any one norm): FORCING at the first
    iteration (previous None), else γ (residual/previous)^α, at most FORCING: loose while Newton converges
    linearly, tight once it converges quadratically."""
    if previous is None or previous <= 0.0:
        return FORCING
    return min(FORCING, EW_GAMMA * (residual / previous) ** EW_ALPHA)


def forcing(tolerance, residual, eta=0.0):
    """GMRES's relative tolerance for a step at `residual` (p_ref units): no accuracy beyond what the stop needs
    (0.3 tolerance / residual), nor beyond η (`eisenstat_walker`; 0: the floor FORCING_MIN alone)."""
    return min(FORCING, max(eta, FORCING_MIN, 0.3 * tolerance / residual))


def balance(law, z_ind, fft, stiff, clamp):
    """The coupled balance as a function of the spectrum: uh ↦ (f̂, f, u), f = t(u) − K u on the nodes (the q = 0
    mode removed where `clamp`, a half-plane's fixed mean); raises the law's CompressionOverflowError in its overflow range."""

    def force(uh):
        u = fft.irfft(uh)
        t, _ = law.traction(u, z_ind)
        fh = fft.rfft(t) - stiff.stiffness(uh)
        if clamp:
            fh[:, 0] = 0.0
        return fh, fft.irfft(fh), u

    return force


def balance_residual(model, law, z_ind, u_hat):
    """(max nodal |f| / p_ref of the coupled balance at the spectrum u_hat, inf in the law's overflow range; the FFT
    pairs it took)."""
    fft = Fft(model.nodes)
    try:
        _, f, _ = balance(law, z_ind, fft, stiffness_operator(model), model.half_plane)(u_hat)
    except laws.CompressionOverflowError:
        return np.inf, fft.pairs
    return float(np.max(np.abs(f))) / model.reference_traction, fft.pairs


def nodal_force(law, z_ind, u, ku, clamp):
    """f = t(u) − K u on the nodes from u and its K u (no FFT; `balance`'s f to round-off): t's mean removed where
    `clamp` (K u has none there); raises the law's CompressionOverflowError in its overflow range."""
    t, _ = law.traction(u, z_ind)
    if clamp:
        t -= t.mean(axis=1, keepdims=True)
    return t - ku


def nodes_and_stiffness(x_hat, stiff, fft):
    """(x, K x) on the nodes of the spectra x_hat: one FFT pair (two inverse transforms, counted as such)."""
    return fft.irfft(x_hat), fft.irfft(stiff.stiffness(x_hat))


def balance_state(model, law, z_ind, u_hat, fft, stiff=None):
    """(f, u, K u) on the nodes at the spectrum u_hat (its q = 0 mode taken as 0 where the half-plane clamps it):
    one FFT pair (u and K u) and `nodal_force`; raises the law's CompressionOverflowError in its overflow range."""
    stiff = stiffness_operator(model) if stiff is None else stiff
    if model.half_plane and np.any(u_hat[:, 0] != 0.0):
        u_hat = u_hat.copy()
        u_hat[:, 0] = 0.0
    u, ku = nodes_and_stiffness(u_hat, stiff, fft)
    return nodal_force(law, z_ind, u, ku, model.half_plane), u, ku


def better_start(problem, guess, previous, margin):
    """(`previous` where the max nodal force residual of `guess` is more than `margin` times its own, else `guess`;
    both residuals in p_ref, infinite in the law's overflow range; the FFT pairs spent, one per start; the chosen
    start's `balance_state` (f, u, K u), None where it overflows): `gfmd.chains`' start of a coupled step
    (COUPLED_BETTER_START, `gfmd.coupled_rules`), whose Newton takes that state (`Problem.start_state`)."""
    model, fft = problem.model, Fft(problem.model.nodes)
    residuals, states = [], []
    for start in (guess, previous):
        try:
            state = balance_state(model, problem.law, problem.z_ind, start, fft)
        except laws.CompressionOverflowError:
            residuals.append(np.inf), states.append(None)
            continue
        residuals.append(float(np.max(np.abs(state[0]))) / model.reference_traction)
        states.append(state)
    chosen = 1 if margin * residuals[1] < residuals[0] else 0
    return (guess, previous)[chosen], tuple(residuals), fft.pairs, states[chosen]


def newton_direction(model, law, z_ind, u, f, stiff, fft, rtol, restart=GMRES_RESTART, cycles=GMRES_CYCLES):
    """(δu, K δu, GMRES's info) on the nodes solving (K + D) δu = f (f nodal, zero-mean rows where clamped) as
    `newton_step` does, without its transforms after the solve: with the two-level preconditioner GMRES sums
    δu = M⁻¹ x and K δu = Π g(x) from its products' parts (`gfmd.gmres.gmres`'s extras) and skips the true
    residual's product (the Newton tests its own residual next); on the spectrum (`spectral_step`) one FFT pair and a
    half more than the solve, for f̂ in and δu, K δu out (`nodes_and_stiffness`)."""
    two_level = _two_level(model, law, z_ind, u, stiff, fft)
    if two_level is None:
        f_hat = fft.rfft(f)
        if model.half_plane:
            f_hat[:, 0] = 0.0
        du_hat, info = spectral_step(model, law, z_ind, u, f_hat, stiff, fft, rtol, restart, cycles,
                                     trust_estimate=True)
        return nodes_and_stiffness(du_hat, stiff, fft) + (info,)
    coarse, tangent = two_level
    _, product = coupled_preconditioner.operators(coarse, stiff, fft, tangent, parts=True)
    n = model.nodes

    def times(x):
        out, s, g = product(x.reshape(2, n))
        return out.ravel(), s, g

    _, info, (du, g) = gfmd_gmres.gmres(times, f.ravel(), rtol, restart, cycles, trust_estimate=True, extras=2)
    if model.half_plane:
        g = g - g.mean(axis=1, keepdims=True)
    return du, g, info


def _two_level(model, law, z_ind, u, stiff, fft):
    """(the `coupled_preconditioner.CoarseSpace`, the tangent) of `newton_step`'s two-level preconditioner, or None
    where it runs on the spectrum (the choice "stiffness", one component, no stiff node)."""
    if coupled_preconditioner.CHOICE not in ("two-level", "stiffness"):
        raise ValueError(f"gfmd.coupled_preconditioner.CHOICE = {coupled_preconditioner.CHOICE!r}: expected "
                         "'two-level' or 'stiffness'")
    if coupled_preconditioner.CHOICE != "two-level" or model.components != 2:
        return None
    tangent = law.law.tangent(z_ind - u[-1], -u[0])
    coarse = coupled_preconditioner.coarse_space(stiff, fft, tangent, law.law.initial_stiffness)
    return None if coarse is None else (coarse, tangent)


def newton_step(model, law, z_ind, u, f_hat, stiff, fft, rtol, restart=GMRES_RESTART, cycles=GMRES_CYCLES,
                f=None):
    """(δû, GMRES's info: 0 where it reached rtol) solving (K + D) δu = f: with the two-level right preconditioner
    M⁻¹ = Q + K⁻¹(I − A Q) (`gfmd.coupled_preconditioner`, `coupled_preconditioner.CHOICE` "two-level") by GMRES on
    the nodes, y = M δu, A M⁻¹ y = Π(g + D s), g = y − D Π Z E⁻¹ Zᵀ y, s = K⁻¹ g: one FFT pair per product, GMRES's
    norm the nodal one; `spectral_step` (K⁻¹ alone) where the choice is "stiffness", the model has one component
    or no node is stiff. The clamped q = 0 mode of a half-plane stays 0. f: the nodal f = irfft f̂ where the caller
    has it (no FFT for it here)."""
    two_level = _two_level(model, law, z_ind, u, stiff, fft)
    if two_level is None:
        return spectral_step(model, law, z_ind, u, f_hat, stiff, fft, rtol, restart, cycles)
    coarse, tangent = two_level
    inverse, product = coupled_preconditioner.operators(coarse, stiff, fft, tangent)
    n = model.nodes
    rhs = fft.irfft(f_hat) if f is None else f
    y, info = gfmd_gmres.gmres(lambda x: product(x.reshape(2, n)).ravel(), rhs.ravel(), rtol, restart, cycles)
    return inverse(y.reshape(2, n)).copy(), info


def spectral_step(model, law, z_ind, u, f_hat, stiff, fft, rtol, restart=GMRES_RESTART, cycles=GMRES_CYCLES,
                  trust_estimate=False):
    """(δû, GMRES's info: 0 where it reached rtol) solving (K + D) δu = f by GMRES on the spectrum,
    right-preconditioned by K⁻¹: y = K δû,
    B y = y + rfft(D irfft(K⁻¹ y)) = f̂, one FFT pair per product; the unknowns scaled by √(w_q/N) so that
    GMRES's norm is the nodal one (Parseval). The clamped q = 0 mode of a half-plane stays 0. trust_estimate:
    `gfmd.gmres.gmres`'s (no true residual's product after a cycle that reached rtol)."""
    n, c = model.nodes, model.components
    clamp = model.half_plane
    d_nn, d_nt, d_tn, d_tt = law.law.tangent(z_ind - u[-1], -u[0])
    scale = np.sqrt(spectral_weights(n) / n)
    shape = (c, n // 2 + 1)
    inverse = divided_blocks(stiff.inv_mass, scale)  # z ↦ K⁻¹ y with y = z / scale, one product per block
    tangent_times = coupled_kernels()[1]
    dv = np.empty((c, n))
    ky = np.empty(shape, complex)

    def b_times(x):
        z = np.ascontiguousarray(x).view(complex).reshape(shape)
        v = fft.irfft(stiff._apply(inverse, z, ky))
        if c == 1:
            np.multiply(d_nn, v[0], out=dv[0])
        else:
            tangent_times(d_nn, d_nt, d_tn, d_tt, v, dv)
        out = fft.rfft(dv)
        out *= scale
        out += z
        if clamp:
            out[:, 0] = z[:, 0]
        return out.view(float).ravel()

    rhs = np.ascontiguousarray(f_hat * scale).view(float).ravel()
    size = rhs.size
    if GMRES == "gfmd":
        y, info = gfmd_gmres.gmres(b_times, rhs, rtol, restart, cycles, trust_estimate=trust_estimate)
    else:
        y, info = gmres(LinearOperator((size, size), matvec=b_times, dtype=float), rhs, rtol=rtol, restart=restart,
                        maxiter=cycles)
    du_hat = stiff._apply(inverse, np.ascontiguousarray(y).view(complex).reshape(shape))
    if clamp:
        du_hat[:, 0] = 0.0
    return du_hat, info
