"""Our FE reference (reference.fem, P2 plane strain) behind the solver-adapter protocol.

The FE models a periodic layer bonded to a rigid base, not a half-plane: this adapter meshes a layer of depth
DEPTH × L, whose non-mean modes match the half-plane's to e^{−4π·DEPTH} (the mean mode is the layer's own
compression, so pressure control only). The penetration it reports is the half-plane's, δ = ⟨h⟩ − min h − ⟨g⟩
(⟨u_z⟩ = 0 there), which the gap field fixes alone.
"""

from __future__ import annotations

import time

import numpy as np

from .gfmd import scene_of
from .protocol import Answer, Capabilities, Cost, Problem
from .ramp_path import run_path

DEPTH = 2.0  # layer depth / L
#: the deep layers' coarsest spacing L/64, not reference.fem's default L/32: the longest modes decay over ~L/2π, so
#: the coarse deep elements set their stiffness, which does not refine with N. Mode 1's stiffness error is 1.3e-5
#: at L/32, 1.8e-6 at L/64 (1.7e-7 at L/128); at L/32 it left Westergaard's p̄(ḡ) a bias of +0.9e-6 … +2.3e-6 p*
#: (rising with the load) at every N = 128 … 1024, the floor of the cross-code convergence case; L/64 cuts it below
#: 2.2e-7 p* for 1.6× the time at N = 1024 (L/128: below 5e-8 p*, 3.4×). docs/design/cross_code.md has the numbers.
MESH = {"min_segments": 64}


class FESolver:
    """reference.fem P2 on a deep periodic layer (pressure control), 1+1-D."""

    name = "fe"
    capabilities = Capabilities(
        dimensions=frozenset({1}), boundaries=frozenset({"periodic"}),
        interfaces=frozenset({"hard-wall", "exponential-cz", "lj93"}), controls=frozenset({"pressure"}),
        warm_start=True,
        why_not={"2": "this adapter drives the plane-strain FE (reference.fem) only; the 3-D FE (reference.fem3d) "
                      "solves displacement-controlled layers and is not wired in",
                 "free": "the FE cell is periodic",
                 "penetration": "the FE solves a layer on a rigid base, whose δ counts the layer's mean compression; "
                                "the half-plane's δ (⟨u_z⟩ = 0) is not a control it has",
                 "hard-wall+exponential": "the FE solves either a hard wall or a smooth law, not both at once"})

    def solve(self, problem: Problem) -> Answer:
        from reference.fem.run import prepare_cohesive, prepare_hard_wall
        scene = scene_of(problem, thickness=DEPTH * problem.lengths[0])
        h = np.asarray(problem.heights, float)
        prepare = prepare_hard_wall if problem.interface.kind == "hard-wall" else prepare_cohesive
        t0 = time.perf_counter()
        cell = prepare(scene, h, mesh_kw=MESH)
        states, iterations = run_path(cell, scene, h, problem)
        for s in states:
            s.penetration = float(np.mean(h) - np.min(h) - np.mean(s.gap))
        return Answer(states=states, cost=Cost(wall_s=time.perf_counter() - t0, iterations=iterations),
                      ran=f"gfmd-contact reference.fem: {cell.model}")
