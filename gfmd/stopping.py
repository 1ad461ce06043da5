"""The stopping test every GFMD algorithm shares, and the `Relaxed` of a final state.

Convergence: max_j |r_j| < tolerance · p_ref, with r the nodal force residual (Pa) and p_ref =
`Model.reference_traction`. On a law with a traction function r = f (`gfmd.problem`); on a wall the
net force, f with the wall's reaction taken off the nodes it pushes into the wall
(`gfmd.problem.wall_net_force`): the fixed points are the KKT points (no pulling wall node, zero
force off the wall, no penetration). The dynamics test every `check_every` iterations with one extra
inverse FFT, the CGs when their own cheaper measure says the test can pass. A step that hits
`max_iterations`, or whose law evaluation would overflow, is returned with converged = False, its
residual and a message: it is never silently accepted.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core import laws

from .fft import Fft
from .problem import wall_balance, wall_net_force_from
from .settings import Relaxed


def wall_check(model, fft, k, u, ku, z_ind, wall_tolerance, tolerance):
    """The hard-wall CGs' stopping test on u, K u recomputed into ku: (residual, converged, message).

    residual = max |net nodal force| of `wall_net_force` / p_ref; converged when below `tolerance`;
    message non-empty when the residual is not finite (the solver stops: diverged)."""
    fft.apply_to(k, u, ku)
    residual = wall_residual(model, u, ku, z_ind, wall_tolerance)
    if residual < tolerance:
        return residual, True, ""
    return residual, False, "" if np.isfinite(residual) else "diverged: non-finite force residual"


def wall_residual(model, u, ku, z_ind, wall_tolerance):
    """max |net nodal force| of `wall_net_force` / p_ref for u and its K u (the hard-wall residual)."""
    net, _ = wall_net_force_from(model, ku, z_ind - u <= wall_tolerance)
    return float(np.max(np.abs(net))) / model.reference_traction


def finish(problem, u_hat, iterations, residual, converged, message, wall_state=None):
    """The `Relaxed` of the state u_hat. wall_state = (u_z, K u_z) of a hard-wall state whose residual was
    just taken from exactly these arrays: the tractions then come from them, not from two more inverse FFTs.
    The fields come from the solvers' FFT (`gfmd.fft.Fft`, not counted in their FFT pairs)."""
    model, law, z_ind, wall_tolerance = problem.model, problem.law, problem.z_ind, problem.wall_tolerance
    n = model.nodes
    fft = Fft(n, grid=model.grid)
    if wall_state is not None:
        u = wall_state[0][None, :].copy()
    else:
        u = fft.irfft(u_hat)
    if law.constraint:
        gap = z_ind - u[-1]
        on_wall = gap <= wall_tolerance
        gap = np.maximum(gap, 0.0)
        u[-1] = z_ind - gap
        ku = wall_state[1] if wall_state is not None else fft.irfft(model.k_zz * u_hat[-1])
        force = wall_balance(model, ku, on_wall)
        t = np.zeros_like(u)
        t[-1] = np.where(on_wall, -np.maximum(force, 0.0), 0.0)
    else:
        try:
            t, gap = law.traction(u, z_ind)
        except laws.CompressionOverflowError as exc:  # only if the initial guess itself overflows
            raise laws.CompressionOverflowError(f"initial state of the step is out of the law's range: {exc}") from exc
    u_x = u[0] if model.tangential else np.zeros(n)
    t_x = t[0] if model.tangential else np.zeros(n)
    return Relaxed(u_hat=u_hat, u_z=u[-1], u_x=u_x, gap=gap, t_z=t[-1], t_x=t_x, iterations=iterations,
                   residual=float(residual), converged=bool(converged), message=message)
