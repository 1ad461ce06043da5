"""The damped-dynamics steppers the FIRE and Verlet algorithms share (reference-formulas §5.2).

* `Fire`: FIRE's step size and mixing state (Bitzek et al. 2006, FIRE 2.0 back-step on restart);
* `verlet_coefficients`: the seed's damped Störmer–Verlet, uniform mass, every mode damped
  critically for the discrete scheme (γΔt = ωΔt√(4 − (ωΔt)²));
* `fire_wall_velocity`: FIRE's velocity step of the projected wall dynamics.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .fft import dot, irfft_nodes, rfft_nodes
from .settings import Settings


@dataclass(frozen=True)
class DynamicsOptions:
    """What FIRE and damped Verlet read: the `Settings` fields of these names (dimensionless, time unit 1/ω0)."""

    method: str  # "fire" or "verlet"
    tolerance: float  # max nodal force residual / p_ref
    max_iterations: int
    check_every: int  # iterations between residual tests
    dt_start: float  # FIRE (Bitzek et al. 2006)
    dt_max: float
    n_min: int
    f_inc: float
    f_dec: float
    alpha_start: float
    f_alpha: float
    verlet_omega_dt: float  # Verlet: ω_max Δt


@dataclass
class Fire:
    """FIRE step size and mixing state (Bitzek et al. 2006; FIRE 2.0 back-step on restart)."""

    settings: Settings
    dt: float = 0.0
    alpha: float = 0.0
    n_pos: int = 0

    def __post_init__(self):
        self.dt = min(self.settings.dt_start, self.settings.dt_max)
        self.reset()

    def reset(self):
        self.alpha, self.n_pos = self.settings.alpha_start, 0

    def adapt(self, power):
        """Update Δt and α from the power P = f·v; True means restart (caller backs up and zeroes v)."""
        s = self.settings
        if power > 0:
            self.n_pos += 1
            if self.n_pos > s.n_min:
                self.dt = min(self.dt * s.f_inc, s.dt_max)
                self.alpha *= s.f_alpha
            return False
        self.dt *= s.f_dec
        self.reset()
        return True


def verlet_coefficients(stiffness, settings):
    """Uniform mass ρ with ω_max Δt = verlet_omega_dt (Δt = 1) and per-mode discrete
    critical damping γΔt = ωΔt √(4 − (ωΔt)²) (reference-formulas §5.2)."""
    rho = stiffness.max() / settings.verlet_omega_dt**2
    wdt = np.sqrt(stiffness / rho)
    return rho, wdt * np.sqrt(np.clip(4 - wdt**2, 0, None))


def fire_wall_velocity(fire, force, u, v, stuck, on_wall, inv_mass, inv_mass_diag, n):
    """FIRE velocity step of the projected wall dynamics (`gfmd.algorithms.hard_wall_dynamics`,
    `gfmd.algorithms.cohesive_wall`).

    Mass-weighted acceleration M⁻¹f, zeroed on the stuck nodes and capped at f_j·diag(M⁻¹) on wall
    nodes that pull away (the fixed points are then the KKT points); FIRE's power check, its restart
    stepping u back half a step. u and v in place; returns the new Δt. n: the node count, or the grid
    (Nx, Ny) of a 2+1-D surface's flat fields (`gfmd.fft`).
    """
    acc = irfft_nodes(inv_mass * rfft_nodes(force, n), n)
    acc[stuck] = 0.0  # precondition on the non-stuck subspace only
    pulling = on_wall & (force < 0)  # must leave the wall: never let M⁻¹ smear it back in
    acc[pulling] = np.minimum(acc[pulling], force[pulling] * inv_mass_diag)
    restart = fire.adapt(dot(force, v))
    dt = fire.dt
    if restart:
        u -= 0.5 * dt * v
        v[:] = 0.0
    v += dt * acc
    a_norm = np.sqrt(dot(acc, acc))
    if a_norm > 0:
        mix = fire.alpha * np.sqrt(dot(v, v)) / a_norm
        v *= 1 - fire.alpha
        v += mix * acc
    return dt
