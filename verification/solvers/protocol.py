"""The solver-adapter protocol: what a verification case gives a contact code, and what the code returns.

Units SI, signs of `gfmd_contact.core.conventions`: the rigid indenter is above an elastic body; heights h are
its lower surface (it touches first where h is smallest); the gap g ≥ 0 on a hard wall; pressure p = −t_z is
compressive > 0 (negative where an adhesive interface pulls).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import numpy as np

#: the interface laws a case may ask for (`Interface.kind`)
INTERFACES = ("hard-wall", "exponential-cz", "hard-wall+exponential", "lj93")
#: the control quantities (`Problem.control`)
CONTROLS = ("penetration", "pressure")
#: the boundary kinds (`Problem.boundary`)
BOUNDARIES = ("periodic", "free")


@dataclass(frozen=True)
class Capabilities:
    """What an adapter can do; `why_not` gives, for each value it lacks, the reason in the code's own terms.

    dimensions: {1, 2}: 1 = 1+1-D profile on a plane-strain half-plane, 2 = 2+1-D surface on a half-space.
    boundaries: ⊆ {"periodic", "free"}; interfaces: ⊆ `INTERFACES`; controls: ⊆ {"penetration", "pressure"};
    warm_start: a path continues from the previous state. why_not keys are the lacking values as strings
    ("2", "free", "lj93", "pressure", ...).
    """
    dimensions: frozenset
    boundaries: frozenset
    interfaces: frozenset
    controls: frozenset
    warm_start: bool
    why_not: Mapping[str, str] = field(default_factory=dict)


@dataclass(frozen=True)
class Interface:
    """The interface law.

    kind: "hard-wall"; "exponential-cz" (normal only: T = (w/ρ)(g/ρ)e^{−g/ρ}, tensile > 0);
    "hard-wall+exponential" (hard wall plus V(g) = −w e^{−g/ρ}); "lj93" (Lennard-Jones 9-3 wall, work of
    adhesion w, equilibrium gap ρ). work_of_adhesion w (J/m²), 0 for the hard wall; range ρ (m).
    """
    kind: str
    work_of_adhesion: float = 0.0
    range: float = 0.0


@dataclass(frozen=True)
class Problem:
    """A case's inputs, the same for every code.

    heights: the indenter's lower surface h (m), shape (N,) or (Nx, Ny), axis 0 = x; grid x_j = (j − N/2)·L/N.
    lengths: cell sizes (m), (L,) or (Lx, Ly). contact_modulus: E* = E/(1−ν²) (Pa).
    boundary: "periodic" | "free". control: "penetration" — δ (m) past first touch, g = h − min h − δ − u_z,
    u_z > 0 out of the body, ⟨u_z⟩ = 0 over a periodic cell; or "pressure" — mean pressure p̄ (Pa), compressive > 0.
    path: the control's values in order (a load path). name: the case's name, for messages.
    """
    heights: np.ndarray
    lengths: tuple
    contact_modulus: float
    interface: Interface
    boundary: str
    control: str
    path: tuple
    name: str = ""

    @property
    def dimension(self) -> int:
        """1 for a profile (1+1-D), 2 for a surface (2+1-D)."""
        return int(np.ndim(self.heights))


@dataclass
class State:
    """One equilibrium on the path: fields at the nodes and the means.

    pressure p = −t_z (Pa), compressive > 0; gap g (m); mean_pressure p̄ (Pa); penetration δ (m) (NaN where
    a pressure-controlled code cannot say); contact: bool, nodes in contact by the code's own rule.
    """
    pressure: np.ndarray
    gap: np.ndarray
    mean_pressure: float
    penetration: float
    contact: np.ndarray


@dataclass
class Cost:
    """The path's cost: wall time (s), and the code's own iteration count and FFT pairs where exposed."""
    wall_s: float
    iterations: int | None = None
    fft_pairs: int | None = None


@dataclass
class Answer:
    """A code's answer to a `Problem`: one `State` per path value, the cost, and what ran (code, version,
    algorithm, options)."""
    states: list
    cost: Cost
    ran: str


@runtime_checkable
class Solver(Protocol):
    """A contact code behind the protocol: a name, its capabilities, and `solve`; optionally `refuses(problem)`,
    the reason it cannot answer a combination its capabilities allow one by one (see `not_applicable`)."""
    name: str
    capabilities: Capabilities

    def solve(self, problem: Problem) -> Answer: ...


def _needs(problem: Problem) -> list[tuple[str, bool]]:
    """(key, present?) for each need of the problem, keyed as in `Capabilities.why_not`."""
    return [(str(problem.dimension), problem.dimension in (1, 2)),
            (problem.boundary, problem.boundary in BOUNDARIES),
            (problem.interface.kind, problem.interface.kind in INTERFACES),
            (problem.control, problem.control in CONTROLS)]


class NotConverged(RuntimeError):
    """An adapter's step of the path did not converge (the message names the case, the step and the code's words)."""


def not_applicable(solver, problem: Problem) -> str | None:
    """The adapter's reason why it cannot answer `problem`, or None when it can: first the capability sets (reasons
    from `why_not`), then, where they all allow it, the adapter's optional hook `refuses(problem) -> str | None`
    for combinations the sets cannot express (e.g. a free boundary only in 2+1-D); an adapter without the hook
    refuses nothing more."""
    for key, known in _needs(problem):
        if not known:
            raise ValueError(f"problem {problem.name!r}: unknown value {key!r} (Problem.dimension/boundary/"
                             f"interface.kind/control; known: {BOUNDARIES}, {INTERFACES}, {CONTROLS})")
    caps = solver.capabilities
    lacking = [key for key, have in ((str(problem.dimension), problem.dimension in caps.dimensions),
                                     (problem.boundary, problem.boundary in caps.boundaries),
                                     (problem.interface.kind, problem.interface.kind in caps.interfaces),
                                     (problem.control, problem.control in caps.controls)) if not have]
    if not lacking:
        refuses = getattr(solver, "refuses", None)
        return refuses(problem) if refuses is not None else None
    return "; ".join(f"{key}: {caps.why_not.get(key, 'not supported by ' + solver.name)}" for key in lacking)
