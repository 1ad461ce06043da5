"""The hard wall by projected preconditioned conjugate gradients on the contact pressures (the dual).

The dual of `gfmd.problem`'s hard-wall problem, preconditioned by a band of K on the contact set,
one FFT pair per iteration: 8.6–10× fewer FFT pairs per step than FIRE at N = 2^16–2^17
(docs/design/performance.md). First in the hard wall's chain while the contact set
holds at most `Settings.dual_contact_limit` (15 %) of the nodes (`gfmd.chains`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse

from ..dual_cg import TRANSIENT_FACTOR, DualOptions, solve_dual
from ..problem import band_stiffness as _band_stiffness

#: the name of this algorithm in `Relaxed.method`, result files and the chains (`gfmd.chains`)
LABEL = "cg-dual"

Options = DualOptions  # what it reads: the dual CG's options

DUAL_BAND_HALF_WIDTH = 32
#: 2+1-D surfaces: the preconditioner keeps K_ij for |x_i − x_j|, |y_i − y_j| ≤ this many nodes (periodic), a
#: (2w + 1)² window per row (`_band_stiffness_surface`; K's kernel decays as 1/r³ in 2-D). Measured
#: (docs/design/performance.md hard-wall ramp, 5 steps to a_rel ≈ 3 %), CG iterations per step for
#: w = 0 (diagonal) / 1 / 2 / 3 / 4 / 6: 128²: 8–28 / 7–14 / 7–14 / 7–14 / 7–14 / 7–14; 256²: 10–48 / 8–20 /
#: 8–21 / 8–19 / 8–19 / 8–19: the nearest neighbours carry the gain, a wider window only costs.
DUAL_WINDOW_HALF_WIDTH_2D = 1
#: the step is handed over when A grows past this multiple of `Settings.dual_contact_limit` (`gfmd.dual_cg`)
DUAL_TRANSIENT_FACTOR = TRANSIENT_FACTOR


def _band_stiffness_surface(k_kernel, act, grid, half_width):
    """`_band_stiffness` on a 2+1-D surface (flat node indices act on the grid (Nx, Ny), row-major): K_AA
    truncated to the periodic window |Δi_x|, |Δi_y| ≤ half_width (CSR, Pa/m). K_ij = k[|Δi_x|, |Δi_y|]
    (the kernel is even in each offset): exactly symmetric; the same diagonal-dominance argument as in
    1+1-D makes it positive definite. The window is cut to (N − 1)//2 per axis so no pair is counted twice."""
    nx, ny = grid
    kk = np.reshape(k_kernel, grid)
    wx, wy = min(half_width, (nx - 1) // 2), min(half_width, (ny - 1) // 2)
    position = np.full(nx * ny, -1, np.int64)
    position[act] = np.arange(act.size)
    ix, iy = np.divmod(act, ny)
    rows, cols, data = [], [], []
    for dx in range(-wx, wx + 1):
        row_x = ((ix + dx) % nx) * ny
        for dy in range(-wy, wy + 1):
            j = position[row_x + (iy + dy) % ny]
            hit = np.flatnonzero(j >= 0)
            rows.append(hit)
            cols.append(j[hit])
            data.append(np.full(hit.size, kk[abs(dx), abs(dy)]))
    rows, cols, data = np.concatenate(rows), np.concatenate(cols), np.concatenate(data)
    return scipy.sparse.csr_matrix((data, (rows, cols)), shape=(act.size, act.size))


def solve(problem, start, options):
    """Hard wall by projected CG on the contact pressures (the dual, small contact sets), preconditioned by
    the band of K_AA: |i − j| ≤ DUAL_BAND_HALF_WIDTH on a profile (`gfmd.problem.band_stiffness`), the
    periodic window of DUAL_WINDOW_HALF_WIDTH_2D on a 2+1-D surface (`_band_stiffness_surface`). The loop,
    its set changes, stopping test and hand-over to the primal CG: `gfmd.dual_cg.solve_dual`."""
    model = problem.model
    if len(model.grid) > 1:  # 2+1-D: the periodic window of `_band_stiffness_surface`
        def band_stiffness(kernel, nodes):
            return _band_stiffness_surface(kernel, nodes, model.grid, DUAL_WINDOW_HALF_WIDTH_2D)
    else:
        def band_stiffness(kernel, nodes):
            return _band_stiffness(kernel, nodes, model.nodes, DUAL_BAND_HALF_WIDTH)
    return solve_dual(problem, start, options, label=LABEL, band_stiffness=band_stiffness)
