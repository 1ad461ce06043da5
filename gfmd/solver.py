"""Static equilibrium of one load step by damped dynamics in Fourier space.

Units: SI (see `contact.conventions`). Unknowns are the rfft coefficients û of the
surface displacement (components (x, z), or z alone). The force on mode q is

    f̂ = rfft(t_interface(u)) − K(q) û          (traction units, Pa)

and equilibrium is f = 0 at every node (hard wall: f ≤ 0 pushes are taken by the
wall on nodes that touch it). Two integrators (reference-formulas §5.2):

* ``fire`` (default): FIRE (Bitzek et al. 2006, with the FIRE 2.0 back-step) on
  mass-weighted modes, M_q = K(q) + ⟨k_loc⟩·I, so that every free elastic mode has
  the same frequency and the interface stiffness, averaged over the cell as long
  waves see it (⟨∂T/∂Δ⟩ from the law's tangent, refreshed when it changes by 2×),
  does not slow or destabilise them. A trust region limits every nodal move per
  iteration to `max_move`·min(δn, δt).
* ``verlet``: the seed's damped Störmer–Verlet, uniform mass, every mode damped
  critically for the discrete scheme (γΔt = ωΔt√(4 − (ωΔt)²)).
* Coupled law (no potential): FIRE, and if it stalls (``COUPLED_FIRE_BUDGET``)
  Newton–Krylov on the law's tangent (`_relax_coupled_newton`: GMRES preconditioned by
  M⁻¹, no dynamics; deep in the slip regime the equilibria are flutter points of any damped
  dynamics), then Verlet from the step's guess (see `_relax_coupled_fire`).
* Normal-only cohesive law (a potential), method ``fire``: by default
  (``Settings.cohesive = "ncg"``) nonlinear preconditioned conjugate gradients (Polak–Ribière+,
  preconditioner K⁻¹ as the hard-wall CG, an FFT-free Newton line search on the elastic + CZ
  energy; `_relax_cohesive_ncg`), FIRE as the fallback when NCG stalls; 5–10× fewer FFT pairs
  per step than FIRE (benchmarks/results/bench_vs_tamaas.md). ``cohesive = "fire"`` keeps FIRE.
  `Relaxed.method` says which ran. The law's nodal work runs on the nodes near the indenter
  only, and the spectral algebra in `gfmd.kernels` (numpy, or fused numba kernels where installed).

Hard wall: a constraint, not a penalty. Default (``Settings.hard_wall = "cg"``,
method ``fire``): projected conjugate-gradient active-set methods. While the contact set
holds at most ``Settings.dual_contact_limit`` (15 %) of the nodes, on the contact pressures
(`_relax_hard_wall_dual`: the dual, preconditioned by a band of K on the contact set, one
FFT pair per iteration); beyond, on the displacements of the nodes off the wall
(`_relax_hard_wall_cg`: the primal, preconditioner M⁻¹ = K⁻¹, two pairs per iteration). Both
project what a step pushes through its bound (Polonsky–Keer) and release by proportioning;
5.8–7.3× (primal) and 8.6–10× (dual) fewer FFT pairs per step than FIRE at N = 2^16–2^17
(benchmarks/results/bench_vs_tamaas.md).
``hard_wall = "fire"`` and method ``verlet``: damped dynamics; after each move the
nodes that went through the wall are projected back onto it (u_z ≤ z_ind) and the
velocity that carried them there is removed with the same correction.
All variants stop on the same residual (below) and have the KKT points as fixed points.

Cohesive wall (`contact.laws.CohesiveWall`: Eq. 3's attraction for Δn > 0, Δn ≥ 0 as a
constraint): `_relax_cohesive_wall`, the hard wall's projected FIRE (or Verlet) with the
attraction added to the nodal force, the cohesive solver's mass weighting and trust region;
the same residual, and KKT fixed points (Δn ≥ 0, reaction ≥ 0 on the wall, zero force off it).

FFT backend of the hard-wall CG, the cohesive NCG and FIRE: scipy.fft, or ducc0 where installed
(the ``fast`` extra; 1.4–2× faster pairs measured here); ``GFMD_FFT=scipy|ducc0|auto`` (default
auto) chooses. The FIRE and Verlet hard wall, the cohesive wall and `_finish` use scipy.fft.

Convergence: max_j |r_j| < tolerance · p_ref, with r the nodal force residual
(Pa) and p_ref = `Model.reference_traction`; checked every `check_every`
iterations with one extra inverse FFT. A step that hits `max_iterations`, or
whose law evaluation would overflow, is returned with converged = False, its
residual and a message: it is never silently accepted.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
import scipy.fft
import scipy.sparse

try:  # optional, the `fast` extra: a faster real FFT (measured 1.4–2× per rfft/irfft pair here)
    import ducc0.fft as _ducc_fft
except ImportError:  # pragma: no cover - depends on the environment
    _ducc_fft = None

from contact import laws

from . import kernels


def fft_backend(name=None):
    """The FFT backend in use: "ducc0" or "scipy" (from `name`, else $GFMD_FFT, default "auto")."""
    return kernels.choose_backend("GFMD_FFT", name, "ducc0", "scipy", _ducc_fft is not None)


class _Fft:
    """rfft / irfft along the last axis (length n) through the chosen backend, counting pairs."""

    def __init__(self, n, backend=None):
        self.n, self.backend, self.calls = n, fft_backend(backend), 0
        self._spectrum = None  # `apply_to`'s preallocated spectrum (ducc0)

    def rfft(self, x):
        self.calls += 1
        if self.backend == "ducc0":
            return _ducc_fft.r2c(np.ascontiguousarray(x), axes=(-1,), forward=True)
        return scipy.fft.rfft(x, axis=-1)

    def irfft(self, x_hat):
        self.calls += 1
        if self.backend == "ducc0":
            return _ducc_fft.c2r(np.ascontiguousarray(x_hat), axes=(-1,), forward=False, lastsize=self.n, inorm=2)
        return scipy.fft.irfft(x_hat, n=self.n, axis=-1)

    def apply(self, kernel, x):
        """irfft(kernel · rfft(x)): one pair."""
        x_hat = self.rfft(x)
        x_hat *= kernel
        return self.irfft(x_hat)

    def apply_to(self, kernel, x, out):
        """out ← irfft(kernel · rfft(x)) for 1-D x: one pair; with ducc0 single-threaded and without
        allocating (preallocated spectrum, c2r into `out`, overwriting the spectrum)."""
        self.calls += 2
        if self.backend == "ducc0":
            if self._spectrum is None:
                self._spectrum = np.empty(self.n // 2 + 1, complex)
            spectrum = _ducc_fft.r2c(x, axes=(-1,), forward=True, out=self._spectrum, nthreads=1)
            spectrum *= kernel
            return _ducc_fft.c2r(spectrum, axes=(-1,), forward=False, lastsize=self.n, inorm=2, out=out,
                                 nthreads=1, allow_overwriting_input=True)
        out[...] = scipy.fft.irfft(kernel * scipy.fft.rfft(x), n=self.n)
        return out

    @property
    def pairs(self):
        return self.calls / 2


@dataclass(frozen=True)
class Settings:
    """Integrator parameters (dimensionless; time unit 1/ω0 with ω0 = 1)."""

    method: str = "fire"
    tolerance: float = 1e-8
    max_iterations: int = 200_000
    check_every: int = 10
    # FIRE (Bitzek et al. 2006 defaults, FIRE 2.0 back-step)
    dt_start: float = 0.3
    dt_max: float = 1.0
    n_min: int = 5
    f_inc: float = 1.1
    f_dec: float = 0.5
    alpha_start: float = 0.1
    f_alpha: float = 0.99
    # Verlet: ω_max Δt
    verlet_omega_dt: float = 1.0
    # cohesive laws: largest nodal move per iteration, in units of min(δn, δt)
    max_move: float = 0.5
    # FIRE, cohesive laws: iterations between re-evaluations of the mean interface stiffness
    mass_refresh: int = 100
    # hard wall with method "fire": "cg" (projected preconditioned CG, default) or "fire" (FIRE)
    hard_wall: str = "cg"
    # cohesive normal-only law (a potential) with method "fire": "ncg" (nonlinear preconditioned CG with
    # a Newton line search, FIRE as fallback) or "fire" (FIRE alone, the integrator before issue 13)
    cohesive: str = "ncg"
    # NCG line search: stop when |dE/dα| ≤ line_search_tol · |dE/dα(0)|
    line_search_tol: float = 0.1
    # hard-wall CG: release the wall nodes that pull away once their forces' norm exceeds
    # proportioning × the free nodes' residual norm (Dostál's MPRGP proportioning test)
    proportioning: float = 0.3
    # hard-wall CG: solve for the contact pressures (`_relax_hard_wall_dual`) while the contact set holds at
    # most this fraction of the nodes, else for the displacements (`_relax_hard_wall_cg`); 0: always the latter
    dual_contact_limit: float = 0.15


@dataclass
class Relaxed:
    """Equilibrium of one load step: fields on the N nodes (SI) and solver record."""

    u_hat: np.ndarray  # (c, N//2+1) rfft of u
    u_z: np.ndarray  # m
    u_x: np.ndarray  # m (zeros when not solved)
    gap: np.ndarray  # Δn (m)
    t_z: np.ndarray  # traction on the body (Pa), = T_n
    t_x: np.ndarray  # Pa, = T_t
    iterations: int
    residual: float  # max |r| / p_ref
    converged: bool
    message: str = ""
    fft_pairs: float = 0.0  # rfft+irfft pairs the relaxation used (0 where not counted)
    method: str = ""  # the integrator that produced this state: "ncg", "fire", "verlet", "cg", "ncg→fire"


class InterfaceLaw:
    """The interface law on the solver's unknowns: tractions on the body for displacements (SI).

    The law is `model.law` (`contact.laws`: the law object `contact.model.build_model` chose for
    the model's unknowns; Eq. 2 where u_x is solved). `interface` and `work_tangential` are
    accepted for the callers that pass them and not used: the law object already holds the
    scene's φn, δn, φt, δt. This class only maps displacements u (c, N) to gaps, Δn = z_ind − u_z
    and Δt = −u_x, and the law's tractions back onto the components solved.
    """

    def __init__(self, model, interface=None, work_tangential=None):
        self.model = model
        self.law = model.law
        # a constraint (the hard wall) has no traction function: `relax` projects instead
        self.constraint = self.law.constraint
        # initial slopes of the law (Pa/m): the interface stiffness in Verlet's mode frequencies
        self.k_int_x, self.k_int_z = (0.0, 0.0) if self.constraint else self.law.initial_stiffness

    def _gaps(self, u, z_ind):
        return z_ind - u[-1], (-u[0] if self.model.tangential else None)

    def mean_stiffness(self, u, z_ind):
        """Spatial means (k_x, k_z) of the law's local tangent stiffness ∂T_t/∂Δt, ∂T_n/∂Δn (Pa/m).

        A long-wavelength mode sees the interface stiffness averaged over the cell,
        so M_q = K(q) + ⟨k_loc⟩ keeps those modes at the elastic frequency; out of contact
        ⟨k_loc⟩ ≈ 0 and M_q = K(q).
        """
        if self.constraint:
            return 0.0, 0.0
        dn_dn, _, _, dt_dt = self.law.tangent(*self._gaps(u, z_ind))
        return float(np.mean(np.maximum(dt_dt, 0))), float(np.mean(np.maximum(dn_dn, 0)))

    def traction(self, u, z_ind):
        """(t, Δn): tractions (c, N) on the body and the normal gap, for displacements u (c, N)."""
        gap, slip = self._gaps(u, z_ind)
        t = np.zeros_like(u)
        if self.constraint:  # zero off the wall; the wall's reaction is `_finish`'s
            return t, gap
        t_n, t_t = self.law.tractions(gap, slip)
        t[-1] = t_n
        if self.model.tangential:
            t[0] = t_t
        return t, gap


def _dot(a, b):
    """Σ a_j b_j without BLAS: multi-threaded BLAS dot products of 1-D arrays stalled
    the solver 4× on a loaded 2-core machine (measured: 15.2 s vs 3.6 s per step at N = 2^17)."""
    return float(np.einsum("i,i->", a, b))


def _spectral_weights(nodes):
    """w_n with Σ_j a_j b_j = (1/N) Σ_n w_n Re(conj(â_n) b̂_n) for rfft spectra."""
    w = np.full(nodes // 2 + 1, 2.0)
    w[0] = 1.0
    if nodes % 2 == 0:
        w[-1] = 1.0
    return w


@dataclass
class _Fire:
    """FIRE step size and mixing state (Bitzek et al. 2006; FIRE 2.0 back-step on restart)."""

    settings: Settings
    dt: float = 0.0
    alpha: float = 0.0
    n_pos: int = 0

    def __post_init__(self):
        self.dt = self.settings.dt_start
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


def _verlet_coefficients(stiffness, settings):
    """Uniform mass ρ with ω_max Δt = verlet_omega_dt (Δt = 1) and per-mode discrete
    critical damping γΔt = ωΔt √(4 − (ωΔt)²) (reference-formulas §5.2)."""
    rho = stiffness.max() / settings.verlet_omega_dt**2
    wdt = np.sqrt(stiffness / rho)
    return rho, wdt * np.sqrt(np.clip(4 - wdt**2, 0, None))


class _Elastic:
    """K(q) and mass operators of a model on the rfft half-spectrum."""

    def __init__(self, model, k_int_x, k_int_z):
        self.model = model
        self.clamp = model.half_plane
        if model.tangential:
            a = model.k_xx + k_int_x
            b = model.k_xz
            d = model.k_zz + k_int_z
            det = (a * d - np.abs(b) ** 2).real
            if self.clamp:
                det[0] = np.inf
            self.mass = (a, b, d)
            self.inv_mass = (d / det, -b / det, a / det)
        else:
            m = model.k_zz + k_int_z
            inv = np.zeros_like(m)
            nz = m > 0
            inv[nz] = 1.0 / m[nz]
            if self.clamp:
                inv[0] = 0.0
            self.mass = (m,)
            self.inv_mass = (inv,)

    @staticmethod
    def _apply(blocks, x):
        if len(blocks) == 1:
            return blocks[0] * x
        a, b, d = blocks
        return np.stack([a * x[0] + b * x[1], np.conj(b) * x[0] + d * x[1]])

    def stiffness(self, x):
        """K(q) x for spectra x of shape (c, nq)."""
        m = self.model
        return self._apply((m.k_xx, m.k_xz, m.k_zz) if m.tangential else (m.k_zz,), x)

    def mass_times(self, x):
        return self._apply(self.mass, x)

    def inverse_mass_times(self, x):
        return self._apply(self.inv_mass, x)


def relax(model, law, z_ind, u_hat, settings, wall_tolerance=0.0):
    """Relax one load step from the initial guess `u_hat` (c, N//2+1); returns `Relaxed`.

    z_ind: indenter surface z_ind(x) (m) at this step; wall_tolerance (m): gap
    below which a hard-wall node counts as touching the wall.
    """
    if law.constraint and law.law.adhesive:  # the cohesive wall: CZ attraction + projection onto the wall
        return _relax_cohesive_wall(model, law, z_ind, u_hat, settings, wall_tolerance)
    if law.constraint:  # the hard wall: a constraint, projected (no traction function to relax)
        if settings.method == "fire" and settings.hard_wall == "cg":
            if not 0.0 <= settings.dual_contact_limit <= 1.0:
                raise ValueError(f"Settings.dual_contact_limit = {settings.dual_contact_limit!r}: expected a fraction "
                                 "of the nodes in [0, 1] (0: the primal CG only)")
            if settings.dual_contact_limit > 0:
                return _relax_hard_wall_dual(model, law, z_ind, u_hat, settings, wall_tolerance)
            return _relax_hard_wall_cg(model, law, z_ind, u_hat, settings, wall_tolerance)
        if settings.hard_wall not in ("cg", "fire"):
            raise ValueError(f"Settings.hard_wall = {settings.hard_wall!r}: expected 'cg' or 'fire'")
        return _relax_hard_wall(model, law, z_ind, u_hat, settings, wall_tolerance)
    if settings.method == "fire" and model.tangential:
        return _relax_coupled_fire(model, law, z_ind, u_hat, settings, wall_tolerance)
    if settings.method == "fire" and settings.cohesive not in ("ncg", "fire"):
        raise ValueError(f"Settings.cohesive = {settings.cohesive!r}: expected 'ncg' or 'fire'")
    if settings.method == "fire" and settings.cohesive == "ncg" and type(law.law) is laws.NormalCohesive:
        return _relax_cohesive_ncg(model, law, z_ind, u_hat, settings, wall_tolerance)
    return _relax_cohesive(model, law, z_ind, u_hat, settings, wall_tolerance)


#: FIRE iterations a coupled-law step gets before the Newton–Krylov / damped-Verlet fallback. Measured (layer
#: D = L, sinusoid a = 50 nm, φn* = 0.01, c = 0.5, ν = 0.3): FIRE needs ≤ 790 iterations per step
#: up to δ = 32 nm (N = 64; ≤ 350 at N = 128), then 950, 7 580, 33 060 and fails (residual 1e-2 to
#: 1e2 p_ref) from δ ≈ 39 nm (N = 128), where Verlet converges in 500–1 140. Budget ≈ 2.5 × 790.
COUPLED_FIRE_BUDGET = 2000


#: Newton iterations a coupled-law step gets after FIRE stalls (`_relax_coupled_newton`); each solves the
#: linearised balance by GMRES (restart COUPLED_GMRES_RESTART, at most COUPLED_GMRES_CYCLES cycles).
COUPLED_NEWTON_ITERATIONS = 60
COUPLED_GMRES_RESTART = 60
COUPLED_GMRES_CYCLES = 5
#: Newton step: largest nodal move per iteration in units of min(δn, δt) (trust region), GMRES relative tolerance
COUPLED_NEWTON_MAX_MOVE = 2.0
COUPLED_NEWTON_FORCING = 1e-3


def _relax_coupled_fire(model, law, z_ind, u_hat, settings, wall_tolerance):
    """FIRE for the coupled law (seed Eq. 2); if FIRE stalls, Newton–Krylov, then damped Verlet.

    FIRE's restarts test the power f·v, a descent test only for forces f = −∇E; the
    coupled law has no potential, and at strongly non-symmetric states (large slip
    under compression) FIRE's weakly damped inertia circulates: started at the FE
    equilibrium of such a state it drifts away (residual 8e-3 → 0.19 p_ref in 3e4
    iterations) while per-mode critically damped Verlet converges in 410. Deeper in the
    slip regime Verlet fails the same way: fig8_small (ν = 0.1, c = 0.5, φn* = 0.15, seed 2,
    N = 4096) at δ = 20 nm has a static equilibrium (Newton: 8 iterations, 0.2 s) whose
    eigenvalues of J nearest 0 all have Re λ > 0 (locally stable in the sense of
    `reference.fem.solver.locally_stable`), but damped inertial dynamics started on it at
    residual 5e-9 p_ref drift off (Verlet: 0.09 p_ref after 1e4 iterations; FIRE: 1.5 p_ref
    after 1e3): the tangent's antisymmetric part (circulatory forces at the slipping,
    compressed contact edge) makes the equilibrium a flutter point of the second-order
    dynamics, which no mass weighting or damping of the diagonal modes removes.

    So FIRE gets min(COUPLED_FIRE_BUDGET, max_iterations/2) iterations; then Newton–Krylov
    (`_relax_coupled_newton`, the law's tangent `jacobian_coupled`, no dynamics) from the
    step's guess, then from FIRE's end state. Newton converges to unstable equilibria as
    well: its state is accepted only if the eigenvalues of the tangent nearest 0 have
    Re λ > 0 (`_coupled_stability`, the FE reference's criterion), else it is rejected and
    said so. Then Verlet restarts the step from the guess with the iterations left. The fallbacks are stated in `Relaxed.message` and `Relaxed.method`.
    """
    budget = min(COUPLED_FIRE_BUDGET, settings.max_iterations // 2)
    first = _relax_cohesive(model, law, z_ind, u_hat, replace(settings, max_iterations=budget), wall_tolerance)
    if first.converged:
        return first
    used, pairs = first.iterations, first.fft_pairs
    notes = [f"FIRE stalled on the coupled law ({first.iterations} iterations, residual {first.residual:.3g} p_ref)"]
    starts = [("guess", u_hat)]
    if np.isfinite(first.residual):
        starts.append(("FIRE's end state", first.u_hat))
    for name, start in starts:
        newton = _relax_coupled_newton(model, law, z_ind, start, settings, wall_tolerance)
        used += newton.iterations
        pairs += newton.fft_pairs
        if newton.converged:
            lowest = _coupled_stability(model, law, z_ind, newton.u_hat)
            if lowest is not None and lowest <= 0.0:  # not the state damped dynamics would settle in
                notes.append(f"Newton–Krylov from the {name} reached an equilibrium that is not locally stable "
                             f"(an eigenvalue of the tangent with Re λ = {lowest / law.k_int_z:.3g} φn/δn²: a slip "
                             "or snap-through instability), rejected")
                continue
            newton.iterations, newton.fft_pairs = used, pairs
            newton.message = "; ".join(notes) + f", Newton–Krylov from the {name} converged"
            newton.method = "fire→newton"
            return newton
        notes.append(f"Newton–Krylov from the {name}: {newton.message}")
    second = _relax_cohesive(model, law, z_ind, u_hat,
                             replace(settings, method="verlet", max_iterations=max(settings.max_iterations - used, 1)),
                             wall_tolerance)
    second.iterations += used
    second.fft_pairs += pairs
    second.message = "; ".join(notes) + "; restarted with damped Verlet: " + (second.message or "converged")
    second.method = "fire→newton→verlet"
    return second


def _coupled_operators(model, law, z_ind, u, fft):
    """(A, M⁻¹, project) at displacements u (c, N): the coupled balance's tangent A = K + D as a
    scipy LinearOperator on flattened (c, N) nodal fields (D: the nodal 2×2 law tangent, rows and
    columns (x, z); ∂f/∂u = −A), the inverse FIRE mass M⁻¹ (`_Elastic` with ⟨k_loc⟩) as its
    preconditioner, and the projection onto zero-mean fields where the half-plane clamps the mean."""
    from scipy.sparse.linalg import LinearOperator

    n, c = model.nodes, model.components
    clamp = model.half_plane
    stiff = _Elastic(model, 0.0, 0.0)
    mass = _Elastic(model, *law.mean_stiffness(u, z_ind))
    d_nn, d_nt, d_tn, d_tt = law.law.tangent(z_ind - u[-1], -u[0])

    def project(x):
        return x - x.mean(axis=1, keepdims=True) if clamp else x

    def a_times(v):
        v = project(v.reshape(c, n))
        vh = fft.rfft(v)
        if clamp:
            vh[:, 0] = 0.0
        out = fft.irfft(stiff.stiffness(vh))
        out += np.stack([d_tt * v[0] + d_tn * v[1], d_nt * v[0] + d_nn * v[1]])
        return project(out).ravel()

    def m_inv(v):
        vh = fft.rfft(v.reshape(c, n))
        if clamp:
            vh[:, 0] = 0.0
        return fft.irfft(mass.inverse_mass_times(vh)).ravel()

    size = c * n
    return (LinearOperator((size, size), matvec=a_times, dtype=float),
            LinearOperator((size, size), matvec=m_inv, dtype=float), project)


#: eigenvalues of the tangent nearest 0 that `_coupled_stability` computes (shift-invert Arnoldi)
COUPLED_STABILITY_EIGENVALUES = 6


def _coupled_stability(model, law, z_ind, u_hat):
    """Smallest Re λ (Pa/m) among the COUPLED_STABILITY_EIGENVALUES eigenvalues nearest 0 of the
    tangent J = K + D at u_hat (None if Arnoldi found none). The FE reference's test of a coupled
    equilibrium (`reference.fem.solver.locally_stable`: every eigenvalue of W⁻¹J has Re λ > 0,
    W the nodal weights, uniform here) restricted to the eigenvalues a fold or a slip instability
    sends through 0: shift-invert ARPACK on J⁻¹, each solve by GMRES (M⁻¹-preconditioned)."""
    from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigs, gmres

    fft = _Fft(model.nodes)
    a_op, m_op, project = _coupled_operators(model, law, z_ind, fft.irfft(u_hat), fft)
    shape = (model.components, model.nodes)

    def solve(b):
        x, _ = gmres(a_op, project(b.reshape(shape)).ravel(), M=m_op, rtol=1e-8,
                     restart=COUPLED_GMRES_RESTART * 2, maxiter=COUPLED_GMRES_CYCLES * 4)
        return x

    inverse = LinearOperator(a_op.shape, matvec=solve, dtype=float)
    k = COUPLED_STABILITY_EIGENVALUES
    try:
        mu = eigs(inverse, k=k, which="LM", return_eigenvectors=False, tol=1e-4, maxiter=100 * k)
    except ArpackNoConvergence as exc:
        mu = exc.eigenvalues
    mu = np.asarray(mu)
    mu = mu[np.isfinite(mu) & (np.abs(mu) > 0)]
    return float(np.min((1.0 / mu).real)) if mu.size else None


def _relax_coupled_newton(model, law, z_ind, u_hat, settings, wall_tolerance):
    """Newton–Krylov on the coupled law's nodal balance f(u) = t(u) − K u = 0 (no dynamics).

    Each iteration solves (K + D) δu = f by GMRES, D the nodal 2×2 tangent of Eq. 2
    (`contact.laws.jacobian_coupled`, ∂t/∂u = −D since Δn = z_ind − u_z, Δt = −u_x), K applied
    by FFT, preconditioned by the inverse of the FIRE mass M_q = K(q) + ⟨k_loc⟩ (`_Elastic`),
    to relative tolerance COUPLED_NEWTON_FORCING; the step is capped so that no node moves
    more than COUPLED_NEWTON_MAX_MOVE·min(δn, δt) and halved until ‖f‖₂ decreases (a step
    into the law's overflow range counts as no decrease). Half-plane: the mean modes stay
    clamped (the operator acts on zero-mean fields). Stops on the solver's residual
    (max |f| < tolerance·p_ref); `iterations` counts Newton iterations, `fft_pairs` includes
    GMRES's products. Not converged (message says why) after COUPLED_NEWTON_ITERATIONS or
    when the line search finds no decrease.
    """
    from scipy.sparse.linalg import gmres  # only this fallback needs it

    n, c = model.nodes, model.components
    fft = _Fft(n)
    p_ref = model.reference_traction
    u_hat = np.array(u_hat, dtype=complex, copy=True)
    clamp = model.half_plane
    if clamp:
        u_hat[:, 0] = 0.0
    stiff = _Elastic(model, 0.0, 0.0)
    max_move = COUPLED_NEWTON_MAX_MOVE * law.law.length_scale

    def force(uh):
        """(f_hat, f, u): the nodal force (mean removed where clamped); raises on overflow."""
        u = fft.irfft(uh)
        t, _ = law.traction(u, z_ind)
        fh = fft.rfft(t) - stiff.stiffness(uh)
        if clamp:
            fh[:, 0] = 0.0
        return fh, fft.irfft(fh), u

    def project(x):
        return x - x.mean(axis=1, keepdims=True) if clamp else x

    try:
        _, f, u = force(u_hat)
    except laws.CompressionOverflowError as exc:
        out = _finish(model, law, z_ind, u_hat, 0, np.inf, False, f"diverged: {exc}", wall_tolerance)
        out.method = "newton"
        return out
    residual = float(np.max(np.abs(f))) / p_ref
    message, converged, it = "", residual < settings.tolerance, 0
    while not converged:
        if it >= COUPLED_NEWTON_ITERATIONS:
            message = f"not converged after {it} Newton iterations (residual {residual:.3g} p_ref)"
            break
        it += 1
        a_op, m_op, _ = _coupled_operators(model, law, z_ind, u, fft)
        du, _ = gmres(a_op, f.ravel(), M=m_op, rtol=COUPLED_NEWTON_FORCING,
                      restart=COUPLED_GMRES_RESTART, maxiter=COUPLED_GMRES_CYCLES)
        du = project(du.reshape(c, n))
        largest = float(np.max(np.abs(du)))
        if not np.isfinite(largest) or largest == 0.0:
            message = f"Newton step not finite or zero (residual {residual:.3g} p_ref)"
            break
        du_hat = fft.rfft(du)
        if clamp:
            du_hat[:, 0] = 0.0
        norm0 = float(np.sqrt(np.einsum("ij,ij->", f, f)))
        step = min(1.0, max_move / largest)
        accepted = False
        while step > 1e-3:
            try:
                trial = force(u_hat + step * du_hat)
            except laws.CompressionOverflowError:
                step *= 0.5
                continue
            if np.sqrt(np.einsum("ij,ij->", trial[1], trial[1])) <= (1.0 - 1e-4 * step) * norm0:
                accepted = True
                break
            step *= 0.5
        if not accepted:
            message = f"Newton line search found no decrease of |f| (iteration {it}, residual {residual:.3g} p_ref)"
            break
        u_hat = u_hat + step * du_hat
        _, f, u = trial
        residual = float(np.max(np.abs(f))) / p_ref
        if not np.isfinite(residual):
            message = "diverged: non-finite force residual"
            break
        converged = residual < settings.tolerance
    pairs = fft.pairs
    out = _finish(model, law, z_ind, u_hat, it, residual, converged, message, wall_tolerance)
    out.fft_pairs = pairs + 0.5
    out.method = "newton"
    return out


def _relax_cohesive(model, law, z_ind, u_hat, settings, wall_tolerance):
    """Cohesive-law relaxation with FIRE or Verlet (see module docstring and `relax`)."""
    n = model.nodes
    fft = _Fft(n)
    w = _spectral_weights(n)
    u_hat = np.array(u_hat, dtype=complex, copy=True)
    if model.half_plane:
        u_hat[:, 0] = 0.0
    v = np.zeros_like(u_hat)
    k_mean = law.mean_stiffness(fft.irfft(u_hat), z_ind)
    elastic = _Elastic(model, *k_mean)

    def dot(a, b):
        return float(np.sum(w * (np.conj(a) * b).real))

    fire = None if settings.method == "verlet" else _Fire(settings)
    if fire is None:  # Verlet: per-mode ω² from the diagonal stiffness plus the law's initial slope
        k_diag = [model.k_zz] if not model.tangential else [model.k_xx.real, model.k_zz]
        k_int = [law.k_int_z] if not model.tangential else [law.k_int_x, law.k_int_z]
        rho, gdt = _verlet_coefficients(np.stack([k + ki for k, ki in zip(k_diag, k_int)]), settings)
    dt = fire.dt if fire else 1.0

    residual = np.inf
    message = ""
    converged = False
    it = 0
    max_move = settings.max_move * law.law.length_scale  # min(δn, δt) where u_x is solved, else δn
    u_hat_prev = u_hat.copy()
    _last_finite = u_hat.copy()
    u_prev = fft.irfft(u_hat)
    for it in range(1, settings.max_iterations + 1):
        u = fft.irfft(u_hat)
        move = float(np.max(np.abs(u - u_prev)))
        if move > max_move:  # trust region: no node moves more than max_move per iteration
            scale = max_move / move
            u_hat = u_hat_prev + scale * (u_hat - u_hat_prev)
            u = u_prev + scale * (u - u_prev)
            v *= scale
            if fire:
                fire.dt *= settings.f_dec
        u_hat_prev, u_prev = u_hat.copy(), u
        try:
            t, _ = law.traction(u, z_ind)
        except laws.CompressionOverflowError as exc:
            message = f"diverged: {exc}"
            u_hat = _last_finite
            break
        _last_finite = u_hat.copy()
        if fire and it % settings.mass_refresh == 0:
            k_now = law.mean_stiffness(u, z_ind)
            if any(b > 2 * a + 1e-300 or a > 2 * b + 1e-300 for a, b in zip(k_mean, k_now)):
                k_mean = k_now  # interface stiffness changed 2×: re-weight the modes, restart FIRE
                elastic = _Elastic(model, *k_mean)
                v[:] = 0.0
                fire.reset()
        f_hat = fft.rfft(t) - elastic.stiffness(u_hat)
        if elastic.clamp:
            f_hat[:, 0] = 0.0
        if it % settings.check_every == 0 or it == 1:
            residual = float(np.max(np.abs(fft.irfft(f_hat)))) / model.reference_traction
            if residual < settings.tolerance:
                converged = True
                break
            if not np.isfinite(residual):
                message = "diverged: non-finite force residual"
                break
        if fire is None:
            v = ((1 - gdt / 2) * v + dt * f_hat / rho) / (1 + gdt / 2)
        else:
            restart = fire.adapt(dot(f_hat, v))
            dt = fire.dt
            if restart:
                u_hat -= 0.5 * dt * v
                v[:] = 0.0
            acc = elastic.inverse_mass_times(f_hat)
            v += dt * acc
            f_norm = dot(f_hat, acc)
            if f_norm > 0:
                v_norm = dot(v, elastic.mass_times(v))
                v = (1 - fire.alpha) * v + fire.alpha * np.sqrt(max(v_norm, 0.0) / f_norm) * acc
        if elastic.clamp:
            v[:, 0] = 0.0
        u_hat += dt * v
    else:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"

    pairs = fft.pairs
    out = _finish(model, law, z_ind, u_hat, it, residual, converged, message, wall_tolerance)
    out.fft_pairs = pairs + 0.5
    out.method = "verlet" if fire is None else "fire"
    return out


#: NCG iterations a cohesive step gets before the FIRE fallback (at most max_iterations / 2)
NCG_BUDGET = 5000

#: NCG: nodes whose attraction (Eq. 3) is at most NCG_FAR_FRACTION · tolerance · p_ref, Δn ≥ s_c δn, are
#: left out of the nodal work; a converged state is checked again with every node
NCG_FAR_FRACTION = 1e-3
#: NCG: the near set holds the nodes with Δn < (s_c + NCG_NEAR_MARGIN) δn; it is rebuilt from the state when
#: a step could have moved a far node by more than the margin
NCG_NEAR_MARGIN = 8.0
#: NCG: every node is near once the near set would hold more than this fraction of them (a gather then
#: costs more than the nodal work it saves)
NCG_NEAR_FULL = 0.5
#: e^{−s} is exactly 0 in double precision beyond this s
EXP_UNDERFLOW = 746.0


def _attraction_cut(x):
    """s_c ≥ 1 with s_c e^{−s_c} = x: beyond Δn = s_c δn, |T_n| < x φn/δn (Eq. 3; s e^{−s} falls for s > 1).

    inf for x ≤ 0 (every node counts); 1 for x ≥ 1/e; at most EXP_UNDERFLOW, where T_n is exactly 0.
    Newton on s − ln s = ln(1/x), convex and rising for s > 1, from s = 2 ln(1/x) + 1 above the root:
    the iterates fall monotonically onto it.
    """
    if not x > 0:
        return np.inf
    if x >= np.exp(-1.0):
        return 1.0
    rhs = -np.log(x)
    s = 2.0 * rhs + 1.0
    for _ in range(200):
        step = (s - np.log(s) - rhs) / (1.0 - 1.0 / s)
        s -= step
        if step <= 1e-13 * s:
            break
    return float(min(max(s, 1.0), EXP_UNDERFLOW))


def _relax_cohesive_ncg(model, law, z_ind, u_hat, settings, wall_tolerance):
    """Normal-only cohesive law by nonlinear preconditioned conjugate gradients, FIRE as fallback.

    The law has a potential (`contact.laws.potential_normal`): the step minimises
    E(u) = ½ uᵀKu + Σ_j V(Δn_j), Δn = z_ind − u, whose negative gradient is the force
    f = T_n(Δn) − K u of `_relax_cohesive` (mean removed on a half-plane, ⟨u⟩ = 0).
    Polak–Ribière+ CG on the nodal displacements preconditioned as the hard-wall CG, s = K⁻¹ f
    (K(q)⁻¹ on the modes; the q = 0 mode clamped on a half-plane). FIRE's M = K + ⟨k_loc⟩ was
    measured worse here (2^14, δn = 0.25 nm: 2× the iterations; a Jacobi split for the stiff
    contact nodes 1.5–2×): the line search handles the interface stiffness. The line search
    along d needs no FFT: d·Ku and d·Kd are sums (below), and
    dE/dα = d·Ku + α d·Kd − Σ T_n(Δn − αd) d, d²E/dα² = d·Kd + Σ k_loc d² are nodal sums,
    so safeguarded Newton on dE/dα (bracketed; secant or bisection when Newton leaves the
    bracket or the curvature is negative; stop at |dE/dα| ≤ line_search_tol·|dE/dα(0)|) costs
    one exp over the nodes per trial (≈ 1.05 trials per iteration measured). The force is kept
    in Fourier space, f̂ = rfft(T_n) − K û (q = 0 clamped on a half-plane), so K u never drifts
    and an iteration costs one FFT pair (rfft T_n, irfft d); the stopping test is
    `_relax_cohesive`'s, max_j |f_j| < tolerance · p_ref on the nodes (one more irfft), taken
    every `check_every` iterations and whenever the energy norm (f·K⁻¹f)^½ times the last
    measured max-norm/energy-norm ratio predicts it passes: the converged states and their
    residuals mean what FIRE's do.

    Cost per iteration (issue 13): the nodal law work (exp, the line search's sums) runs on the near
    set only, the nodes with Δn < (s_c + NCG_NEAR_MARGIN) δn, where s_c e^{−s_c} (φn/δn) =
    NCG_FAR_FRACTION · tolerance · p_ref (`_attraction_cut`): a far node's attraction is below a
    thousandth of the stopping test. The set is rebuilt from a fresh irfft when a step could have
    brought a far node (Δn falls by α max_j d_j) within s_c δn, and a state that passes the test is
    checked again with every node's attraction (if that fails, every node stays in from then on),
    so the converged states are those of the plain NCG. The spectral algebra is one pass per
    product: d·Ku = Σ_j d_j T_n,j − f·d (f = T_n − K u − ⟨T_n⟩, Σ_j d_j = 0 on a half-plane) and,
    with K s = f, d·Kd = f·s + 2β f·d_old + β² d_old·K d_old: no K d.

    Fallback: a step NCG does not finish within min(NCG_BUDGET, max_iterations / 2)
    iterations, or whose line search finds no descent, restarts from the same guess with
    FIRE (`_relax_cohesive`) and the rest of the iterations; `Relaxed.method` is then
    "ncg→fire" and the message says why.
    """
    n = model.nodes
    fft = _Fft(n)
    clamp = model.half_plane
    cz = law.law
    phi, dn = float(cz.work_normal), float(cz.length_normal)
    tn_scale, kn_scale = phi / dn, phi / dn**2
    p_ref = model.reference_traction
    budget = min(NCG_BUDGET, settings.max_iterations // 2) if settings.max_iterations > 1 else 1
    k = np.ascontiguousarray(np.real(model.k_zz), dtype=float)

    def preconditioner():
        g = np.zeros(k.size)
        np.divide(1.0, k, out=g, where=k > 0)
        if clamp:
            g[0] = 0.0
        return g

    g = preconditioner()
    products, direction, advance = kernels.ncg_kernels()  # the spectral algebra (numpy or fused)
    cut = _attraction_cut(NCG_FAR_FRACTION * settings.tolerance * p_ref / tn_scale)  # s_c

    def scaled_gap(gap_nodes):
        """(s, e^{−s}) with s = Δn/δn, capped at −MAX_COMPRESSION against overflow."""
        s = gap_nodes * (1.0 / dn)
        np.maximum(s, -laws.MAX_COMPRESSION, out=s)
        return s, np.exp(-s)

    def near(margin, first=False):
        """(near, Δn on it, s, e^{−s}) at the state uh: the nodes with Δn < (s_c + margin) δn
        (slice(None): every node), from a fresh irfft."""
        gap_all = z_ind - fft.irfft(uh)
        if first:  # an initial guess out of the law's range raises, as FIRE's does
            laws._check_compression(gap_all, dn)
        idx = np.flatnonzero(gap_all < (cut + margin) * dn) if np.isfinite(cut) else None
        if idx is None or idx.size > NCG_NEAR_FULL * n:
            return slice(None), gap_all, *scaled_gap(gap_all)
        gap_near = gap_all[idx]
        return idx, gap_near, *scaled_gap(gap_near)

    t_nodes = np.zeros(n)  # T_n on every node: zero off the near set

    def traction_hat():
        """(rfft(T_n), T_n on the near set), T_n = (φn/δn) s e^{−s} (seed Eq. 3) on the near set, 0 off it."""
        t = sv * ev
        t *= tn_scale
        if isinstance(idx, slice):
            return fft.rfft(t), t
        t_nodes[idx] = t
        return fft.rfft(t_nodes), t

    def full_residual():
        """max_j |f_j| / p_ref with every node's attraction (the converged state's check)."""
        gap_all = z_ind - fft.irfft(uh)
        s_all, e_all = scaled_gap(gap_all)
        f_all = fft.rfft(tn_scale * s_all * e_all)
        f_all -= k * uh
        if clamp:
            f_all[0] = 0.0
        return float(np.max(np.abs(fft.irfft(f_all)))) / p_ref, gap_all, s_all, e_all, f_all

    guess = np.array(u_hat, dtype=complex, copy=True)
    uh = np.array(guess[-1], dtype=complex, copy=True)
    if clamp:
        uh[0] = 0.0
    idx, gap, sv, ev = near(NCG_NEAR_MARGIN, first=True)
    slack = NCG_NEAR_MARGIN * dn  # how far a far node may still approach before the near set is stale
    f_hat, t = traction_hat()  # f̂ = rfft(T_n) − K û, q = 0 clamped on a half-plane
    f_hat -= k * uh
    if clamp:
        f_hat[0] = 0.0
    d_hat = np.zeros_like(f_hat)  # the search direction (spectrum), updated in place
    f_old = f_hat
    rz_old, c2 = 1.0, 0.0  # f_old·K⁻¹f_old, d·Kd of the last direction
    restart = True
    residual, converged, message, failed = np.inf, False, "", ""
    eta = settings.line_search_tol
    ratio = None  # last max|f| / rms(f): predicts when the max-norm test can pass
    it = 0
    while True:
        rz, f_old_s, f_d_old = products(f_hat, f_old, d_hat, g, n)  # f·s, f_old·s, f·d_old; s = K⁻¹ f
        e_norm = np.sqrt(max(rz, 0.0))
        if ratio is None or it % settings.check_every == 0 or e_norm * ratio < settings.tolerance * p_ref:
            # the test of `_relax_cohesive` (verification.mutations' stop-early-cohesive mutates all three)
            residual = float(np.max(np.abs(fft.irfft(f_hat)))) / model.reference_traction
            if residual < settings.tolerance:
                if not isinstance(idx, slice):  # the far nodes' attraction included: converged as FIRE's is
                    residual, gap, sv, ev, f_hat = full_residual()
                    if not residual < settings.tolerance:  # it counts after all: every node is near from here
                        idx, restart, ratio = slice(None), True, None
                        t = tn_scale * sv * ev
                        continue
                converged = True
                break
            ratio = residual * p_ref / e_norm if e_norm > 0 else 1.0
            if not np.isfinite(residual):
                failed = "non-finite force residual"
                break
        if it >= budget:
            residual = float(np.max(np.abs(fft.irfft(f_hat)))) / p_ref
            failed = f"not converged after {it} iterations (residual {residual:.3g} p_ref)"
            break
        it += 1
        # d = s + β d_old, and K s = f (K K⁻¹ = 1 on every mode but a half-plane's q = 0, where s = f = 0):
        # dE/dα(0) = −f·d = −(f·s + β f·d_old), d·Kd = f·s + 2β f·d_old + β² d_old·K d_old, no K d needed
        beta = 0.0 if restart else max(0.0, (rz - f_old_s) / rz_old)  # Polak–Ribière+
        slope0, c2 = -(rz + beta * f_d_old), rz + beta * (2.0 * f_d_old + beta * c2)
        if not slope0 < 0:  # not a descent direction: restart along s
            beta, slope0, c2 = 0.0, -rz, rz
            if not slope0 < 0:
                failed = "no descent direction"
                break
        direction(f_hat, g, beta, d_hat)  # d̂ ← ŝ + β d̂
        restart = False
        f_old, rz_old = f_hat, rz
        d_all = fft.irfft(d_hat)
        approach = float(np.max(d_all)) if not isinstance(idx, slice) else 0.0  # Δn falls by α d: d > 0 approaches
        for _ in range(2):  # a second pass only when the step left the near set stale: rebuilt, searched again
            d = d_all[idx]
            # d·Ku = Σ_j d_j T_n,j − d·f: f = T_n − K u − ⟨T_n⟩ and Σ_j d_j = 0 on a half-plane
            c1 = _dot(d, t) + slope0

            def curvature(s_a, e_a):  # d²E/dα² = d·Kd + Σ k_loc d², k_loc = (φn/δn²)(1 − s) e^{−s}
                x = e_a * d
                return c2 + kn_scale * (_dot(x, d) - float(np.einsum("i,i,i->", s_a, x, d)))

            alpha, found, gap_a, s_a, e_a = _ncg_line_search(curvature, c1, c2, slope0, gap, sv, ev, d, dn,
                                                             tn_scale, scaled_gap, eta, settings.max_move)
            if alpha * approach <= slack:
                break
            margin = NCG_NEAR_MARGIN + 2.0 * alpha * approach / dn
            idx, gap, sv, ev = near(margin)
            slack = margin * dn
            t = tn_scale * sv * ev
            t_nodes[:] = 0.0
        if not found and beta > 0.0:  # a conjugate direction failed: retry once along s = K⁻¹ f
            restart = True
            continue
        if not found:
            failed = "line search found no minimum along the search direction"
            break
        gap, sv, ev = gap_a, s_a, e_a
        slack -= alpha * approach
        f_hat, t = traction_hat()
        advance(uh, d_hat, alpha, k, f_hat)  # û ← û + α d̂, f̂ ← rfft(T_n) − K û
        if clamp:
            f_hat[0] = 0.0
    if failed:
        budget_left = settings.max_iterations - it
        second = _relax_cohesive(model, law, z_ind, guess, replace(settings, cohesive="fire",
                                 max_iterations=max(budget_left, 1)), wall_tolerance)
        second.iterations += it
        second.fft_pairs += fft.pairs
        second.method = "ncg→fire"
        second.message = (f"NCG stopped ({failed}), restarted with FIRE: " + (second.message or "converged"))
        return second
    pairs = fft.pairs
    out = _finish(model, law, z_ind, uh[None, :], it, residual, converged, message, wall_tolerance)
    out.fft_pairs = pairs + 0.5
    out.method = "ncg"
    return out


def _ncg_line_search(curvature, c1, c2, slope0, gap, sv, ev, d, dn, tn_scale, scaled_gap, eta, max_move):
    """Safeguarded Newton on dE/dα along d (`_relax_cohesive_ncg`): (α, found, Δn, s, e^{−s} at α).

    dE/dα = c1 + α c2 − (φn/δn) Σ_j s_j e^{−s_j} d_j at Δn − α d; stops at |dE/dα| ≤ eta |dE/dα(0)|.
    found = False with α = 0: no step lowers E.
    """
    curv0 = curvature(sv, ev)
    reach = float(np.max(np.abs(d))) if d.size else 0.0
    alpha = -slope0 / curv0 if curv0 > 0 else (max_move * dn / reach if reach > 0 else 1.0)
    lo, hi = 0.0, np.inf
    p_lo, p_hi = slope0, np.inf
    found = False
    widths = []
    for _ in range(100):
        gap_a = d * (-alpha)
        gap_a += gap
        s_a, e_a = scaled_gap(gap_a)
        p = c1 + alpha * c2 - tn_scale * float(np.einsum("i,i,i->", s_a, e_a, d))
        if not np.isfinite(p):
            hi, p_hi = alpha, np.inf
        elif abs(p) <= eta * abs(slope0):
            found = True
            break
        elif p < 0:
            lo, p_lo = alpha, p
        else:
            hi, p_hi = alpha, p
        c = curvature(s_a, e_a) if np.isfinite(p) else np.nan
        nxt = alpha - p / c if c > 0 else np.nan
        if np.isfinite(hi):
            if not lo < nxt < hi:
                nxt = lo - p_lo * (hi - lo) / (p_hi - p_lo) if np.isfinite(p_hi) else np.nan
                if not (lo + 0.01 * (hi - lo) < nxt < hi - 0.01 * (hi - lo)):
                    nxt = 0.5 * (lo + hi)
            widths.append(hi - lo)
            if len(widths) > 2 and widths[-1] > 0.5 * widths[-3]:  # Newton creeps (steep repulsive
                nxt = 0.5 * (lo + hi)  # side of the law): bisect whenever two trials did not halve the bracket
            if hi - lo <= 1e-14 * hi:
                alpha = lo if lo > 0 else hi
                gap_a = d * (-alpha)
                gap_a += gap
                s_a, e_a = scaled_gap(gap_a)
                found = alpha > 0
                break
        elif not nxt > alpha:
            nxt = 4.0 * alpha
        alpha = nxt
    if not found and lo > 0:  # no tight minimum found, but E decreases up to lo: take that step
        alpha = lo
        gap_a = d * (-alpha)
        gap_a += gap
        s_a, e_a = scaled_gap(gap_a)
        found = True
    if not found:
        alpha = 0.0
    return alpha, found, gap_a, s_a, e_a



def _mean_shift(u_z, z_ind, pinned=None):
    """Scalar c with ⟨min(u_z + c, z_ind)⟩ = 0 (m): Euclidean projection onto {u ≤ z_ind, ⟨u⟩ = 0}.

    φ(c) = ⟨min(u + c, b)⟩ is concave, increasing and piecewise linear; Newton started
    left of the root approaches it monotonically from below and ends in a few steps.
    `pinned` nodes are held on the wall (u = z_ind) and take no shift.
    """
    if pinned is not None and pinned.any():
        return _pinned_shift(u_z, z_ind, pinned, u_z.size)
    # at c0 = min(b − u) every node is free, so φ(c0) = ⟨u⟩ + c0; if that is ≥ 0 the root
    # lies in the all-free range, c = −⟨u⟩; otherwise Newton from c0 (left of the root).
    mean_u = float(np.mean(u_z))
    c = float(np.min(z_ind - u_z))
    if mean_u + c >= 0.0:
        return -mean_u
    for _ in range(100):
        free = u_z + c < z_ind
        phi = np.mean(np.where(free, u_z + c, z_ind))
        slope = np.mean(free)
        if phi >= 0.0 or slope == 0.0:
            if slope == 0.0 and phi < 0.0:
                raise ValueError("hard wall everywhere below the mean plane: full contact reached, "
                                 "the clamped half-plane cannot be indented further")
            return c
        step = -phi / slope
        c += step
        if step <= 1e-15 * (abs(c) + np.max(np.abs(z_ind))):
            return c
    return c


def _pinned_shift(u_z, z_ind, pinned, n_total):
    """`_mean_shift` with pinned nodes fixed at z_ind: ⟨where(pinned, b, min(u + c, b))⟩ = 0."""
    target = -float(np.sum(z_ind[pinned])) / n_total  # required mean of the others, times their share
    u, b = u_z[~pinned], z_ind[~pinned]
    share = u.size / n_total
    # ⟨min(u + c, b)⟩_others · share = target  ⇔  ⟨min(u + c − t, b − t)⟩ = 0 with t = target/share
    t = target / share
    return _mean_shift(u - t, b - t)


def _wall_balance(model, ku, on_wall):
    """Elastic plus far-field force on every node of a hard-wall configuration (Pa).

    −(Ku)_j, plus on a half-plane the uniform far-field load p that keeps ⟨u⟩ = 0,
    p = mean of (Ku) over the free nodes. On wall nodes, a positive value is the
    contact pressure the wall must supply; on free nodes it is the residual.
    """
    free = ~on_wall
    p = float(np.mean(ku[free])) if model.half_plane and free.any() else 0.0
    return p - ku


def _fire_wall_velocity(fire, force, u, v, stuck, on_wall, inv_mass, inv_mass_diag, n):
    """FIRE velocity step of the projected wall dynamics (`_relax_hard_wall`, `_relax_cohesive_wall`).

    Mass-weighted acceleration M⁻¹f, zeroed on the stuck nodes and capped at f_j·diag(M⁻¹) on wall
    nodes that pull away (the fixed points are then the KKT points, `_relax_hard_wall`); FIRE's
    power check, its restart stepping u back half a step. u and v in place; returns the new Δt.
    """
    acc = scipy.fft.irfft(inv_mass * scipy.fft.rfft(force), n=n)
    acc[stuck] = 0.0  # precondition on the non-stuck subspace only
    pulling = on_wall & (force < 0)  # must leave the wall: never let M⁻¹ smear it back in
    acc[pulling] = np.minimum(acc[pulling], force[pulling] * inv_mass_diag)
    restart = fire.adapt(_dot(force, v))
    dt = fire.dt
    if restart:
        u -= 0.5 * dt * v
        v[:] = 0.0
    v += dt * acc
    a_norm = np.sqrt(_dot(acc, acc))
    if a_norm > 0:
        mix = fire.alpha * np.sqrt(_dot(v, v)) / a_norm
        v *= 1 - fire.alpha
        v += mix * acc
    return dt


def _project_onto_wall(u, v, z_ind, stuck, clamp):
    """Positions onto {u ≤ z_ind} (on a half-plane also ⟨u⟩ = 0, the stuck nodes pinned on the wall);
    the velocity into the wall of the projected nodes is removed (v in place). Returns the new u."""
    shift = _mean_shift(u, z_ind, stuck) if clamp else 0.0
    projected = np.where(stuck, z_ind, np.minimum(u + shift, z_ind))
    hit = projected < u + shift
    v[hit] = np.minimum(v[hit], 0.0)
    return projected


def _relax_hard_wall(model, law, z_ind, u_hat, settings, wall_tolerance):
    """Hard-wall relaxation in real space (normal only; see module docstring).

    The wall reaction enters as a force: on nodes touching the wall, a net force
    pushing into it is cancelled (net 0), so the dynamics sees the true KKT
    residual. A Euclidean projection after a non-diagonal preconditioner has
    spurious fixed points (a wall node's pull-off force smeared into push-in
    accelerations that the wall absorbs), so the mass-weighted acceleration M⁻¹f
    is zeroed on the stuck nodes (Z M⁻¹ Z, positive definite on the rest), and on
    wall nodes that pull away it is capped at their diagonal-preconditioned value
    f_j·diag(M⁻¹) < 0: at a fixed point no node pulls on the wall and f = 0 on the
    free set, i.e. the fixed points are exactly the KKT points. Positions are
    projected onto {u ≤ z_ind} (and ⟨u⟩ = 0 for the half-plane, stuck nodes
    pinned), and the velocity into the wall of projected nodes is removed.
    Each iteration costs two rfft/irfft pairs: K u and the mass-weighted acceleration
    (FIRE), or the damped velocity update in Fourier space (Verlet, uniform mass).
    """
    n = model.nodes
    elastic = _Elastic(model, 0.0, 0.0)
    k = model.k_zz
    inv_mass = elastic.inv_mass[0]
    inv_mass_diag = float(np.sum(_spectral_weights(n) * inv_mass)) / n  # real-space diagonal of M⁻¹
    fire = None if settings.method == "verlet" else _Fire(settings)
    if fire is None:
        rho, gdt = _verlet_coefficients(k, settings)
    dt = fire.dt if fire else 1.0
    u = scipy.fft.irfft(u_hat[-1], n=n)
    shift = _mean_shift(u, z_ind) if elastic.clamp else 0.0
    u = np.minimum(u + shift, z_ind)
    v = np.zeros(n)
    residual, converged, message = np.inf, False, ""
    it = 0
    for it in range(1, settings.max_iterations + 1):
        on_wall = z_ind - u <= wall_tolerance
        force, stuck = _wall_net_force(model, k, u, on_wall, n)
        if it % settings.check_every == 0 or it == 1:
            residual = float(np.max(np.abs(force))) / model.reference_traction
            if residual < settings.tolerance:
                converged = True
                break
            if not np.isfinite(residual):
                message = "diverged: non-finite force residual"
                break
        if fire is None:
            v_hat = scipy.fft.rfft(v)
            v_hat = ((1 - gdt / 2) * v_hat + dt * scipy.fft.rfft(force) / rho) / (1 + gdt / 2)
            if elastic.clamp:
                v_hat[0] = 0.0
            v = scipy.fft.irfft(v_hat, n=n)
        else:
            dt = _fire_wall_velocity(fire, force, u, v, stuck, on_wall, inv_mass, inv_mass_diag, n)
        u += dt * v
        u = _project_onto_wall(u, v, z_ind, stuck, elastic.clamp)
    else:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"
    u_hat = scipy.fft.rfft(u)[None, :]
    return _finish(model, law, z_ind, u_hat, it, residual, converged, message, wall_tolerance)


def _relax_hard_wall_cg(model, law, z_ind, u_hat, settings, wall_tolerance):
    """Hard wall by projected preconditioned conjugate gradients (active set; normal only).

    The step's problem is min ½ uᵀKu over u ≤ z_ind (half-plane: and ⟨u⟩ = 0, whose
    multiplier is the far-field pressure of `_wall_balance`). Nodes on the wall form the
    active set A (held at their place); on the others, F, the force r = p − Ku (`_wall_balance`)
    is the negative gradient, and CG runs on F with the mass weighting of the FIRE
    solver as preconditioner, s = Π M⁻¹ r (Π: zero on A and, on a half-plane, mean
    zero over F, so ⟨u⟩ stays 0): the free elastic modes are solved at once, what is
    left is the coupling through the few contact nodes, hence iterations nearly flat in N.

    Set changes (Polonsky & Keer 1999; Dostál's proportioning):
    * a CG step that takes free nodes through the wall is kept and projected (the
      nodes go onto the wall and into A, ⟨u⟩ restored by `_mean_shift` with A pinned),
      K u is recomputed exactly and CG restarts;
    * wall nodes whose force pulls them off (r < 0) are released once the norm of those
      forces exceeds `proportioning` × the norm of r on F (CG restarts).

    Stop: the residual of `_relax_hard_wall` (max |net force| of `_wall_net_force`,
    pulling wall nodes included, stuck ones zero) below tolerance · p_ref, recomputed
    with a fresh K u, so the converged states and their residuals mean what FIRE's do;
    the fixed points are the KKT points (no pulling wall node, zero force off the wall,
    no penetration). Cost: two FFT pairs per iteration (K d and M⁻¹ r), one more per
    projection; K u is updated with the step instead of recomputed.
    """
    n = model.nodes
    fft = _Fft(n)
    clamp = model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz))
    g = np.ascontiguousarray(np.real(_Elastic(model, 0.0, 0.0).inv_mass[0]))  # M⁻¹ = K⁻¹, 0 at q = 0 (half-plane)
    p_ref = model.reference_traction
    tol = settings.tolerance * p_ref
    gamma2 = settings.proportioning**2
    z_ind = np.ascontiguousarray(z_ind, dtype=float)

    u = fft.irfft(np.ascontiguousarray(u_hat[-1]))
    shift = _mean_shift(u, z_ind) if clamp else 0.0
    u = np.minimum(u + shift, z_ind)
    # work arrays, allocated once; the active set A (a few % of the nodes at most) is kept as indices,
    # so that everything it touches costs O(|A|) and the loop makes no boolean-mask copies of length N
    ku, r, s, d, kd, tmp = (np.empty(n) for _ in range(6))
    d[:] = 0.0
    through = np.empty(n, bool)
    fft.apply_to(k, u, ku)
    act = np.flatnonzero(z_ind - u <= wall_tolerance)
    rz_old = 1.0
    restart, checked = True, False
    residual, converged, message = np.inf, False, ""
    it = 0
    while it < settings.max_iterations:
        n_free = n - act.size
        p_far = (float(np.sum(ku)) - float(np.sum(ku[act]))) / n_free if clamp and n_free else 0.0
        np.subtract(p_far, ku, out=r)  # force (`_wall_balance`); on A, the wall's load
        force_act = r[act]
        r[act] = 0.0
        pull = force_act < 0
        r_free2 = _dot(r, r)
        if pull.any():
            f_pull = force_act[pull]
            pull2 = _dot(f_pull, f_pull)
            if pull2 > gamma2 * r_free2 or r_free2 < tol * tol:  # proportioning: release them
                act = act[~pull]
                restart = True
                continue
        # max |r| < tol needs Σ r² < n_free·tol²: only then is the max worth a pass over r
        worst = max(float(np.max(r)), -float(np.min(r))) if n_free and r_free2 < n_free * tol * tol else np.inf
        if n_free == 0:
            worst = 0.0
        if worst < tol and not checked:  # candidate: the solver's residual with a fresh K u
            residual, converged, message = _wall_check(model, fft, k, u, ku, z_ind, wall_tolerance, settings.tolerance)
            if converged or message:
                break
            restart, checked = True, True  # next: a CG iteration (or a release) before checking again
            continue
        it += 1
        checked = False
        fft.apply_to(g, r, s)
        s[act] = 0.0
        if clamp:  # mean zero over F (A stays 0)
            s -= float(np.sum(s)) / n_free
            s[act] = 0.0
        rz = _dot(r, s)
        if restart or rz_old <= 0:
            np.copyto(d, s)
            restart = False
        else:
            d *= rz / rz_old
            d += s
        rz_old = rz
        fft.apply_to(k, d, kd)
        curvature = _dot(d, kd)
        if not curvature > 0:
            message = "diverged: non-positive curvature along the search direction"
            break
        alpha = rz / curvature
        np.multiply(d, alpha, out=tmp)
        u += tmp
        np.multiply(kd, alpha, out=tmp)
        ku += tmp
        np.greater(u, z_ind, out=through)
        if through.any():  # Polonsky–Keer: keep the step, put the nodes onto the wall, restart
            if clamp:
                active = np.zeros(n, bool)
                active[act] = True
                active |= through
                shift = _mean_shift(u, z_ind, active)
                u = np.where(active, z_ind, np.minimum(u + shift, z_ind))
                act = np.flatnonzero(u >= z_ind)
            else:
                np.minimum(u, z_ind, out=u)
                act = np.union1d(act, np.flatnonzero(through))
            fft.apply_to(k, u, ku)
            restart = True
        if not np.isfinite(alpha):
            message = "diverged: non-finite step"
            break
    else:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"
    if not converged and not message:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"
    u_hat = fft.rfft(u)[None, :]
    pairs = fft.pairs
    out = _finish(model, law, z_ind, u_hat, it, residual, converged, message, wall_tolerance)
    out.fft_pairs = pairs + 1.5  # _finish: one irfft of u_hat and one pair for K u
    out.method = "cg"
    return out


#: Half-width (nodes) of the band of K_AA that preconditions the dual hard-wall CG (`_band_stiffness`).
#: Measured (bench_vs_tamaas.py's ramp, N = 2^16 / 2^17, medians of 10 steps): FFT pairs per step
#: 61.5 / 80 at 4, 56.5 / 73.5 at 8, 54 / 67.5 at 16, 52 / 64 at 32, 52.5 / 64.5 at 64.
DUAL_BAND_HALF_WIDTH = 32
#: The dual hard-wall CG hands a step over to the primal only when its contact set grows past this
#: multiple of `Settings.dual_contact_limit` (`_relax_hard_wall_dual`). Measured (section 7, N = 2^16):
#: with factor 1, steps ending at a_rel = 0.025–0.055 were handed over mid-way and cost 1.1–1.5× the
#: dual alone.
DUAL_TRANSIENT_FACTOR = 2.0


def _band_stiffness(k_kernel, act, n, half_width):
    """K_AA truncated to |i − j| ≤ half_width (CSR, Pa/m): the dual CG's preconditioner.

    k_kernel: real-space kernel of K (K_ij = k_kernel[(i − j) mod n]); act: sorted node indices.
    The band counts |i − j| along the index, not around the period. Rows of K sum to K(q = 0) ≥ 0 with
    negative off-diagonal entries, so a row that loses an entry (A short of all nodes, or the band
    cut) is strictly diagonally dominant: the truncation is symmetric positive definite.
    """
    lo = np.searchsorted(act, act - half_width)
    hi = np.searchsorted(act, act + half_width, side="right")
    counts = hi - lo
    indptr = np.zeros(act.size + 1, np.int64)
    np.cumsum(counts, out=indptr[1:])
    cols = np.repeat(lo - indptr[:-1], counts) + np.arange(indptr[-1])
    rows = np.repeat(np.arange(act.size), counts)
    data = k_kernel[np.abs(act[rows] - act[cols])]  # K_ij = k(|i − j|): exactly symmetric
    return scipy.sparse.csr_matrix((data, cols, indptr), shape=(act.size, act.size))


def _relax_hard_wall_dual(model, law, z_ind, u_hat, settings, wall_tolerance):
    """Hard wall by projected preconditioned CG on the contact pressures (the dual, small contact sets).

    With P ≥ 0 the wall's pressure on the nodes (Pa), u = −G P (G = K⁻¹; on a half-plane
    G(0) = 0, so ⟨u⟩ = 0 and the far-field load is ⟨P⟩) and the gap Δ = z_ind − u = z_ind + G P,
    the step is  min ½ Pᵀ G P + z_indᵀ P  over P ≥ 0  (gradient Δ; KKT: P ≥ 0, Δ ≥ 0, P Δ = 0),
    the primal problem of `_relax_hard_wall_cg` seen from the wall. CG runs on the contact set
    A = {P > 0} with residual −Δ_A and preconditioner K_AA truncated to |i − j| ≤
    DUAL_BAND_HALF_WIDTH (`_band_stiffness`; G⁻¹ = K, and K's kernel decays as 1/x² while G's is
    logarithmic): a sparse product, so an iteration costs one FFT pair (G d) where the primal CG
    needs two (K d and its preconditioner K⁻¹ r). s = K_band Δ_A is ≈ the nodal force the gap
    error makes, the stopping measure.

    Set changes, as the primal: a step that drives pressures negative is kept and projected
    (P ← max(P, 0), the nodes leave A, Δ recomputed, restart: Polonsky & Keer 1999); nodes off A
    that penetrate (Δ < 0) join A with P = 0 once the norm of their gaps exceeds `proportioning` ×
    that of Δ_A (restart).

    Stop: the same residual as `_relax_hard_wall_cg` (max |net force| of `_wall_net_force`, K u
    recomputed from u = z_ind on A, z_ind − max(Δ, 0) off A) below tolerance · p_ref; the
    candidate is tested when max |s| < ½ tolerance · p_ref, then at tenfold tighter thresholds.
    A guess that already passes is returned unchanged (iterations 0): the fixed points are the
    KKT points. The primal `_relax_hard_wall_cg` takes over from the guess when its contact set
    holds more than `Settings.dual_contact_limit` of the nodes (beyond, the band products and set
    changes cost more than the pair they save; measured on whole Fig. 3 hard-wall study tasks, N = 2^17,
    0.04 nm steps, CPU s for limits 0 / 0.05 / 0.15 / 0.3: 36.9 / 27.5 / 23.5 / 24.7 (a_rel up to
    0.25) and – / 17.3 / 14.0 / 13.6 (up to 0.083); with 1.8 nm jumps (benchmarks/bench_vs_tamaas.py,
    section 7) the dual is 1.05× the primal at a_rel 0.08 and 1.7× at 0.13), and from
    the current state when A grows past DUAL_TRANSIENT_FACTOR × that limit (the nodes that join in
    bulk after an extrapolated guess can double A before the projections thin it out: measured
    1553 → 745 nodes at N = 2^17), when A would hold every node but one (a half-plane's G_AA is
    singular on all nodes), or when the tighter thresholds do not reach the tolerance.
    """
    n = model.nodes
    fft = _Fft(n)
    clamp = model.half_plane
    k = np.ascontiguousarray(np.real(model.k_zz))
    g = np.ascontiguousarray(np.real(_Elastic(model, 0.0, 0.0).inv_mass[0]))
    p_ref = model.reference_traction
    tol = settings.tolerance * p_ref
    gamma2 = settings.proportioning**2
    limit = settings.dual_contact_limit * n
    transient_limit = min(DUAL_TRANSIENT_FACTOR * limit, n - 2)
    z = np.ascontiguousarray(z_ind, dtype=float)

    u_hat_z = np.ascontiguousarray(u_hat[-1])
    u = fft.irfft(u_hat_z)
    ku = fft.irfft(k * u_hat_z)
    if float(np.max(u - z)) <= wall_tolerance:  # feasible up to round-off: already converged?
        residual = _wall_residual(model, u, ku, z, wall_tolerance)
        if residual < settings.tolerance:
            out = _finish(model, law, z_ind, fft.rfft(np.minimum(u, z))[None, :], 0, residual, True, "",
                          wall_tolerance)
            out.fft_pairs, out.method = fft.pairs + 1.5, "cg-dual"  # _finish: 1.5 pairs
            return out
    # the guess's pressures: P = p_far − K u where positive; p_far = K u on the nodes the guess leaves free
    free = z - u > 0
    p_far = float(np.median(ku[free])) if clamp and free.any() else 0.0
    pressure = p_far - ku  # full length; zero off A from here on
    on_wall = pressure > 1e-9 * float(np.max(np.abs(ku)))
    if np.count_nonzero(on_wall) > limit:  # a large contact set: the primal CG from the guess
        out = _relax_hard_wall_cg(model, law, z_ind, u_hat, settings, wall_tolerance)
        out.fft_pairs += fft.pairs
        return out
    pressure[~on_wall] = 0.0
    act = np.flatnonzero(on_wall)
    k_kernel = fft.irfft(k.astype(complex))
    sparse_in, g_d, gap = np.zeros(n), np.empty(n), np.empty(n)

    def g_times(values, out):  # out ← G χ_A values: one FFT pair
        sparse_in[act] = values
        fft.apply_to(g, sparse_in, out)
        sparse_in[act] = 0.0
        return out

    def recompute_gap():
        g_times(pressure[act], gap)
        np.add(gap, z, out=gap)

    def primal_state():
        u_new = z - np.maximum(gap, 0.0)
        u_new[act] = z[act]
        return u_new

    recompute_gap()
    # the band on a superset U ⊇ A, rebuilt only when nodes outside U join A (leaving A needs no rebuild:
    # rows and columns of U \ A meet zeros and are not read)
    band_nodes = act
    k_band = _band_stiffness(k_kernel, band_nodes, n, DUAL_BAND_HALF_WIDTH)
    band_in = np.zeros(band_nodes.size)

    def precondition(r):  # K_band restricted to A, times r
        at = np.searchsorted(band_nodes, act)
        band_in[at] = r
        out = (k_band @ band_in)[at]
        band_in[at] = 0.0
        return out

    d = np.zeros(act.size)
    rz_old, restart, stop = 1.0, True, 0.5
    residual, converged, message, hand_over = np.inf, False, "", False
    it = 0
    while not hand_over and it < settings.max_iterations:
        r = -gap[act]
        s = precondition(r)
        worst = float(np.max(np.abs(s))) if act.size else 0.0
        # penetration off A, counted once its force (≈ K(0)_jj |Δ_j|) is not negligible
        enter = np.empty(0, np.int64)
        penetration_tol = 0.1 * stop * tol / k_kernel[0]
        if float(np.min(gap)) < -penetration_tol:
            off = gap < -penetration_tol
            off[act] = False
            enter = np.flatnonzero(off)
        if enter.size:
            g_enter = gap[enter]
            if _dot(g_enter, g_enter) > gamma2 * _dot(r, r) or worst < stop * tol:
                act = np.union1d(act, enter)
                hand_over = act.size > transient_limit
                if not np.isin(enter, band_nodes, assume_unique=True).all():
                    band_nodes = act
                    k_band = _band_stiffness(k_kernel, band_nodes, n, DUAL_BAND_HALF_WIDTH)
                    band_in = np.zeros(band_nodes.size)
                restart = True
                continue
        if worst < stop * tol:  # candidate: the primal residual with a fresh K u
            u = primal_state()
            residual, converged, message = _wall_check(model, fft, k, u, ku, z, wall_tolerance, settings.tolerance)
            if converged or message:
                break
            stop *= 0.1
            hand_over = stop < 1e-4
            continue
        it += 1
        rz = _dot(r, s)
        if restart or rz_old <= 0:
            d = s.copy()
            restart = False
        else:
            d = s + (rz / rz_old) * d
        rz_old = rz
        g_times(d, g_d)
        curvature = _dot(d, g_d[act])
        if not curvature > 0:
            message = "diverged: non-positive curvature along the search direction"
            break
        alpha = rz / curvature
        if not np.isfinite(alpha):
            message = "diverged: non-finite step"
            break
        p_act = pressure[act] + alpha * d
        g_d *= alpha
        gap += g_d
        negative = p_act < 0
        if negative.any():  # Polonsky–Keer: keep the step, project, those nodes leave A
            p_act[negative] = 0.0
            pressure[act] = p_act
            act = act[~negative]
            recompute_gap()
            restart = True
        else:
            pressure[act] = p_act
    u = primal_state()
    if hand_over and not message:  # the primal CG from here, with the iterations left
        rest = replace(settings, max_iterations=settings.max_iterations - it)
        out = _relax_hard_wall_cg(model, law, z_ind, fft.rfft(u)[None, :], rest, wall_tolerance)
        out.iterations += it
        out.fft_pairs += fft.pairs + 0.5
        out.method = "cg-dual→cg"
        return out
    if not converged and not message:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"
    state = (u, ku) if converged else None  # converged: K u of this very u was the last check's
    out = _finish(model, law, z_ind, fft.rfft(u)[None, :], it, residual, converged, message, wall_tolerance, state)
    out.fft_pairs = fft.pairs + (0.0 if converged else 1.0)  # _finish otherwise: irfft of u_hat and of K û
    out.method = "cg-dual"
    return out


def _wall_check(model, fft, k, u, ku, z_ind, wall_tolerance, tolerance):
    """The hard-wall CGs' stopping test on u, K u recomputed into ku: (residual, converged, message).

    residual = max |net nodal force| of `_wall_net_force` / p_ref; converged when below `tolerance`;
    message non-empty when the residual is not finite (the solver stops: diverged)."""
    fft.apply_to(k, u, ku)
    residual = _wall_residual(model, u, ku, z_ind, wall_tolerance)
    if residual < tolerance:
        return residual, True, ""
    return residual, False, "" if np.isfinite(residual) else "diverged: non-finite force residual"


def _wall_residual(model, u, ku, z_ind, wall_tolerance):
    """max |net nodal force| of `_wall_net_force` / p_ref for u and its K u (the hard-wall residual)."""
    net, _ = _wall_net_force_from(model, ku, z_ind - u <= wall_tolerance)
    return float(np.max(np.abs(net))) / model.reference_traction


def _wall_net_force_from(model, ku, on_wall):
    """`_wall_net_force` for a given K u (Pa): (net force, stuck mask)."""
    force = _wall_balance(model, ku, on_wall)
    stuck = on_wall & (force > 0)
    return np.where(stuck, 0.0, force), stuck


def _wall_net_force(model, k, u, on_wall, n):
    """(net nodal force (Pa), stuck mask) of a hard-wall configuration.

    Net force = `_wall_balance` + wall reaction: "stuck" nodes are on the wall and
    pushed into it, so the wall cancels their force.
    """
    force = _wall_balance(model, scipy.fft.irfft(k * scipy.fft.rfft(u), n=n), on_wall)
    stuck = on_wall & (force > 0)
    return np.where(stuck, 0.0, force), stuck


def _finish(model, law, z_ind, u_hat, iterations, residual, converged, message, wall_tolerance, wall_state=None):
    """The `Relaxed` of the state u_hat. wall_state = (u_z, K u_z) of a hard-wall state whose residual was
    just taken from exactly these arrays (u_hat its rfft): the tractions then come from them, not from
    two more inverse FFTs."""
    n = model.nodes
    if wall_state is not None:
        u = wall_state[0][None, :].copy()
    else:
        u = scipy.fft.irfft(u_hat, n=n, axis=-1)
    if law.constraint:
        gap = z_ind - u[-1]
        on_wall = gap <= wall_tolerance
        gap = np.maximum(gap, 0.0)
        u[-1] = z_ind - gap
        ku = wall_state[1] if wall_state is not None else scipy.fft.irfft(model.k_zz * u_hat[-1], n=n)
        force = _wall_balance(model, ku, on_wall)
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


def _relax_cohesive_wall(model, law, z_ind, u_hat, settings, wall_tolerance):
    """Cohesive wall (`contact.laws.CohesiveWall`): Eq. 3's attraction off the wall, Δn ≥ 0 projected.

    The `_relax_hard_wall` projected FIRE (or Verlet) with the attraction T_n(Δn) added to the
    nodal force, f = T_n(Δn) + p − K u (p: the half-plane's far-field load keeping ⟨u⟩ = 0, the
    mean of K u − T_n over the nodes off the wall; 0 on a layer). Nodes on the wall (Δn ≤
    wall_tolerance) pushed into it (f > 0) are "stuck": the wall takes their force (reaction
    f ≥ 0, compressive) and their preconditioned acceleration is zeroed; wall nodes pulled away keep
    their force, capped as in `_relax_hard_wall`. After each move the nodes pushed through the
    wall are projected back (u_z ≤ z_ind, ⟨u⟩ = 0 on a half-plane with the stuck nodes pinned)
    and their velocity into the wall is removed. The mass M_q = K(q) + ⟨∂T_n/∂Δn⟩₊ (mean over
    the nodes off the wall, refreshed as in `_relax_cohesive`) and a trust region of
    `max_move`·δn per iteration follow the cohesive solver. Residual: max |net force| (stuck
    nodes 0, pulling wall nodes and free nodes their force) / p_ref, the hard wall's semantics;
    the fixed points are the KKT points: Δn ≥ 0, reaction ≥ 0 on the wall, f = 0 off it.
    Returns `Relaxed` with t_z = T_n(Δn) off the wall and T_n − reaction on it (normal only).
    """
    if model.tangential:
        raise ValueError("the cohesive wall is frictionless and normal-only: no tangential unknowns")
    cz = law.law
    n = model.nodes
    clamp = model.half_plane
    k = model.k_zz
    weights = _spectral_weights(n)

    def attraction(gap):
        return cz.tractions(gap)[0]

    def mean_slope(gap):
        off = gap > wall_tolerance
        if not off.any():
            return 0.0
        return float(np.sum(np.maximum(cz.tangent(gap[off])[0], 0.0))) / n

    def net_force(u):
        gap = z_ind - u
        on_wall = gap <= wall_tolerance
        t = attraction(gap)
        ku = scipy.fft.irfft(k * scipy.fft.rfft(u), n=n)
        free = ~on_wall
        p = float(np.mean(ku[free] - t[free])) if clamp and free.any() else 0.0
        force = t + p - ku
        stuck = on_wall & (force > 0)
        return np.where(stuck, 0.0, force), stuck, on_wall, force, t

    u = scipy.fft.irfft(u_hat[-1], n=n)
    shift = _mean_shift(u, z_ind) if clamp else 0.0
    u = np.minimum(u + shift, z_ind)
    k_mean = mean_slope(z_ind - u)

    def preconditioner(k_mean):
        inv = _Elastic(model, 0.0, k_mean).inv_mass[0]
        return inv, float(np.sum(weights * inv)) / n  # M⁻¹ and its real-space diagonal

    inv_mass, inv_mass_diag = preconditioner(k_mean)
    fire = _Fire(settings) if settings.method != "verlet" else None
    if fire is None:
        rho, gdt = _verlet_coefficients(np.real(k) + cz.initial_stiffness[1], settings)
    dt = fire.dt if fire else 1.0
    max_move = settings.max_move * cz.length_scale
    p_ref = model.reference_traction
    v = np.zeros(n)
    residual, converged, message = np.inf, False, ""
    it = 0
    for it in range(1, settings.max_iterations + 1):
        force, stuck, on_wall, _, _ = net_force(u)
        if it % settings.check_every == 0 or it == 1:
            residual = float(np.max(np.abs(force))) / p_ref
            if residual < settings.tolerance:
                converged = True
                break
            if not np.isfinite(residual):
                message = "diverged: non-finite force residual"
                break
        if fire is not None and it % settings.mass_refresh == 0:
            k_now = mean_slope(z_ind - u)
            if k_now > 2 * k_mean + 1e-300 or k_mean > 2 * k_now + 1e-300:
                k_mean = k_now  # interface stiffness changed 2×: re-weight the modes, restart FIRE
                inv_mass, inv_mass_diag = preconditioner(k_mean)
                v[:] = 0.0
                fire.reset()
        if fire is None:
            v_hat = scipy.fft.rfft(v)
            v_hat = ((1 - gdt / 2) * v_hat + dt * scipy.fft.rfft(force) / rho) / (1 + gdt / 2)
            if clamp:
                v_hat[0] = 0.0
            v = scipy.fft.irfft(v_hat, n=n)
            v[stuck] = np.minimum(v[stuck], 0.0)
        else:
            dt = _fire_wall_velocity(fire, force, u, v, stuck, on_wall, inv_mass, inv_mass_diag, n)
        move = float(np.max(np.abs(dt * v)))
        if move > max_move:  # trust region: no node moves more than max_move per iteration
            v *= max_move / move
            if fire is not None:
                fire.dt *= settings.f_dec
        u += dt * v
        u = _project_onto_wall(u, v, z_ind, stuck, clamp)
    else:
        message = f"not converged after {settings.max_iterations} iterations (residual {residual:.3g} p_ref)"
    u_hat = scipy.fft.rfft(u)[None, :]
    u = scipy.fft.irfft(u_hat[-1], n=n)
    gap = np.maximum(z_ind - u, 0.0)
    u = z_ind - gap
    _, stuck, on_wall, force, t = net_force(u)
    t_z = np.where(on_wall, t - np.maximum(force, 0.0), t)  # the wall's reaction on top of T_n (0 at Δn = 0)
    return Relaxed(u_hat=u_hat, u_z=u, u_x=np.zeros(n), gap=gap, t_z=t_z, t_x=np.zeros(n), iterations=it,
                   residual=float(residual), converged=bool(converged), message=message)
