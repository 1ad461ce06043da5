"""Our GFMD behind the solver-adapter protocol: the example a third party copies for its own code.

An adapter does three things: declare what the code can do (`capabilities`, with the reason for each thing it
cannot), translate a `Problem` into the code's own input (here a `gfmd_contact` Scene and the heights array,
kept in memory), and translate the code's answer back into `State`s (SI, p compressive > 0, g = indenter −
body) with its cost. Register it under a name in the entry-point group ``gfmd_contact.solvers``::

    [project.entry-points."gfmd_contact.solvers"]
    mycode = "mypackage.adapter:MyCodeSolver"

then ``gfmd verify --solver mycode`` runs every cross-code case against it.
"""

from __future__ import annotations

import math
import time

import numpy as np

from gfmd_contact.core.scene import Scene

from .far_field import FarFieldCell
from .protocol import Answer, Capabilities, Cost, Problem
from .ramp_path import run_path

#: ν of the scene we build: the adapter is given E* only, and a normal-only law on a half-space needs no more
POISSON = 0.3
#: the far-field approach of a free 2+1-D step to this fraction of `reach` (the solver's own tolerance)
FAR_FIELD_TOLERANCE = 1e-10


def interface_keys(interface, contact_modulus):
    """The scene's [interface] keys for the protocol's `Interface` (E in φn* = w/(δn E) is the scene's E)."""
    if interface.kind == "hard-wall":
        return {"interface.law": "hard-wall"}
    if interface.kind == "exponential-cz":  # seed Eq. 3, normal only: φn = w, δn = ρ
        youngs = contact_modulus * (1.0 - POISSON ** 2)
        return {"interface.law": "cohesive", "interface.tangential_ratio": 0.0,
                "interface.length_normal": interface.range,
                "interface.phi_n_star": interface.work_of_adhesion / (interface.range * youngs)}
    if interface.kind == "lj93":
        return {"interface.law": "lj93", "interface.work_of_adhesion": interface.work_of_adhesion,
                "interface.range_length": interface.range}
    raise ValueError(f"Interface.kind = {interface.kind!r}: the gfmd adapter has no such law")


def reach(problem, heights):
    """The problem's length scale (m): the height range, or the law's range where that is larger."""
    return max(float(np.ptp(heights)), problem.interface.range, 1e-12)


def loading_keys(problem, heights):
    """[loading] keys: δ0 places the indenter's start; under pressure control the path sets the load tolerance."""
    reach_ = reach(problem, heights)
    if problem.control == "penetration":
        d0 = max(-min(problem.path), 0.0) + 0.05 * reach_
        return {"loading.initial_separation": d0, "loading.final_penetration": max(max(problem.path), 0.0),
                "loading.steps": len(problem.path)}
    top = float(np.max(np.abs(problem.path)))
    return {"loading.control": "force", "loading.initial_separation": 0.05 * reach_ + 4 * problem.interface.range,
            "loading.path": [0.0, top], "loading.steps": [1]}


def scene_of(problem: Problem, thickness=math.inf) -> Scene:
    """The `gfmd_contact` Scene of `problem` (the surface keys give only the grid: the heights stay in memory)."""
    h = np.asarray(problem.heights, float)
    grid = {"surface.kind": "flat", "surface.realizations": 1, "surface.nodes": h.shape[0],
            "surface.length": problem.lengths[0], "surface.boundary": problem.boundary}
    if h.ndim == 2:
        grid.update({"surface.nodes_y": h.shape[1], "surface.length_y": problem.lengths[1]})
    material = {"material.youngs_modulus": problem.contact_modulus * (1.0 - POISSON ** 2),
                "material.poisson_ratio": POISSON, "material.thickness": thickness}
    return Scene().replace(**grid, **material, **interface_keys(problem.interface, problem.contact_modulus),
                           **loading_keys(problem, h), **{"solver.tolerance": 1e-10})


class GFMDSolver:
    """GFMD (gfmd.loading's cell: the production algorithm chain) on a periodic half-space, or a free one (the
    cell zero-padded). On a free 2+1-D half-space δ is the approach from the far field (u_z → 0 there), under
    either control (`far_field.FarFieldCell`); on a free 1+1-D half-plane it is NaN: the free half-plane's
    displacement is defined only up to a constant (the log), so there is no far-field reference to measure δ from,
    and a penetration path drives the padded cell's mean plane."""

    name = "gfmd"
    capabilities = Capabilities(
        dimensions=frozenset({1, 2}), boundaries=frozenset({"periodic", "free"}),
        interfaces=frozenset({"hard-wall", "exponential-cz", "lj93"}),
        controls=frozenset({"penetration", "pressure"}), warm_start=True,
        why_not={"hard-wall+exponential": "GFMD's cohesive wall pairs the hard wall with seed Eq. 3's attraction "
                                          "(w/ρ)(g/ρ)e^{−g/ρ}, not with the traction (w/ρ)e^{−g/ρ} of V = −w e^{−g/ρ}"})

    def scene(self, problem: Problem) -> Scene:
        """The scene GFMD solves (a subclass may change it; tests/ plants a wrong E* this way)."""
        return scene_of(problem)

    def heights(self, problem: Problem) -> np.ndarray:
        """The profile h GFMD solves (m)."""
        return np.asarray(problem.heights, float)

    def solve(self, problem: Problem) -> Answer:
        from gfmd.loading import (  # the method itself: imported only when it runs
            integrator,
            prepare,
        )
        scene, h = self.scene(problem), self.heights(problem)
        t0 = time.perf_counter()
        cell = prepare(scene, h)
        free = problem.boundary == "free"
        driven = FarFieldCell(cell, FAR_FIELD_TOLERANCE * reach(problem, h)) if free and h.ndim == 2 else cell
        states, iterations = run_path(driven, scene, h, problem)
        if free and h.ndim == 1:
            for state in states:
                state.penetration = float("nan")
        ran = f"gfmd-contact GFMD, {integrator(cell.physics, cell.settings)}, solver.tolerance {scene.solver.tolerance:g}"
        return Answer(states=states, cost=Cost(wall_s=time.perf_counter() - t0, iterations=iterations), ran=ran)
