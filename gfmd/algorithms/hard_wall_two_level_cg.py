"""The hard wall by the dual CG with a two-level preconditioner: the band of K plus a coarse space.

`gfmd.algorithms.hard_wall_dual_cg`'s projected CG on the contact pressures, its band-of-K_AA
preconditioner wrapped in a balancing (BNN) coarse correction on blocks of the contact patches: the
first in the hard wall's chain (`gfmd.chains`, ``Settings.dual_coarse_block > 0``). Why: the dual CG's
count grows with N because its linear part does (docs/design/performance.md: CG on
a fixed contact set, K_AA-preconditioned, 16 → 35 iterations from N = 2^12 to 2^18), not because of set
changes: K_AA is the Dirichlet-to-Neumann map of the whole line restricted to a patch, G_AA⁻¹ its Schur
complement, and the two differ on the smooth modes of each patch (the open-arc log² growth of the
hypersingular-preconditioned single layer, Steinbach & Wendland 1998). The coarse space, piecewise
constants on blocks of ≤ `Settings.dual_coarse_block` consecutive contact nodes, takes exactly those
modes; a block size fixed in nodes makes the condition number independent of N (the two-level bound
depends on the block / node ratio only; docs/design/performance.md: on the 0.1 nm
Fig. 3 step 5–10 iterations per step from N = 2^14 to 2^20, the band alone 14 → 36). The coarse level's cost is
dense in contact nodes × blocks (G_AA Z): where even one block per patch would exceed
COARSE_ENTRIES_PER_NODE · N entries (many patches: a_rel ≈ 0.06 on the Fig. 3 profile), the band
preconditions alone, as in the dual CG.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from ..dual_cg import DualOptions, solve_dual
from ..problem import band_stiffness, stiffness_operator

#: the name of this algorithm in `Relaxed.method`, result files and the chains (`gfmd.chains`)
LABEL = "cg-dual2"


@dataclass(frozen=True)
class Options(DualOptions):
    """What it reads: the dual CG's options and the coarse blocks' size (the `Settings` fields of these names)."""

    dual_coarse_block: int  # coarse blocks of at most this many consecutive contact nodes


#: half-width (nodes) of the band of K_AA (the fine level; as the dual CG's)
BAND_HALF_WIDTH = 32
#: G_AA Z holds at most this many entries per grid node (contact nodes × coarse blocks ≤ this × N): the blocks
#: grow beyond `Settings.dual_coarse_block` nodes where the contact set is large, and where even one block
#: per contact patch would exceed it the band preconditions alone. Each iteration reads G_AA Z twice and each
#: change of the contact set rebuilds it, so beyond a few N entries the coarse level costs more time than
#: the FFT pairs it saves. Measured (N = 2^17, Fig. 3 profile, 0.1 nm steps at δ ≈ 28.5 nm, a_rel = 0.058,
#: one run under load): with 16 N entries 13–16 iterations per step against the band's 94–166, but 10.9 CPU s
#: for the ramp there against 7.1; with 4 N the band alone (as the dual CG); at δ ≈ 19.5 nm (a_rel = 0.011,
#: the end of Fig. 3's ramp) both 8–11 iterations against 37–41 and 1.3–1.4 CPU s against 2.6.
COARSE_ENTRIES_PER_NODE = 4


def coarse_blocks(act, block):
    """Start positions (in act) of the coarse blocks: ≤ block consecutive nodes, never across a gap."""
    pos = np.arange(act.size)
    run_start = np.r_[0, np.flatnonzero(np.diff(act) > 1) + 1]
    first_of_run = run_start[np.cumsum(np.isin(pos, run_start)) - 1]
    return np.flatnonzero((pos - first_of_run) % block == 0)


def coarse_space(g_sum, act, n, block):
    """(starts, G_AA Z, Cholesky factor of E = Zᵀ G_AA Z) on the blocks of `coarse_blocks`, or None (the cost
    gate: one block per patch over COARSE_ENTRIES_PER_NODE · n entries; the blocks grow past `block` below it).

    g_sum: cumulative sum of G's real-space kernel over the offsets −n … n−1 (`solve`), so that the
    column of block [j0, j1] is G_AA Z_J = Σ_{j=j0}^{j1} g(i − j) = g_sum[i − j0 + n] − g_sum[i − j1 − 1 + n].
    None where E is not positive definite (round-off on a nearly full set): the band alone then.
    """
    budget = COARSE_ENTRIES_PER_NODE * n
    runs = 1 + np.count_nonzero(np.diff(act) > 1)
    if act.size < 2 or runs * act.size > budget:
        return None
    starts = coarse_blocks(act, max(block, -(-act.size * act.size // budget)))
    first = act[starts]
    last = act[np.r_[starts[1:], act.size] - 1]
    gz = g_sum[act[:, None] - first[None, :] + n] - g_sum[act[:, None] - last[None, :] - 1 + n]
    e = np.add.reduceat(gz, starts, axis=0)
    try:
        factor = scipy.linalg.cho_factor(0.5 * (e + e.T))
    except np.linalg.LinAlgError:
        return None
    return starts, gz, factor


def two_level(r, fine, coarse):
    """The balancing preconditioner (I − P G) M (I − G P) + P, P = Z E⁻¹ Zᵀ, M the band (`fine`), on r."""
    if coarse is None:
        return fine(r)
    starts, gz, factor = coarse
    sizes = np.diff(np.r_[starts, r.size])
    c = scipy.linalg.cho_solve(factor, np.add.reduceat(r, starts))
    y = fine(r - gz @ c)
    c2 = scipy.linalg.cho_solve(factor, gz.T @ y)
    return y + np.repeat(c - c2, sizes)


def solve(problem, start, options):
    """Hard wall by projected two-level-preconditioned CG on the contact pressures (small contact sets).

    As `gfmd.algorithms.hard_wall_dual_cg.solve` (the problem min ½ PᵀGP + z_indᵀP over P ≥ 0, the set
    changes, the stopping test and its residual, the hand-over to the primal CG), with the preconditioner
    `two_level`: the band of K_AA (half-width BAND_HALF_WIDTH) balanced by the coarse space of blocks of
    `Settings.dual_coarse_block` contact nodes (`coarse_space`), rebuilt when the contact set changes; no
    FFT is added (G_AA Z from G's real-space kernel). The loop: `gfmd.dual_cg.solve_dual`. The preconditioned
    residual s is the stopping measure, as there (≈ the nodal force of the gap error: the preconditioner approximates G_AA⁻¹).
    """
    n = problem.model.nodes

    def fine(kernel, nodes):
        return band_stiffness(kernel, nodes, n, BAND_HALF_WIDTH)

    def preconditioner(fft, g):
        g_sum = stiffness_operator(problem.model).kept(  # `coarse_space`'s, once per task (≈ 1.7 ms at 2^16)
            ("compliance sums", fft.backend), lambda: np.cumsum(fft.irfft(g.astype(complex))[np.arange(-n, n) % n]))
        coarse_of = [None, None]  # (the contact set it was built on, the coarse space)

        def precondition(r, band, act):
            if coarse_of[0] is not act:
                coarse_of[:] = act, coarse_space(g_sum, act, n, options.dual_coarse_block)
            return two_level(r, band, coarse_of[1])
        return precondition

    return solve_dual(problem, start, options, label=LABEL, band_stiffness=fine, preconditioner=preconditioner)
