"""The cohesive NCG's nodal law work (`gfmd.algorithms.ncg`): seed Eq. 3's, numpy or fused, and a user law's.

Each NCG iteration evaluates the law on the near set at trial states Δn − α d of its line search: the scaled
gap s = Δn/δn, e^{−s}, dE/dα's law term Σ_j T_n,j d_j and d²E/dα²'s Σ_j k_loc,j d_j², with (seed Eq. 3)

    T_n = (φn/δn) s e^{−s},   k_loc = dT_n/dΔn = (φn/δn²)(1 − s) e^{−s}.

numpy needs 7 passes over the nodes per trial (a temporary each); numba two, into reused arrays: the state
(Δn − α d, s, e^{−s}) with `gfmd.vector_exp.exp`, which LLVM vectorizes (libm's exp, a scalar call, keeps a single
fused pass from vectorizing), then the two sums (reassociated). Measured
(docs/design/performance.md, N = 2^17): a trial 0.53 ms against 0.97 ms with libm's exp in one pass and
5.4 ms in numpy. Both backends give the same sums up to round-off; ``GFMD_JIT`` chooses, as for the spectral algebra
(`gfmd.kernels.jit_backend`).
Any other law (a user law, `gfmd_contact.core.user_law`; the LJ 9-3 wall) is evaluated through its tractions and
tangent (`LawNodes`); `nodes_for` chooses by the law's `nodal_form`. `line_search` is the NCG's safeguarded Newton
on dE/dα along a direction, one trial of the nodal work per step.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core import laws

from . import kernels, vector_exp
from .fft import dot

numba = kernels.numba


class Eq3Nodes:
    """Seed Eq. 3 on the scaled gap: state (s, e^{−s}), s = Δn/δn, capped at −MAX_COMPRESSION against overflow."""

    def __init__(self, dn, tn_scale, kn_scale, backend=None):
        self.dn, self.tn_scale, self.kn_scale = dn, tn_scale, kn_scale
        self.fused = kernels.jit_backend(backend) == "numba"
        self._sets = []  # the fused trial's output arrays: two sets, written in turn
        self._traction = None  # traction_new's output array (fused)

    def _outputs(self, gap):
        """(Δn, s, e^{−s}) arrays for a fused trial: of the two sets of gap's size, the one that does not hold
        `gap` (the state the trial starts from, itself an earlier trial's output or a fresh array). Reused:
        fresh 1 MB arrays cost their page faults, 0.7–0.9 ms a trial at N = 2^17."""
        for out in self._sets:
            if out[0].size == gap.size and out[0] is not gap:
                return out
        out = (np.empty(gap.size), np.empty(gap.size), np.empty(gap.size))
        self._sets = [x for x in self._sets if x[0].size == gap.size][-1:] + [out]
        return out

    def state(self, gap_nodes):
        """(s, e^{−s}) with s = Δn/δn, capped at −MAX_COMPRESSION against overflow."""
        s = gap_nodes * (1.0 / self.dn)
        np.maximum(s, -laws.MAX_COMPRESSION, out=s)
        return s, np.exp(-s)

    def trial(self, gap, d, alpha):
        """(Δn − α d, s, e^{−s}, Σ_j T_n,j d_j, Σ_j k_loc,j d_j² or None) at the trial state Δn − α d: the fused
        kernel gives the curvature sum with the rest, numpy leaves it to `curvature_sum` (when needed). The fused
        trial writes into one of two reused sets of arrays, never the one holding `gap` (`_outputs`): its arrays
        live until the next trial that does not start from them (the line search keeps only its last trial, the
        NCG only the state it accepted)."""
        if self.fused:
            gap_a, s, e = self._outputs(gap)
            work, curv = _trial_fused(gap, d, float(alpha), 1.0 / self.dn, float(laws.MAX_COMPRESSION), gap_a, s, e)
            return gap_a, s, e, self.tn_scale * work, self.kn_scale * curv
        gap_a = d * (-alpha)
        gap_a += gap
        s, e = self.state(gap_a)
        return gap_a, s, e, self.work(s, e, d), None

    def traction_new(self, s, e):
        """T_n = (φn/δn) s e^{−s} (Pa), as (s e^{−s}) φn/δn; fused, one pass into an array kept for the next call
        (the NCG copies it into the FFT's input at once)."""
        if self.fused:
            if self._traction is None or self._traction.size != s.size:
                self._traction = np.empty(s.size)
            _traction_fused(s, e, self.tn_scale, self._traction)
            return self._traction
        t = s * e
        t *= self.tn_scale
        return t

    def traction(self, s, e):
        """T_n = (φn/δn) s e^{−s} (Pa)."""
        return self.tn_scale * s * e

    def work(self, s, e, d):
        """Σ_j T_n,j d_j."""
        return self.tn_scale * float(np.einsum("i,i,i->", s, e, d))

    def stiffness(self, s, e):
        """k_loc = (φn/δn²)(1 − s) e^{−s} (Pa/m)."""
        return self.kn_scale * (1.0 - s) * e

    def direction_sums(self, s, e, d):
        """(Σ_j T_n,j d_j, Σ_j k_loc,j d_j²) at the state along a new direction d: the line search's dE/dα(0) law
        term and curvature; fused, the trial's two sums in one pass."""
        if self.fused:
            work, curv = _trial_sums(s, e, d)
            return self.tn_scale * work, self.kn_scale * curv
        return self.work(s, e, d), self.curvature_sum(s, e, d)

    def curvature_sum(self, s, e, d):
        """Σ_j k_loc,j d_j², k_loc = (φn/δn²)(1 − s) e^{−s}."""
        if self.fused:
            return self.kn_scale * _curvature_fused(s, e, d)
        x = e * d
        return self.kn_scale * (dot(x, d) - float(np.einsum("i,i,i->", s, x, d)))


def nodes_for(law, backend=None):
    """The nodal work of `law` (the law protocol, `gfmd_contact.core.law_protocol`): `Eq3Nodes` for its
    "exponential" nodal form (seed Eq. 3, fused), `LawNodes` (its tractions and tangent) for any other law."""
    form = law.nodal_form
    if form is not None and form[0] == "exponential":
        return Eq3Nodes(*form[1:], backend=backend)
    return LawNodes(law)


class LawNodes:
    """Any normal law with a potential (a user law, the LJ 9-3 wall, ...): state (T_n, dT_n/dΔn) from its
    tractions and tangent."""

    def __init__(self, law):
        self.law = law

    def state(self, gap_nodes):
        """(T_n, k_loc) (Pa, Pa/m) at the gaps."""
        return self.law.tractions(gap_nodes)[0], self.law.tangent(gap_nodes)[0]

    def trial(self, gap, d, alpha):
        """(Δn − α d, T_n, k_loc, Σ_j T_n,j d_j, None) at the trial state (`Eq3Nodes.trial`)."""
        gap_a = d * (-alpha)
        gap_a += gap
        t, k = self.state(gap_a)
        return gap_a, t, k, self.work(t, k, d), None

    def traction_new(self, t, k):
        return t

    def traction(self, t, k):
        return t

    def work(self, t, k, d):
        return dot(t, d)  # no BLAS (`gfmd.fft.dot`)

    def stiffness(self, t, k):
        return k

    def direction_sums(self, t, k, d):
        return self.work(t, k, d), self.curvature_sum(t, k, d)

    def curvature_sum(self, t, k, d):
        return float(np.einsum("i,i,i->", k, d, d))



def line_search(nodal, c1, c2, law_curvature, slope0, gap, sv, ev, d, dn, eta, max_move):
    """The NCG's line search (`gfmd.algorithms.ncg`), safeguarded Newton on dE/dα along d: (α, found, Δn and the
    nodal state at α: Eq. 3's s, e^{−s}; another law's T_n, k_loc).

    dE/dα = c1 + α c2 − Σ_j T_n(Δn_j − α d_j) d_j, d²E/dα² = c2 + Σ_j k_loc,j d_j² (`nodal.trial`
    evaluates a trial state, Eq. 3 in one fused pass where numba is installed); stops at |dE/dα| ≤ eta |dE/dα(0)|.
    law_curvature: Σ_j k_loc,j d_j² at α = 0 (`nodal.direction_sums`, with c1's law term). found = False with α = 0:
    no step lowers E.
    """
    curv0 = c2 + law_curvature
    reach = float(np.max(np.abs(d))) if d.size else 0.0
    alpha = -slope0 / curv0 if curv0 > 0 else (max_move * dn / reach if reach > 0 else 1.0)
    lo, hi = 0.0, np.inf
    p_lo, p_hi = slope0, np.inf
    found = False
    widths = []
    for _ in range(100):
        gap_a, s_a, e_a, work, curv = nodal.trial(gap, d, alpha)
        p = c1 + alpha * c2 - work
        if not np.isfinite(p):
            hi, p_hi = alpha, np.inf
        elif abs(p) <= eta * abs(slope0):
            found = True
            break
        elif p < 0:
            lo, p_lo = alpha, p
        else:
            hi, p_hi = alpha, p
        c = c2 + (curv if curv is not None else nodal.curvature_sum(s_a, e_a, d)) if np.isfinite(p) else np.nan
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
                gap_a, s_a, e_a, _, _ = nodal.trial(gap, d, alpha)
                found = alpha > 0
                break
        elif not nxt > alpha:
            nxt = 4.0 * alpha
        alpha = nxt
    if not found and lo > 0:  # no tight minimum found, but E decreases up to lo: take that step
        alpha = lo
        gap_a, s_a, e_a, _, _ = nodal.trial(gap, d, alpha)
        found = True
    if not found:
        alpha = 0.0
    return alpha, found, gap_a, s_a, e_a

if numba is not None:
    # reassociated sums and fused multiply-adds, but no finite-math assumptions: an overflowing trial's inf
    # must reach the line search (its bracket treats a non-finite dE/dα as the upper end)
    _FLAGS = {"reassoc", "contract", "nsz", "arcp"}

    @numba.njit(cache=True, fastmath=vector_exp.STRICT_FLAGS)
    def _trial_state(gap, d, alpha, inv_dn, max_compression, gap_a, s, e):  # Δn − α d, s, e^{−s}: a vectorized pass
        for i in range(gap.size):
            g = gap[i] - alpha * d[i]
            si = g * inv_dn
            si = si if si >= -max_compression else -max_compression
            gap_a[i], s[i], e[i] = g, si, vector_exp.exp(-si)

    @numba.njit(cache=True, fastmath=_FLAGS)
    def _trial_sums(s, e, d):  # Σ s e d and Σ (1 − s) e d²
        work = curv = 0.0
        for i in range(s.size):
            x = e[i] * d[i]
            work += s[i] * x
            curv += (1.0 - s[i]) * x * d[i]
        return work, curv

    def _trial_fused(gap, d, alpha, inv_dn, max_compression, gap_a, s, e):
        """Eq3Nodes.trial's state and sums: two passes (the exp's loop may not reassociate, the sums' must)."""
        _trial_state(gap, d, alpha, inv_dn, max_compression, gap_a, s, e)
        return _trial_sums(s, e, d)

    @numba.njit(cache=True, fastmath=_FLAGS)
    def _traction_fused(s, e, scale, out):  # (s e) scale, as numpy's (s e) *= scale
        for i in range(s.size):
            out[i] = (s[i] * e[i]) * scale

    @numba.njit(cache=True, fastmath=_FLAGS)
    def _curvature_fused(s, e, d):  # Σ (1 − s) e d²
        curv = 0.0
        for i in range(s.size):
            curv += (1.0 - s[i]) * e[i] * d[i] * d[i]
        return curv
