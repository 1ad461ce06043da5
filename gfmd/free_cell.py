"""GFMD on a free boundary: the cell of `gfmd.loading` on the padded cell, its results those of the region.

Units: SI (see `gfmd_contact.core.conventions`). The model (`gfmd_contact.core.free_boundary.padded_model`) is the
padded cell; this cell raises the indenter outside the region by the law's exact-zero gap
(`gfmd_contact.core.free_boundary.far_gap`, plus the region's size: a hard wall is never reached there), checks
that no traction acted outside the region (a step where one did is not converged), and hands the ramp the
region's gap, tractions and fields. The warm-start state stays the padded spectrum. Each saved step keeps
the far-field shift s (m, `gfmd_contact.core.free_boundary.far_field_shift`): u + s is the free body's
displacement (2+1-D: from the far field), δ − s the approach from there.
"""

from __future__ import annotations

import dataclasses
import functools

from gfmd_contact.core import free_boundary


class FreeRegion:
    """What `gfmd.loading.GfmdCell` changes on a free-boundary model (a mixin before it: `gfmd.loading.FreeGfmdCell`):
    the indenter on the region only, the results cropped to it."""

    @functools.cached_property
    def far(self):
        """The indenter's height (m) outside the region above the region's highest point."""
        s = self.scene.surface
        size = max(s.length, s.length_y if s.two_d else 0.0)
        return free_boundary.far_gap(self.physics.law, size)

    def indenter(self, displacement):
        z = super().indenter(displacement)
        return free_boundary.padded_indenter(z, self.physics.region, self.far)

    def solve(self, displacement, guess, fallback):
        solved = super().solve(displacement, guess, fallback)
        region = self.physics.region
        outside = free_boundary.outside_traction(solved.t_n, region)
        if self.physics.tangential and solved.relaxed:  # the tangential traction too (u_x solved)
            outside = max(outside, free_boundary.outside_traction(solved.fields()["t_t"], region))
        messages, converged = solved.messages, solved.converged
        if outside != 0.0:
            messages += ((f"free boundary: a traction of {outside:.3g} Pa acted outside the region (the indenter's "
                          "far surface was reached): the step is not the free-boundary solution"),)
            converged = False
        fields = solved.fields

        def cropped():
            return {k: free_boundary.crop(v, region) for k, v in fields().items()}

        shift = free_boundary.far_field_shift(self.physics, solved.t_n)
        return dataclasses.replace(
            solved, gap=free_boundary.crop(solved.gap, region), t_n=free_boundary.crop(solved.t_n, region),
            u_x=free_boundary.crop(solved.u_x, region), fields=cropped, messages=messages, converged=converged,
            keep=dict(solved.keep, far_field_shift=shift))
