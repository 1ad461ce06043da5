"""ContactMechanics (+ Adhesion), ContactEngineering's FFT half-spaces, behind the solver-adapter protocol.

Translation (each checked in tests/test_peer_adapters.py):

* units: the code runs in units of the cell length L (x) and E* (pressures), where its absolute tolerances
  (L-BFGS-B's gtol, the CG's pentol/forcetol) mean the same for every case; answers are scaled back to SI.
* heights: its topography is the rigid surface summits-up and its gap is g = u − s − offset (u its displacement,
  positive into the body); ours is the indenter's lower surface h, so s = −h and offset = δ + min h puts the
  indenter δ past first touch (LJ 9-3: its gap is the distance z = Δn + z0, so offset = δ + min h − z0).
* modulus: a half-space built with young = E* and no Poisson ratio uses E* itself (kernel E*|q|/2; 1D is the
  plane-strain half-plane).
* the mean displacement: periodic penetration control needs ⟨u_z⟩ = 0. The hard-wall CG gets a zero q = 0
  compliance (stiffness_q0 = 0 in 2D; in 1D that raises IndexError, so stiffness_q0 = inf, the same Green's
  function). The adhesive systems minimise over u with a finite q = 0 stiffness (the Nyquist one: the
  conditioning is unchanged); the offset is corrected until δ = ⟨h⟩ − min h − ⟨g⟩ meets the target. Under
  pressure control (CG only) δ is that same mean-gap expression; on a free boundary u → 0 far away and
  δ = offset − min h.
* interfaces: hard wall = constrained_conjugate_gradients (Polonsky–Keer); "hard-wall+exponential" =
  BoundedSmoothContactSystem with Adhesion's Exponential (V = −w e^{−g/ρ}, gap ≥ 0 as bounds of L-BFGS-B); "lj93"
  = SmoothContactSystem with Adhesion's LJ93 (ε, σ chosen so that its minimum is −w at z0) behind Adhesion's
  LinearCorePotential (linear below z0/2, where the equilibria of the cases never go).

Cost: wall time, the code's iterations (CG or L-BFGS-B) and its force evaluations (one FFT pair each).
"""

from __future__ import annotations

import math
import time

import numpy as np
from Adhesion.Interactions import LJ93, Exponential
from Adhesion.Interactions.Cutoff import LinearCorePotential
from Adhesion.System.Systems import BoundedSmoothContactSystem, SmoothContactSystem
from ContactMechanics import FreeFFTElasticHalfSpace, PeriodicFFTElasticHalfSpace
from ContactMechanics import __version__ as cm_version
from ContactMechanics.Optimization import constrained_conjugate_gradients
from SurfaceTopography import Topography, UniformLineScan

from .protocol import Answer, Capabilities, Cost, NotConverged, Problem, State

#: relative tolerances: penetration and δ to this fraction of the height range, forces (gradients) to this
#: fraction of the pressure scale max(E*·ptp(h)/L, w/ρ) per node
TOLERANCE = 1e-10
#: L-BFGS-B's gtol on the smooth systems, relative to the pressure scale per node; its line search may stop
#: short of it at the energy's round-off (~1e-7 measured on the adhesive sinusoid): it restarts from where it
#: stopped, RESTARTS tries in all, and a state within ACCEPT × gtol is accepted (the reached gradient is reported)
GRADIENT_TOLERANCE, RESTARTS, ACCEPT = 1e-8, 2, 100.0
#: offset corrections of a periodic adhesive step (the q = 0 mode), at most
OFFSET_ROUNDS = 12


class Scaled:
    """The problem in the code's units (lengths / L, pressures / E*), and the way back."""

    def __init__(self, problem: Problem):
        self.length = float(problem.lengths[0])
        self.sizes = tuple(float(s) / self.length for s in problem.lengths)
        self.h = np.asarray(problem.heights, float) / self.length
        self.w = problem.interface.work_of_adhesion / (problem.contact_modulus * self.length)
        self.rho = problem.interface.range / self.length
        self.area = float(np.prod(self.sizes)) / self.h.size  # per node
        self.pressure_scale = max(float(np.ptp(self.h)), self.w / self.rho if self.rho > 0 else 0.0, 1e-300)
        self.shift = self.rho if problem.interface.kind == "lj93" else 0.0  # the code's gap − ours


def _topography(s: Scaled, periodic):
    if s.h.ndim == 1:
        return UniformLineScan(-s.h, s.sizes[0], periodic=periodic)
    return Topography(-s.h, s.sizes, periodic=periodic)


