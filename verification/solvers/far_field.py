"""GFMD's free 2+1-D cell driven by the protocol's penetration: the approach from the far field (u_z → 0 there).

The free cell (`gfmd.free_cell`) clamps the padded cell's mean displacement, so its displacement U refers to the
padded cell's mean plane; the free body's surface is u + s, s the far-field shift the step keeps
(`StepSolution.keep["far_field_shift"]`, docs/design/free_boundary.md). The approach from the far field is then
U − s. `FarFieldCell.solve(V, …)` finds the U with U − s(U) = V (secant, warm-started), so `ramp_path.run_path`
drives it in far-field terms under either control, and δ = V − δ0 is the protocol's penetration.
"""

from __future__ import annotations

import dataclasses

#: secant rounds per step at most (s changes with U by ~a/L of it on a contact of radius a in a region L: measured
#: 1 round out of contact, 3–5 in contact on the free Hertz sphere at N = 64)
ROUNDS = 30


class FarFieldCell:
    """A free 2+1-D `gfmd.loading` cell whose `solve` takes the far-field displacement V = U − s (m)."""

    def __init__(self, cell, tolerance):
        self.cell, self.tolerance, self.shift = cell, float(tolerance), 0.0

    def initial_state(self):
        return self.cell.initial_state()

    def solve(self, far, guess, fallback):
        """The padded cell's step at the U whose far-field approach U − s is `far` to `tolerance` (m); the
        iterations of every round are counted; not converged where a round fails or the secant does not close."""
        U, points, iterations = float(far) + self.shift, [], 0
        for _ in range(ROUNDS):
            sol = self.cell.solve(U, guess, fallback)
            iterations += sol.iterations
            if not sol.converged:
                return dataclasses.replace(sol, iterations=iterations)
            shift = float(sol.keep["far_field_shift"])
            miss = U - shift - float(far)
            if abs(miss) <= self.tolerance:
                self.shift = shift
                return dataclasses.replace(sol, iterations=iterations)
            points.append((U, miss))
            guess = fallback = sol.state
            (u0, m0), (u1, m1) = points[-2:] if len(points) > 1 else ((None, None), points[-1])
            U = float(far) + shift if u0 is None or m1 == m0 else u1 - m1 * (u1 - u0) / (m1 - m0)
        return dataclasses.replace(sol, iterations=iterations, converged=False, messages=sol.messages + (
            f"far-field approach {far:.6g} m: U − s missed it by {miss:.3g} m after {ROUNDS} secant rounds",))
