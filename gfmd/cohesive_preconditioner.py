"""Preconditioners of the cohesive NCG (`gfmd.algorithms.ncg`) beyond its default K⁻¹.

The NCG's Hessian is A = K + D, K diagonal on the modes (K(q) ∝ q E*/2), D = diag(k_loc) on the nodes
(k_loc = V''(Δn), the law's curvature, ≈ φn/δn² in and near contact). Under K⁻¹ the spectrum is
I + K⁻¹D: its largest eigenvalues grow with the width of the stiff patches (the modes longer than the
crossover wavelength, where K(q) = φn/δn², are held by D, not K). `Settings.cohesive_preconditioner`:

* "auto" (the default): "two-level" on a profile with a law that gives a curvature scale (seed Eq. 3's), "stiffness"
  elsewhere (2+1-D surfaces, laws without one), `resolve`; measured at N = 2^17 on whole strong-adhesion ramps (φn* = 0.15) against K⁻¹:
  seed 2, δn = 0.25 nm −36 % FFT pairs, −33 % CPU; seed 7, δn = 1 nm (the seed's figures) −13 % pairs, −13 % CPU
  (with STIFF_FRACTION 0.25; 0.01 saves another 17–21 % of the pairs); the same states
  (docs/design/performance.md);
* "stiffness": K⁻¹ (the NCG's own fused path, no object of this module; the earlier default);
* "two-level": K⁻¹ balanced by a coarse space (the BNN form of `gfmd.algorithms.hard_wall_two_level_cg`),
  (I − P A) K⁻¹ (I − A P) + P, P = Z E⁻¹ Zᵀ, E = Zᵀ A Z, Z piecewise constant on blocks of consecutive
  stiff nodes (max(k_loc, 0) ≥ STIFF_FRACTION φn/δn²) of about half the crossover wavelength, so that
  the modes inside a block are held by K again, and on each gap between them as one block (`COARSE_GAPS`,
  `cover`; on a half-plane the last block is dropped: the blocks sum to a constant, which Π removes, so the
  span of Π Z is the same and E stays definite). D = diag(k_loc) with its sign (`SIGNED_CURVATURE`: the
  softening tail's negative curvature softens the long modes of the gaps, which the coarse space then holds);
  SPD wherever E is (max(k_loc, 0), SPD for D ≥ 0, where E is not definite with the signed D); E from K's
  real-space kernel (no FFT; `gfmd.coarse_kernels.coarse_matrix`); 2 FFT pairs per application where a coarse
  space exists (`apply`), one of which the NCG saves (the direction on the nodes comes with it). The NCG calls
  `apply_split` instead: the force given as T_n on the nodes and the state as its spectral part and coarse tail,
  Zᵀ K u kept on the coarse level, s returned as its spectral part and tail, 2 transforms per application with the
  force's own rfft included (`apply` and the force: 5); the NCG's products come from the parts (`split_products`).
  Profiles (1+1-D) only.

The deflated form A-DEF2 (Tang, Nabben, Vuik & Erlangga 2009), s = P f + (I − P A) K⁻¹ f, 1 FFT pair per application
to the balanced form's 2 (the balanced one on restarts and wherever f·s strays from f·K⁻¹f by more than half), was
measured and dropped (fewer FFT pairs, more iterations, no CPU gain: docs/design/solvers.md); without the f·s check
a step started far from equilibrium stalls.
(K(q) + ⟨max(k_loc, 0)⟩)⁻¹ on the modes was measured and dropped (more iterations than K⁻¹,
docs/design/performance.md). A step starts with K⁻¹; after ENGAGE_AFTER iterations,
or after ENGAGE_EARLY where its convergence rate predicts more than ENGAGE_AFTER (`slow_step`), the NCG builds the
two-level one (a step that finishes before never pays its setup), switches to it, rebuilds it from the state every
REBUILD_EVERY iterations and restarts its direction where the stiff set changed. Its nodal passes are
`gfmd.coarse_kernels`' (fused with numba).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from . import coarse_kernels

CHOICES = ("auto", "stiffness", "two-level")
#: a step runs its first ENGAGE_AFTER iterations with K⁻¹ (the easy steps never pay for the coarse level). Swept
#: (docs/design/solvers.md): 10 and 20 save pairs but settle a jump-in step on another branch, 0 costs more pairs
#: (the two-level pass costs ≈ 2.5 FFT pairs to K⁻¹'s ≈ 1.1): kept at 40
ENGAGE_AFTER = 40
#: ... but a step whose NCG, at its ENGAGE_EARLY-th iteration, converges too slowly to finish within ENGAGE_AFTER (its
#: rate since iteration ENGAGE_EARLY // 2: `slow_step`) engages it from the next iteration on. Measured
#: against ENGAGE_AFTER alone (docs/design/solvers.md): CPU × 0.80–0.93 on the strong ramps, unchanged on the weak
#: ones. Engaging at 10 on every step costs the weak ramps 31–44 % more FFT pairs.
ENGAGE_EARLY = 10
#: then the NCG rebuilds the preconditioner every this many iterations, restarting its direction where it changed.
#: Measured (docs/design/solvers.md): 10 costs more CPU in rebuilds than it saves in iterations, 40 gains nothing
REBUILD_EVERY = 20
#: "two-level": a node is stiff (in the coarse space) where max(k_loc, 0) ≥ this × φn/δn². Measured
#: (docs/design/solvers.md): 0.01 against 0.25 −15 to −18 % CPU, the same states; 0 (every node) grows the coarse
#: matrix to N/block
STIFF_FRACTION = 0.01
#: "two-level": the coarse space also holds each run of soft nodes between the stiff blocks as one block (the gaps
#: between the adhered patches; `cover`), so that it spans the cell. Measured (whole 201-step ramps at N = 2^17,
#: φn* = 0.15, docs/design/performance.md §7): −33 % FFT pairs and −28 % CPU (seed 2,
#: δn = 0.25 nm), −26 % and −23 % (seed 7, δn = 1 nm), the same states
COARSE_GAPS = True
#: "two-level": a stiff block spans this fraction of the crossover wavelength. Measured
#: (docs/design/solvers.md): 0.25 saves 8 % of the FFT pairs but only 3 % CPU for a coarse matrix twice as large:
#: kept 0.5
BLOCK_WAVELENGTHS = 0.5
#: "two-level": D = diag(k_loc) with its sign, the softening tail's negative curvature (Δn > δn, most of the nodes out
#: of contact) included, in the coarse matrix and the balancing; max(k_loc, 0) where False, or where E is not definite
#: with it. Measured (docs/design/solvers.md): −6 to −7 % iterations on the strong ramps at 2^17, CPU × 0.85 to
#: 0.98, unchanged on weak ones. Cutting the gaps into blocks as well: fewer FFT pairs, more CPU: not kept
SIGNED_CURVATURE = True


def slow_step(e_before, e_now, span, e_target, remaining):
    """True where a step's NCG, its energy norm (f·K⁻¹f)^½ gone from e_before to e_now over its last `span` iterations,
    would need more than `remaining` more iterations to reach e_target at that rate (or made no progress). The
    recent rate, not the mean from the step's start: an extrapolated guess's first iterations fall fast and erratically
    (whole 2^15 ramps under K⁻¹, seed 2: the rate over iterations 5–10 told the steps that went past 40 from the
    others on 296 of 304 steps at φn* = 0.15 (ν = 0.1 and 0.45), the mean rate over 0–10 on 262; at φn* = 0.01 on 93
    and 92 of 109)."""
    if not e_now < e_before:
        return True
    if e_now <= e_target:
        return False
    return np.log(e_target / e_now) / (np.log(e_now / e_before) / span) > remaining


def split_products(spectral, now, old, d_old, sums):
    """(f·s, f_old·s, f·d_old) of the NCG under `TwoLevel.apply_split`, from the vectors' parts.

    f = r + D w with r = K x (+ a constant where clamped, which the mean-free s and d do not see), so each product is
    a K-product plus its nodal part (`sums`). A vector a = a_s + Π Z e_a (spectral part a_s, coarse tail e_a) has
    ⟨a, b⟩_K = a_s·K b_s + e_a·ℓ_b + e_b·ℓ_a + e_a·E_K e_b, ℓ_a = Zᵀ K a_s. spectral: (x'·Kx', x'_old·Kx', d_s·Kx')
    (`gfmd.kernels.preconditioned_kernels`' stiffness_products; s's spectral part is x'); now: `apply_split`'s parts
    (e_x, e_s, E_K e_s, ℓ_x'); old: the last force's (e_x, ℓ_x') or None; d_old: the last direction's
    (e_d, E_K e_d, Zᵀ K d) or None (ℓ_d = Zᵀ K d − E_K e_d); None: that product 0 (a restart does not read it)."""
    e_x, e_s, k_s, l_x = now
    rz = spectral[0] + float(np.dot(e_x + e_s, l_x)) + float(np.dot(e_x, k_s)) + sums[0]
    f_old_s = f_d_old = 0.0
    if old is not None:
        e_xo, l_xo = old
        f_old_s = spectral[1] + float(np.dot(e_xo, l_x) + np.dot(e_s, l_xo) + np.dot(e_xo, k_s)) + sums[1]
    if d_old is not None:
        e_d, k_d, z_kd = d_old
        f_d_old = spectral[2] + float(np.dot(e_x, z_kd - k_d) + np.dot(e_d, l_x) + np.dot(e_x, k_d)) + sums[2]
    return rz, f_old_s, f_d_old


def split_energy(spectral, e_d, k_d, z_kd):
    """d·Kd of a direction d = d_s + Π Z e_d from d_s·K d_s (spectral), E_K e_d (k_d) and Zᵀ K d (z_kd)."""
    return spectral + 2.0 * float(np.dot(e_d, z_kd - k_d)) + float(np.dot(e_d, k_d))


def blocks(nodes, block):
    """Start positions (in `nodes`, sorted node indices) of runs of ≤ block consecutive nodes, never across a gap."""
    pos = np.arange(nodes.size)
    run_start = np.r_[0, np.flatnonzero(np.diff(nodes) > 1) + 1]
    in_run = pos - run_start[np.searchsorted(run_start, pos, side="right") - 1]
    return np.flatnonzero(in_run % block == 0)


def kernel_sums(kr, n):
    """The double cumulative sums of a real-space kernel kr (N,), (K u)_i = Σ_j kr(i − j) u_j, that
    `gfmd.coarse_kernels.block_sums` reads: cs1[x] = Σ of kr over offsets −n … x − n − 1, and its own cumulative sum."""
    cs1 = np.r_[0.0, np.cumsum(kr[np.arange(-n, n) % n])]
    return np.r_[0.0, np.cumsum(cs1)]


def cover(stiff, n, block):
    """(nodes, starts) of a coarse space over every node 0 … n − 1: the runs of consecutive stiff nodes (`stiff`, sorted)
    cut every `block` nodes (`blocks`), and each run of soft nodes between them one block; nodes = 0 … n − 1, starts
    the positions where a block begins (a run that wraps around the cell's end is two blocks)."""
    soft = np.ones(n, bool)
    soft[stiff] = False
    run_start = np.flatnonzero(np.r_[True, soft[1:] != soft[:-1]])
    starts = np.union1d(stiff[blocks(stiff, block)], run_start[soft[run_start]])
    return np.arange(n), starts


def _surface(grid):
    """True for a 2+1-D surface's grid (Nx, Ny); a profile's (N,) or None: False."""
    return grid is not None and np.ndim(grid) > 0 and len(grid) > 1


def check(settings, grid=None):
    """Raise ValueError naming Settings.cohesive_preconditioner for an unknown choice (or "two-level" on a
    2+1-D surface)."""
    name = settings.cohesive_preconditioner
    if name not in CHOICES:
        raise ValueError(f"Settings.cohesive_preconditioner = {name!r}: expected one of {', '.join(CHOICES)}")
    if name == "two-level" and _surface(grid):
        raise ValueError("Settings.cohesive_preconditioner = 'two-level' is for profiles (1+1-D) only")


def resolve(name, grid=None, unscaled=False):
    """The preconditioner a `Settings.cohesive_preconditioner` value runs: "auto" is "two-level" on a profile
    with a law that gives a curvature scale (the law protocol's `curvature_scale`: seed Eq. 3's φn/δn²),
    "stiffness" on a 2+1-D surface or for a law without one (`unscaled`: a user law, the LJ 9-3 wall)."""
    if name != "auto":
        return name
    return "stiffness" if _surface(grid) or unscaled else "two-level"


def build(name, fft, k, clamp, n, kn_scale, keep=None):
    """The preconditioner `name` ("two-level") for K(q) = k on the modes (q = 0 clamped
    where `clamp`) and the law's curvature scale kn_scale (Pa/m, `curvature_scale`), or None for "stiffness" (the NCG's own K⁻¹). keep: an object of the model that outlives the step
    (`gfmd.problem.stiffness_operator`), on which K's kernel sums are kept for the task's later steps."""
    if name == "stiffness":
        return None
    return TwoLevel(fft, k, clamp, n, kn_scale, keep)


def _inverse(k, clamp):
    g = np.zeros(k.size)
    np.divide(1.0, k, out=g, where=k > 0)
    if clamp:
        g[0] = 0.0
    return g


class TwoLevel:
    """K⁻¹ balanced by piecewise constants on blocks of stiff nodes (module docstring)."""

    def __init__(self, fft, k, clamp, n, kn_scale, keep=None):
        self.fft, self.k, self.clamp, self.n, self.kn_scale = fft, k, clamp, n, kn_scale
        self.g = _inverse(k, clamp)

        def sums():
            kq = k.copy()
            if clamp:
                kq[0] = 0.0
            return kernel_sums(fft.irfft(kq.astype(complex)), n)  # (K u)_i = Σ_j kr(i − j) u_j

        # K's, kept on the model's operator (`build`)
        self.cs2 = sums() if keep is None else keep.kept(("stiffness kernel sums", fft.backend), sums)
        above = np.flatnonzero(k >= kn_scale)  # the crossover mode: K(q) = φn/δn²
        crossover = int(above[0]) if above.size else k.size
        self.block = max(1, int(round(BLOCK_WAVELENGTHS * n / max(crossover, 1))))
        self.coarse = self.stiff = self.index = None  # index: the coarse nodes as a slice or an index array
        self.w, self.work = fft.empty_nodes(), np.empty(n)  # apply's buffers; w is apply_split's scratch too
        self.y = fft.empty_nodes()  # apply_split's T − D w (w and y: FFT inputs, aligned for `Fft.rfft_scratch`)
        self.dw = (np.empty(n), np.empty(n))  # and its D w, two in turn
        self.x_hats = (np.empty(k.size, dtype=complex), np.empty(k.size, dtype=complex))  # apply_split's x̂', in turn
        self.split = coarse_kernels.split_kernels()
        self.load = None  # Zᵀ K u of the current coarse space (`apply_split`, `move`); None: made at the next call
        self.tail = self.k_tail = None  # û's coarse tail e_u and E_K e_u (`apply_split`, `move`, `fold`)
        self.folded = fft.empty_nodes()  # `fold`'s Π Z e_u (an FFT input, aligned)
        self.kernels = coarse_kernels.coarse_kernels()  # apply's nodal passes where the blocks cover 0 … m − 1
        self.matrix = coarse_kernels.coarse_matrix()  # E, the coarse matrix

    def rebuild(self, k_loc, u_hat=None):
        """The coarse space of the stiff nodes at k_loc (Pa/m per node, every node) with D = diag(k_loc)
        (SIGNED_CURVATURE; max(k_loc, 0) where E is not definite with it); False (kept as it was) where the stiff set
        has not changed. u_hat: the state's spectral part, into which the old space's tail is folded first (`fold`)."""
        stiff = np.flatnonzero(k_loc >= STIFF_FRACTION * self.kn_scale)
        if self.stiff is not None and np.array_equal(stiff, self.stiff):
            return False
        if u_hat is not None:
            self.fold(u_hat)
        elif self.tail is not None and np.any(self.tail):
            raise ValueError("TwoLevel.rebuild: the state has a coarse tail; pass its spectral part (u_hat) to fold it")
        for signed in ((True, False) if SIGNED_CURVATURE else (False,)):
            if self._build(np.array(k_loc, dtype=float) if signed else np.maximum(k_loc, 0.0), stiff):
                break
        return True

    def _build(self, d, stiff):
        """The coarse space and E's Cholesky factor for D = d on the stiff set `stiff`; False where E is not
        definite."""
        self.d, self.stiff, self.coarse, self.load, self.tail, self.k_tail = d, stiff, None, None, None, None
        if stiff.size == 0:
            return True
        if COARSE_GAPS:  # every node: the stiff blocks and one block per gap between them
            nodes, starts = cover(stiff, self.n, self.block)
            if self.clamp:  # Σ of all blocks = 1, which Π removes: the last block is the others' negative, dropped
                if starts.size < 2:
                    return True
                nodes, starts = nodes[:starts[-1]], starts[:-1]
            index = slice(0, nodes.size)  # `cover`'s nodes are 0 … m − 1: a view, no gather or scatter
        else:
            nodes, starts = stiff, blocks(stiff, self.block)
            index = nodes
        ends = np.r_[starts[1:], nodes.size]
        a, p = nodes[starts], ends - starts  # first node and width of each block (consecutive nodes)
        mass = np.add.reduceat(self.d[nodes], starts)  # Zᵀ D 1 (and Zᵀ D Z = diag of it)
        # Zᵀ K Z + Zᵀ Π D Π Z with Π the mean removal (K kills constants: k(0) = 0)
        e = self.matrix(self.cs2, self.n, a, p, mass, self.clamp, float(np.sum(self.d)))
        try:
            factor = scipy.linalg.cho_factor(e)
        except np.linalg.LinAlgError:
            return False
        self.coarse, self.index = (nodes, starts, p, factor), index
        self.mass, self.dsum = mass, float(np.sum(self.d))
        self.tail, self.k_tail = np.zeros(starts.size), np.zeros(starts.size)
        return True

    def _spread(self, c, z):
        """Π Z c on every node, into z (N,)."""
        p = self.coarse[2]
        z.fill(0.0)
        z[self.index] = np.repeat(c, p)
        if self.clamp:
            z -= z.mean()
        return z

    def _restrict(self, x):
        """E⁻¹ Zᵀ x (x mean-free where clamped, so Zᵀ Π x = Zᵀ x)."""
        _, starts, _, factor = self.coarse
        return scipy.linalg.cho_solve(factor, np.add.reduceat(x[self.index], starts), check_finite=False)

    def apply(self, f_hat):
        """(ŝ, s on the nodes or None): s = P f + (I − P A) K⁻¹ (I − A P) f on the spectrum f̂.

        With w = Π Z c, c = E⁻¹ Zᵀ f, and K K⁻¹ = 1 on the free modes, y = K⁻¹(f − A w) = K⁻¹(f − D w) − w and
        Zᵀ A y = Zᵀ (f − A w) + Zᵀ D y = Zᵀ D y (Zᵀ A w = E c = Zᵀ f), so s = K⁻¹(f − D w) − Π Z c₂,
        c₂ = E⁻¹ Zᵀ Π D y: 2 FFT pairs (irfft f̂, rfft D w, irfft for y, rfft Π Z c₂), s on the nodes for free.
        """
        if self.coarse is None:
            return self.g * f_hat, None
        if isinstance(self.index, slice):
            return self._apply_fused(f_hat)
        fft, d, work = self.fft, self.d, self.work
        w = self._spread(self._restrict(fft.irfft(f_hat)), self.w)
        x_hat = fft.rfft(np.multiply(d, w, out=work))
        np.subtract(f_hat, x_hat, out=x_hat)
        x_hat *= self.g  # K⁻¹(f − D w)
        x = fft.irfft(x_hat)
        dy = np.multiply(d, np.subtract(x, w, out=work), out=work)  # D y, y = x − w
        if self.clamp:
            dy -= dy.mean()
        z = self._spread(self._restrict(dy), self.w)  # Π Z c₂
        s_hat = fft.rfft(z)
        np.subtract(x_hat, s_hat, out=s_hat)
        if self.clamp:
            s_hat[0] = 0.0
        return s_hat, np.subtract(x, z, out=x)

    def apply_split(self, t, u_hat, dw_old=None, d_old=None):
        """`apply` on the force f = T_n − K u (− ⟨T_n⟩ where clamped) given as the tractions t (N,) and the state
        û = û_s + rfft(Π Z e_u), its spectral part u_hat and its coarse tail e_u (`tail`): 2 FFTs.

        Returns (x̂', s on the nodes, ŷ, D w, Zᵀ K s, sums, parts). The coarse load Zᵀ f = Zᵀ T_n − Zᵀ K u (− p ⟨T_n⟩)
        comes from Zᵀ K u kept on the coarse level (`load`: made from û_s and E_K e_u where the coarse space is new,
        then `move`d), f is never needed on the nodes. x = K⁻¹(f − D w) = x' − Π Z e_u with x̂' = g ŷ − û_s,
        ŷ = rfft(T_n − D w): one rfft and one irfft; s = x − Π Z c₂ = x' − Π Z (e_u + c₂) on the nodes, and on the
        modes as its spectral part x̂' and its tail e_s = −(e_u + c₂), never transformed (`split_products`: its dot
        products from the parts). The force f = r + D w (mean removed where clamped), r̂ = ŷ − K û: the NCG's nodal
        products take D w here, sums = (Σ D w s, Σ dw_old s, Σ D w d_old) (dw_old, d_old: the last force's D w and the
        last direction on the nodes, None: 0); its stopping test `fold`s first (r̂ from the exact û). parts =
        (e_x, e_s, E_K e_s, Zᵀ K x') with e_x = −e_u (x's tail) and E_K = Zᵀ Π K Π Z, from what the coarse
        level holds (E_K c₂ = E c₂ − E_D c₂ = b₂ − E_D c₂, E_K e_u moved with e_u) and Zᵀ K x' = Zᵀ K x + E_K e_u,
        Zᵀ K x = Zᵀ r − p ⟨r⟩. Zᵀ K s = Zᵀ K x − E_K c₂, for the load's move. Where the blocks do not cover 0 … m − 1
        in order, or no coarse space exists (û_s is then û: no tail): `apply`'s path, (ŝ, s, f̂, None, None, None,
        None).
        """
        fft, k, clamp, n = self.fft, self.k, self.clamp, self.n
        if self.coarse is None or not isinstance(self.index, slice):
            f_hat = fft.rfft(t)
            f_hat -= k * u_hat
            if clamp:
                f_hat[0] = 0.0
            s_hat, s_nodes = self.apply(f_hat)
            return s_hat, s_nodes, f_hat, None, None, None, None
        block_load, spread_scaled_minus, stiff_sums_of, split_spectrum, spread_subtract_dots, _ = self.split
        _, starts, p, factor = self.coarse
        e_u, k_u = self.tail, self.k_tail
        if self.load is None:  # Zᵀ K u = Zᵀ K u_s + E_K e_u, exact, once per coarse space
            self.load = np.empty(starts.size)
            block_load(fft.irfft(k * u_hat), starts, p, n, self.load)
            self.load += k_u
        zt = np.empty(starts.size)
        t_sum = block_load(t, starts, p, n, zt)  # Zᵀ T_n into zt, Σ T_n
        t_mean = t_sum / n if clamp else 0.0
        c = scipy.linalg.cho_solve(factor, zt - self.load - p * t_mean, check_finite=False)  # E⁻¹ Zᵀ f
        w, dw = self.w, self.dw[0]
        self.dw = self.dw[::-1]  # the caller keeps this D w while the next call writes the other
        spread_scaled_minus(c, starts, p, n, clamp, self.d, t, dw, self.y)  # D w (w = Π Z c), y = T_n − D w
        y_hat = fft.rfft_scratch(self.y)
        x_hat = self.x_hats[0]  # the caller keeps this x̂' (its next products) while the next call writes the other
        self.x_hats = self.x_hats[::-1]
        split_spectrum(y_hat, self.g, u_hat, x_hat)  # x̂' = g ŷ − û_s
        x = fft.irfft(x_hat)  # x' = x + Π Z e_u
        b2 = stiff_sums_of(self.d, x, c + e_u, starts, p, n, clamp, w)  # Zᵀ Π D y, y = x − w = x' − Π Z (c + e_u)
        c2 = scipy.linalg.cho_solve(factor, b2, check_finite=False)
        e_s = -(e_u + c2)
        sums = spread_subtract_dots(-e_s, starts, p, n, clamp, w, x, dw, dw_old, d_old)  # x ← x' − Π Z (e_u + c₂) = s
        mean_c = float(np.dot(p, c)) / n if clamp else 0.0
        r_mean = float(y_hat[0].real) / n if self.g[0] == 0.0 else 0.0  # r̂(0) = ŷ(0) where K(0) = 0
        z_kx = zt - self.mass * (c - mean_c) - self.load - p * r_mean  # Zᵀ K x = Zᵀ r − p ⟨r⟩, Zᵀ D w = mass (c − ⟨Zc⟩)
        k_c2 = b2 - self.coarse_d(c2)  # E_K c₂
        return x_hat, x, y_hat, dw, z_kx - k_c2, sums, (-e_u, e_s, -(k_u + k_c2), z_kx + k_u)

    def fold(self, u_hat):
        """û_s ← û_s + rfft(Π Z e_u), e_u ← 0, in place: the spectral part is û again (one rfft; where the tail is
        zero, nothing). True where it folded."""
        if self.tail is None or not np.any(self.tail):
            return False
        _, starts, p, _ = self.coarse
        u_hat += self.fft.rfft_scratch(coarse_kernels.spread(self.tail, starts, p, self.n, self.clamp, self.folded))
        if self.clamp:
            u_hat[0] = 0.0
        self.tail[:] = 0.0
        self.k_tail[:] = 0.0
        return True

    def coarse_d(self, c):
        """E_D c, E_D = Zᵀ Π D Π Z (the D part of E, `gfmd.coarse_kernels.coarse_matrix`)."""
        _, _, p, _ = self.coarse
        out = self.mass * c
        if self.clamp:
            pc, mc = float(np.dot(p, c)), float(np.dot(self.mass, c))
            out += (self.dsum / self.n**2 * pc) * p - (p * mc + self.mass * pc) / self.n
        return out

    def move(self, u_hat, d_hat, alpha, z_kd, e_d=None, k_d=None):
        """The NCG's step û ← û + α d, in place: û_s ← û_s + α d̂_s, the tail e_u ← e_u + α e_d (E_K e_u with it,
        k_d = E_K e_d; e_d None: d has no tail), and Zᵀ K u ← Zᵀ K u + α Zᵀ K d (z_kd None: Zᵀ K u made afresh at the
        next `apply_split`)."""
        self.split[5](u_hat, d_hat, alpha)
        if e_d is not None:
            self.tail += alpha * e_d
            self.k_tail += alpha * k_d
        if z_kd is None:
            self.load = None
        elif self.load is not None:
            self.load += alpha * z_kd

    def _apply_fused(self, f_hat):
        """`apply` where the blocks cover the nodes 0 … m − 1 in order (`cover`): its nodal passes as
        `gfmd.coarse_kernels`' three (one pass each with numba)."""
        spread_scaled, stiff_sums, spread_subtract = self.kernels
        fft, d, w, work, n, clamp = self.fft, self.d, self.w, self.work, self.n, self.clamp
        _, starts, p, factor = self.coarse
        c = scipy.linalg.cho_solve(factor, np.add.reduceat(fft.irfft(f_hat)[:starts[-1] + p[-1]], starts),
                                   check_finite=False)  # E⁻¹ Zᵀ f (f mean-free where clamped)
        spread_scaled(c, starts, p, n, clamp, d, w, work)  # w = Π Z c, D w
        x_hat = fft.rfft(work)
        np.subtract(f_hat, x_hat, out=x_hat)
        x_hat *= self.g  # K⁻¹(f − D w)
        x = fft.irfft(x_hat)
        c2 = scipy.linalg.cho_solve(factor, stiff_sums(d, x, w, starts, p, n, clamp), check_finite=False)
        spread_subtract(c2, starts, p, n, clamp, w, x)  # w ← Π Z c₂, x ← x − w = s on the nodes
        s_hat = fft.rfft(w)
        np.subtract(x_hat, s_hat, out=s_hat)
        if clamp:
            s_hat[0] = 0.0
        return s_hat, x