def _substrate(problem: Problem, s: Scaled, q0):
    """The half-space: q0 = "clamp" (⟨u⟩ = 0), "default" (the code's own q = 0 stiffness) or "nyquist"."""
    if problem.boundary == "free":
        return FreeFFTElasticHalfSpace(s.h.shape, 1.0, s.sizes)
    stiffness = {"clamp": 0.0 if s.h.ndim == 2 else math.inf, "default": None,
                 "nyquist": math.pi * max(n / (2 * size) for n, size in zip(s.h.shape, s.sizes))}[q0]
    return PeriodicFFTElasticHalfSpace(s.h.shape, 1.0, physical_sizes=s.sizes, stiffness_q0=stiffness)


def _interaction(problem: Problem, s: Scaled):
    if problem.interface.kind == "hard-wall+exponential":
        return Exponential(s.w, s.rho)
    sigma = s.rho * (5.0 / 2.0) ** (1.0 / 6.0)  # minimum of ε(2/15 (σ/z)⁹ − (σ/z)³) at z0, depth −w
    return LinearCorePotential(LJ93(1.5 * s.w * math.sqrt(2.0 / 5.0), sigma))


class _Path:
    """One path's running totals and the warm start."""

    def __init__(self):
        self.iterations, self.evaluations, self.disp, self.gradient = 0, 0, None, 0.0

    def count(self, result):
        self.iterations += int(result.nit)
        self.evaluations += int(getattr(result, "nfev", 0))


def _state(problem, s, pressure, gap, free, offset):
    """A `State` in SI from the code's scaled fields (gap already ours: Δn for LJ 9-3). Contact by the code's
    rules: p > 0 (the CG's contact zone; Adhesion's repulsive area), g = 0 on the bounded system."""
    p, g = pressure * problem.contact_modulus, gap * s.length
    h = s.h * s.length
    delta = (offset + s.shift - s.h.min()) * s.length if free else float(h.mean() - h.min() - g.mean())
    contact = g <= 0.0 if problem.interface.kind == "hard-wall+exponential" else p > 0.0
    return State(pressure=p, gap=g, mean_pressure=float(p.mean()), penetration=float(delta), contact=contact)


def _fail(problem, k, what):
    raise NotConverged(f"{problem.name or 'problem'}: step {k} (path value {problem.path[k]:.6g}): {what}")


def _hard_wall(problem, s, path: _Path):
    free = problem.boundary == "free"
    q0 = "clamp" if problem.control == "penetration" else "default"
    substrate, topography = _substrate(problem, s, q0), _topography(s, not free)
    tol = {"pentol": TOLERANCE * max(float(np.ptp(s.h)), 1e-300),
           "forcetol": TOLERANCE * s.pressure_scale * s.area, "maxiter": 100000}
    states = []
    for k, value in enumerate(problem.path):
        if problem.control == "penetration":
            run = {"offset": float(value) / s.length + s.h.min()}
        else:
            run = {"external_force": float(value) / problem.contact_modulus * np.prod(s.sizes)}
        if path.disp is not None:
            run["initial_displacements"] = path.disp
        result = constrained_conjugate_gradients(substrate, topography, **tol, **run)
        path.count(result)
        if not result.success:
            _fail(problem, k, f"constrained_conjugate_gradients: {result.message}")
        path.disp = result.x
        u = np.asarray(result.x)[tuple(slice(0, n) for n in s.h.shape)]
        pressure = np.asarray(result.jac) / s.area
        gap = u + s.h - result.offset
        states.append(_state(problem, s, pressure, gap, free, result.offset))  # g < 0 down to −pentol
    return states


def _projected_gradient(system, s):
    """max |∂E/∂u| over the nodes the bounds leave free, relative to the pressure scale per node."""
    force = np.asarray(system.force)[tuple(slice(0, n) for n in s.h.shape)]
    free = np.asarray(system.gap) > 0.0 if isinstance(system, BoundedSmoothContactSystem) else np.ones(s.h.shape, bool)
    return float(np.max(np.abs(force[free]), initial=0.0)) / (s.pressure_scale * s.area)


