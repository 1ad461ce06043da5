"""One load step's problem, for every GFMD algorithm: the elastic energy in Fourier space, the
interface law, their gradient and Hessian product, and the hard wall's constraint and its dual.

Units: SI (see `gfmd_contact.core.conventions`). The unknowns are the rfft coefficients û of the surface
displacement (components (x, z), or z alone); the nodal force (Pa, the negative gradient of the
energy per node area) is (reference-formulas §5.2)

    f̂ = rfft(t_interface(u)) − K(q) û,      Δn = z_ind − u_z,  Δt = −u_x,

with the q = 0 mode clamped on a half-plane (⟨u⟩ = 0, the far-field load its multiplier). Where
the law has a potential (the normal-only CZ, `gfmd_contact.core.laws.potential_normal`; a user law's energy), f = −(1/l) ∇E with
E(u) = l Σ_j [½ u_j (K u)_j + V(Δn_j)] (J/m, l = L/N); the coupled law (seed Eq. 2) has none and
only the balance f = 0 and its tangent J = K + D (`Problem.tangent_times`). The hard wall is the
constraint u_z ≤ z_ind (KKT: contact pressure ≥ 0 on the wall, f = 0 off it; `wall_balance`,
`mean_shift`); its dual, over the contact pressures P ≥ 0 with u = −G P (G = K⁻¹), is
min ½ PᵀGP + z_indᵀP (gradient: the gap, `Problem.dual_gap`). The cohesive wall adds Eq. 3's
attraction off the wall to the same constraint.

2+1-D surfaces (Model.shape = (Nx, Ny), normal-only): û of shape (1, Nx, Ny//2 + 1), real fields
(1, Nx, Ny), l the node area Lx Ly/(Nx Ny) (E in J); the algorithms run on
`flat_problem`'s view, the same problem with nodal fields and spectra flattened (`gfmd.fft`).
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np
import scipy.sparse

from .coupled_kernels import coupled_kernels, float_views, hermitian_blocks, split_block_times
from .fft import Fft, irfft_nodes, rfft_nodes


class InterfaceLaw:
    """The interface law on the solver's unknowns: tractions on the body for displacements (SI).

    The law is `model.law` (`gfmd_contact.core.laws`: the law object `gfmd_contact.core.model.build_model` chose for
    the model's unknowns; Eq. 2 where u_x is solved). `interface` and `work_tangential` are
    accepted for the callers that pass them and not used: the law object already holds the
    scene's φn, δn, φt, δt. This class only maps displacements u (c, N) to gaps, Δn = z_ind − u_z
    and Δt = −u_x, and the law's tractions back onto the components solved.
    """

    def __init__(self, model, interface=None, work_tangential=None):
        self.model = model
        self.law = model.law
        # a constraint (the hard wall) has no traction function: the algorithms project instead
        self.constraint = self.law.constraint
        # Eq. 2 on (x, z) fused in one pass (`gfmd.coupled_kernels`, the same as the law's formula to round-off)
        form = self.law.nodal_form
        self._fused = (form is not None and form[0] == "coupled exponential" and model.tangential
                       and model.components == 2)
        if self._fused:
            self._tractions = coupled_kernels()[2]
            self._params = form[1]  # (φn, δn, φt, δt)
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
        if self._fused:
            t = self._tractions(u, z_ind, self._params, np.empty_like(u))
            return t, z_ind - u[-1]
        gap, slip = self._gaps(u, z_ind)
        t = np.zeros_like(u)
        if self.constraint:  # zero off the wall; the wall's reaction is `gfmd.stopping.finish`'s
            return t, gap
        t_n, t_t = self.law.tractions(gap, slip)
        t[-1] = t_n
        if self.model.tangential:
            t[0] = t_t
        return t, gap


class Elastic:
    """K(q) and mass operators M_q = K(q) + ⟨k_loc⟩ of a model on the rfft half-spectrum."""

    def __init__(self, model, k_int_x, k_int_z):
        self.model = model
        self.clamp = model.half_plane
        self._kept = {}  # `kept`'s arrays by key
        self._block_times, self._split_times = coupled_kernels()[0], split_block_times()
        if model.tangential:
            a = model.k_xx + k_int_x
            b = model.k_xz
            d = model.k_zz + k_int_z
            det = (a * d - np.abs(b) ** 2).real
            if self.clamp:
                det.flat[0] = np.inf
            self.mass = hermitian_blocks(a, b, d)
            self.inv_mass = hermitian_blocks(d / det, -b / det, a / det)
        else:
            m = model.k_zz + k_int_z
            inv = np.zeros_like(m)
            nz = m > 0
            inv[nz] = 1.0 / m[nz]
            if self.clamp:
                inv.flat[0] = 0.0  # the q = 0 mode (1+1-D: index 0; 2+1-D: (0, 0))
            self.mass = (m,)
            self.inv_mass = (inv,)

    def kept(self, key, make):
        """make(), made at the first call for `key` and kept on this operator (one per model, `stiffness_operator`),
        read-only: what a step needs that depends on K(q) alone (real-space kernels and their sums), made once per task
        instead of once per step. The key names the FFT backend that made it, so that a kept array holds the same
        numbers as one made afresh in the step."""
        if key not in self._kept:
            value = make()
            value.flags.writeable = False
            self._kept[key] = value
        return self._kept[key]

    @functools.cached_property
    def stiffness_blocks(self):
        """K(q)'s `Blocks` (k_xx, k_xz, k_zz) of a tangential model, made at first use."""
        m = self.model
        return hermitian_blocks(m.k_xx, m.k_xz, m.k_zz)

    def _apply(self, blocks, x, out=None):
        """The block product of `blocks` ((m,) or (a, b, d): (a b; b̄ d)) with spectra x, into `out` if given (on
        `Blocks.split` where it has one: the same numbers, `gfmd.coupled_kernels.split_block_times`)."""
        if len(blocks) == 1:
            return np.multiply(blocks[0], x, out=out)
        if out is None:
            out = np.empty(x.shape, np.result_type(x, *blocks))
        split = getattr(blocks, "split", None)
        if split is not None and self._split_times is not None and float_views(x, out):
            return self._split_times(*split, x, out)
        return self._block_times(*blocks, x, out)

    def stiffness(self, x):
        """K(q) x for spectra x of shape (c, nq)."""
        m = self.model
        return self._apply(self.stiffness_blocks if m.tangential else (m.k_zz,), x)

    def mass_times(self, x):
        return self._apply(self.mass, x)

    def inverse_mass_times(self, x):
        return self._apply(self.inv_mass, x)


def stiffness_operator(model):
    """Elastic(model, 0, 0): K(q) alone, one per model, kept on the model object (in its __dict__, outside its
    fields: a new model, `dataclasses.replace` included, gets its own; it goes with the model), so that what the
    algorithms cache on it (the coarse spaces' kernel sums, `gfmd.coupled_preconditioner`,
    `gfmd.cohesive_preconditioner`) is computed once per task, not per step."""
    op = model.__dict__.get("_stiffness_operator")
    if op is None:
        op = model.__dict__["_stiffness_operator"] = Elastic(model, 0.0, 0.0)
    return op


@dataclass
class Problem:
    """One load step: the model (`gfmd_contact.core.model.Model`: K(q), unknowns, p_ref), the law on its
    unknowns, the indenter surface z_ind (m) and the gap below which a node touches a wall (m)."""

    model: object
    law: InterfaceLaw
    z_ind: np.ndarray
    wall_tolerance: float = 0.0
    #: (a start's spectrum, its `gfmd.coupled_krylov.balance_state`) where the chain evaluated that start already
    #: (`gfmd.coupled_krylov.better_start`): the coupled Newton that starts from that very array takes it (no FFT)
    start_state: tuple | None = None

    @property
    def kind(self):
        """The law's kind, the key of `gfmd.chains.CHAINS`' first level, from the law protocol: a wall (a constraint)
        with or without attraction, the coupled law on (u_x, u_z), or a normal law ("cohesive": Eq. 3, a user law, ...)."""
        if self.law.constraint:
            return "cohesive-wall" if self.law.law.adhesive else "hard-wall"
        return "coupled" if self.model.tangential else "cohesive"

    @property
    def surface(self):
        """True for a 2+1-D surface on its natural grid (not `flat_problem`'s view)."""
        return len(self.model.grid) > 1 and np.ndim(self.model.k_zz) > 1

    def _on_flat(self, method, x, field_shape):
        """`method` of the flat view applied to x (natural 2-D shapes in, natural shapes out)."""
        c = x.shape[0]
        out = getattr(flat_problem(self), method)(x.reshape(c, -1))
        return out.reshape((c,) + field_shape) if isinstance(out, np.ndarray) else out

    def displacements(self, u_hat):
        """u (c, N) of the spectra û ((c, Nx, Ny) of (c, Nx, Ny//2 + 1) on a surface)."""
        if self.surface:
            return self._on_flat("displacements", u_hat, self.model.grid)
        return irfft_nodes(u_hat, self.model.grid)

    def force(self, u_hat):
        """The nodal force f (c, N) in Pa at û: t(u) − K u (q = 0 removed on a half-plane). On a wall the
        constraint's reaction is not in it (`wall_balance`)."""
        if self.surface:
            return self._on_flat("force", u_hat, self.model.grid)
        u = self.displacements(u_hat)
        t, _ = self.law.traction(u, self.z_ind)
        f_hat = rfft_nodes(t, self.model.grid) - stiffness_operator(self.model).stiffness(u_hat)
        if self.model.half_plane:
            f_hat[:, 0] = 0.0
        return self.displacements(f_hat)

    def energy(self, u_hat):
        """E(u) = l Σ_j [½ u_j (K u)_j + V(Δn_j)] (J/m; J on a surface, l the node area), f = −(1/l) ∂E/∂u;
        inf where a wall is penetrated. The coupled law has no potential (ValueError)."""
        if self.kind == "coupled":
            raise ValueError("the coupled law (seed Eq. 2) has no potential: the problem is the balance f = 0")
        if self.surface:
            return self._on_flat("energy", u_hat, self.model.grid)
        u = self.displacements(u_hat)
        ku = self.displacements(stiffness_operator(self.model).stiffness(u_hat))
        gap = self.z_ind - u[-1]
        if self.law.constraint and float(np.min(gap)) < -self.wall_tolerance:
            return np.inf
        cz = self.law.law
        interface = 0.0 if self.kind == "hard-wall" else np.sum(cz.potential(gap))
        return self.model.node_area * float(0.5 * np.sum(u * ku) + interface)

    def tangent_times(self, u_hat, v):
        """J v = (K + D) v (Pa) for nodal fields v (c, N): the Hessian product per node area (the force's
        derivative is −J; D the nodal tangent of the law, `gfmd_contact.core.laws`; zero on a hard wall)."""
        if self.surface:
            flat = flat_problem(self)
            return flat.tangent_times(u_hat.reshape(u_hat.shape[0], -1), v.reshape(v.shape[0], -1)).reshape(v.shape)
        a_op, _, _ = coupled_operators(self.model, self.law, self.z_ind, self.displacements(u_hat),
                                       Fft(self.model.nodes, grid=self.model.grid))
        return a_op.matvec(np.asarray(v, float).ravel()).reshape(v.shape)

    def dual_gap(self, pressure):
        """The dual's gradient, the gap Δ = z_ind + G P (m) for nodal wall pressures P ≥ 0 (Pa), normal only."""
        if self.surface:
            return flat_problem(self).dual_gap(np.reshape(pressure, -1)).reshape(self.model.grid)
        g = stiffness_operator(self.model).inv_mass[0]
        return self.z_ind + irfft_nodes(np.real(g) * rfft_nodes(pressure, self.model.grid), self.model.grid)


def flat_model(model):
    """The model as the algorithms see a 2+1-D surface: q and K(q) flattened over the rfft2 half-spectrum
    (Nx·(Ny//2 + 1),), index 0 the q = 0 mode (`gfmd.fft`); grid and node area kept. 1+1-D: the model."""
    if len(model.grid) == 1 or np.ndim(model.k_zz) == 1:
        return model
    if model.tangential:
        raise ValueError("2+1-D surfaces are normal-only: no tangential unknowns (gfmd.chains)")
    return dataclasses.replace(model, q=np.ravel(model.q), k_zz=np.ravel(model.k_zz))


def flat_problem(problem):
    """The problem on flat nodal fields (N,) and flat spectra (`flat_model`); 1+1-D: the problem itself."""
    if not problem.surface:
        return problem
    z = None if problem.z_ind is None else np.ravel(problem.z_ind)
    return Problem(flat_model(problem.model), problem.law, z, problem.wall_tolerance)


def frictionless(problem):
    """The coupled problem's frictionless reduction, a potential problem (`gfmd.algorithms.ncg`): seed Eq. 3 (Eq. 2 at
    Δt = 0, T_t ≡ 0) on u_z alone, with the normal stiffness of a surface free of shear traction, the Schur complement
    k_zz − |k_xz|²/k_xx of K(q) (a half-plane's E*|q|/2, §1.1; a layer's 1/G_zz)."""
    model, cz = problem.model, problem.law.law
    k_xx, k_zz = np.real(model.k_xx), np.real(model.k_zz)
    sheared = k_xx > 0  # a half-plane's q = 0: no stiffness, nothing to condense
    k_free = k_zz.copy()
    k_free[sheared] -= np.abs(model.k_xz[sheared]) ** 2 / k_xx[sheared]
    normal = cz.normal_only()
    reduced = dataclasses.replace(model, law=normal, tangential=False, k_xx=None, k_xz=None, k_zz=k_free,
                                  description=f"{normal.name}, frictionless reduction of {model.description}")
    return Problem(reduced, InterfaceLaw(reduced), problem.z_ind, problem.wall_tolerance)


def elastic_coupling(model):
    """max over q of |k_xz| / √(k_xx k_zz): how strongly the body couples normal and tangential motion (0 without
    tangential unknowns; a half-plane's β = (1 − 2ν)/(2(1 − ν)) at every q, §1.2)."""
    if not model.tangential:
        return 0.0
    k_xx, k_zz = np.real(model.k_xx), np.real(model.k_zz)
    both = (k_xx > 0) & (k_zz > 0)
    return float(np.max(np.abs(model.k_xz[both]) / np.sqrt(k_xx[both] * k_zz[both]), initial=0.0))


def band_stiffness(k_kernel, act, n, half_width):
    """K_AA truncated to |i − j| ≤ half_width (CSR, Pa/m): the dual hard-wall CGs' preconditioner.

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


def mean_shift(u_z, z_ind, pinned=None):
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
    """`mean_shift` with pinned nodes fixed at z_ind: ⟨where(pinned, b, min(u + c, b))⟩ = 0."""
    target = -float(np.sum(z_ind[pinned])) / n_total  # required mean of the others, times their share
    u, b = u_z[~pinned], z_ind[~pinned]
    share = u.size / n_total
    # ⟨min(u + c, b)⟩_others · share = target  ⇔  ⟨min(u + c − t, b − t)⟩ = 0 with t = target/share
    t = target / share
    return mean_shift(u - t, b - t)


def project_onto_wall(u, v, z_ind, stuck, clamp):
    """Positions onto {u ≤ z_ind} (on a half-plane also ⟨u⟩ = 0, the stuck nodes pinned on the wall);
    the velocity into the wall of the projected nodes is removed (v in place). Returns the new u."""
    shift = mean_shift(u, z_ind, stuck) if clamp else 0.0
    projected = np.where(stuck, z_ind, np.minimum(u + shift, z_ind))
    hit = projected < u + shift
    v[hit] = np.minimum(v[hit], 0.0)
    return projected


def wall_balance(model, ku, on_wall):
    """Elastic plus far-field force on every node of a hard-wall configuration (Pa).

    −(Ku)_j, plus on a half-plane the uniform far-field load p that keeps ⟨u⟩ = 0,
    p = mean of (Ku) over the free nodes. On wall nodes, a positive value is the
    contact pressure the wall must supply; on free nodes it is the residual.
    """
    free = ~on_wall
    p = float(np.mean(ku[free])) if model.half_plane and free.any() else 0.0
    return p - ku


def wall_net_force_from(model, ku, on_wall):
    """`wall_net_force` for a given K u (Pa): (net force, stuck mask)."""
    force = wall_balance(model, ku, on_wall)
    stuck = on_wall & (force > 0)
    return np.where(stuck, 0.0, force), stuck


def wall_net_force(model, k, u, on_wall, n):
    """(net nodal force (Pa), stuck mask) of a hard-wall configuration.

    Net force = `wall_balance` + wall reaction: "stuck" nodes are on the wall and
    pushed into it, so the wall cancels their force.
    """
    force = wall_balance(model, irfft_nodes(k * rfft_nodes(u, model.grid), model.grid), on_wall)
    stuck = on_wall & (force > 0)
    return np.where(stuck, 0.0, force), stuck


def coupled_operators(model, law, z_ind, u, fft, shifted=True):
    """(A, M⁻¹, project) at displacements u (c, N): the coupled balance's tangent A = K + D as a
    scipy LinearOperator on flattened (c, N) nodal fields (D: the nodal 2×2 law tangent, rows and
    columns (x, z); ∂f/∂u = −A), the inverse FIRE mass M⁻¹ (`Elastic` with ⟨k_loc⟩) as its
    preconditioner (shifted = False: K⁻¹), and the projection onto zero-mean fields where the half-plane clamps
    the mean."""
    from scipy.sparse.linalg import LinearOperator

    n, c = model.nodes, model.components
    clamp = model.half_plane
    stiff = stiffness_operator(model)
    mass = Elastic(model, *law.mean_stiffness(u, z_ind)) if shifted else stiff
    if law.constraint:
        d_nn = d_nt = d_tn = d_tt = 0.0
    else:
        d_nn, d_nt, d_tn, d_tt = law.law.tangent(z_ind - u[-1], -u[0])

    def project(x):
        return x - x.mean(axis=1, keepdims=True) if clamp else x

    def a_times(v):
        v = project(v.reshape(c, n))
        vh = fft.rfft(v)
        if clamp:
            vh[:, 0] = 0.0
        out = fft.irfft(stiff.stiffness(vh))
        if c == 1:
            out += d_nn * v
        else:
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
