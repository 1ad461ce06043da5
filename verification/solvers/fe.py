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
        cell = prepare(scene, h)
        states, iterations = run_path(cell, scene, h, problem)
        for s in states:
            s.penetration = float(np.mean(h) - np.min(h) - np.mean(s.gap))
        return Answer(states=states, cost=Cost(wall_s=time.perf_counter() - t0, iterations=iterations),
                      ran=f"gfmd-contact reference.fem: {cell.model}")