def _smooth_step(system, s, offset, path: _Path, problem, k):
    """L-BFGS-B at `offset` (restarted from where it stopped when its line search gives up before gtol):
    (pressure, our gap) in the code's units."""
    gtol = GRADIENT_TOLERANCE * s.pressure_scale * s.area
    for _ in range(RESTARTS):
        result = system.minimize_proxy(offset=offset, initial_displacements=path.disp, method="L-BFGS-B",
                                       options={"gtol": gtol, "ftol": 0.0, "maxiter": 100000, "maxcor": 20})
        path.count(result)
        path.disp = system.disp
        reached = _projected_gradient(system, s)
        if result.success or reached <= GRADIENT_TOLERANCE:
            break
    if reached > ACCEPT * GRADIENT_TOLERANCE:
        _fail(problem, k, f"{type(system).__name__}.minimize_proxy (L-BFGS-B): {result.message}; gradient "
                          f"{reached:.2g} × the pressure scale per node")
    path.gradient = max(path.gradient, reached)
    window = tuple(slice(0, n) for n in s.h.shape)
    pressure = -np.asarray(system.substrate.force)[window] / s.area
    return pressure, np.asarray(system.gap) - s.shift


def _adhesive(problem, s, path: _Path):
    free = problem.boundary == "free"
    cls = BoundedSmoothContactSystem if problem.interface.kind == "hard-wall+exponential" else SmoothContactSystem
    system = cls(_substrate(problem, s, "nyquist"), _interaction(problem, s), _topography(s, not free))
    states = []
    for k, value in enumerate(problem.path):
        target = float(value) / s.length
        offset = target + s.h.min() - s.shift
        for _ in range(1 if free else OFFSET_ROUNDS):
            pressure, gap = _smooth_step(system, s, offset, path, problem, k)
            miss = target - (s.h.mean() - s.h.min() - gap.mean())
            if free or abs(miss) <= TOLERANCE * max(float(np.ptp(s.h)), s.rho):
                break
            offset += miss
        else:
            _fail(problem, k, f"the mean gap missed δ by {miss * s.length:.3g} m after {OFFSET_ROUNDS} offset "
                              "corrections")
        states.append(_state(problem, s, pressure, gap, free, offset))
    return states


class ContactMechanicsSolver:
    """ContactMechanics' FFT half-spaces: Polonsky–Keer CG on the hard wall, Adhesion's smooth systems."""

    name = "contactmechanics"
    capabilities = Capabilities(
        dimensions=frozenset({1, 2}), boundaries=frozenset({"periodic", "free"}),
        interfaces=frozenset({"hard-wall", "hard-wall+exponential", "lj93"}),
        controls=frozenset({"penetration", "pressure"}), warm_start=True,
        why_not={"exponential-cz": "Adhesion 0.93 has no cohesive law T = (w/ρ)(g/ρ)e^{−g/ρ} without a hard wall "
                                   "(its interactions: Exponential V = −γe^{−g/ρ}, LJ 9-3, VdW 8-2, power law, "
                                   "harmonic, Morse); a Potential subclass written here would test our law, not "
                                   "theirs"})

    def refuses(self, problem: Problem) -> str | None:
        """The combinations ContactMechanics cannot do: a free 1+1-D boundary; adhesion under pressure control."""
        if problem.boundary == "free" and problem.dimension == 1:
            return ("free boundary in 1+1-D: ContactMechanics' FreeFFTElasticHalfSpace has no 1D Green's function "
                    "(a free half-plane's displacement has no reference far away)")
        if problem.control == "pressure" and problem.interface.kind != "hard-wall":
            return (f"pressure control with {problem.interface.kind!r}: ContactMechanics' smooth systems minimise "
                    "at a given offset only (no force-controlled adhesive solver)")
        return None

    def solve(self, problem: Problem) -> Answer:
        if reason := self.refuses(problem):
            raise ValueError(f"problem {problem.name!r}: {reason}")
        s, path = Scaled(problem), _Path()
        t0 = time.perf_counter()
        if problem.interface.kind == "hard-wall":
            states, algorithm = _hard_wall(problem, s, path), "constrained_conjugate_gradients (Polonsky–Keer)"
        else:
            states = _adhesive(problem, s, path)
            algorithm = (f"{'Bounded' if problem.interface.kind != 'lj93' else ''}SmoothContactSystem, L-BFGS-B, "
                         f"{'Exponential' if problem.interface.kind != 'lj93' else 'LinearCorePotential(LJ93)'}, "
                         f"largest final gradient {path.gradient:.2g} × the pressure scale per node")
        kind = "FreeFFTElasticHalfSpace" if problem.boundary == "free" else "PeriodicFFTElasticHalfSpace"
        ran = (f"ContactMechanics {cm_version}, {kind}, {algorithm}, relative tolerance {TOLERANCE:g}, warm start "
               "along the path")
        return Answer(states=states, cost=Cost(wall_s=time.perf_counter() - t0, iterations=path.iterations,
                                               fft_pairs=path.evaluations), ran=ran)
