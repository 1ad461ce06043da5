"""One Result shape for every method (GFMD, FE, analytic): per-step curve + selected fields.

Units: SI (see `gfmd_contact.core.conventions`). The curve holds, per load step, the columns
`CURVE_COLUMNS` (U, δ and the observables from `gfmd_contact.core.observables`); `fields`
maps a step index to the surface fields `FIELD_NAMES` on the N nodes (a 2+1-D surface: arrays of
shape (Nx, Ny), axis 0 x, axis 1 y; positions `x` and `y`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

#: per-step columns (SI; converged is 0/1, wall_s in seconds)
CURVE_COLUMNS = ("step", "U", "delta", "p", "a_rel", "g_r", "g", "iterations", "residual", "converged", "wall_s")
#: the keys Result.diagnostics may hold (see Result)
DIAGNOSTICS = ("problem", "setup_s", "solutions", "wall_forces", "fallback_steps", "algorithms", "instabilities")
#: per-node fields saved for selected steps: u_z, u_x, gap Δn (m), t_n = t_z, t_t = t_x (Pa)
FIELD_NAMES = ("u_z", "u_x", "gap", "t_n", "t_t")


@dataclass
class Result:
    """Outcome of one method on one realization of a scene.

    diagnostics holds what only some methods produce, under declared keys (absent
    where a method has none):

    ==============  ===========================================================
    key             meaning
    ==============  ===========================================================
    problem         FE: the assembled cell (reference.fem), for export and checks
    setup_s         FE: mesh, assembly and factorisation time (s)
    solutions       FE: {step: surface-unknowns vector} at the saved steps
    wall_forces     FE hard wall: {step: wall forces μ (N/m)} at the saved steps
    fallback_steps  FE: the steps at which the fallback solver ran (list)
    algorithms      GFMD: per step (list), the algorithms that relaxed it (`gfmd.chains`:
                    "ncg", "ncg→fire", "cg-dual", "fire→newton", ...; "" unknown)
    instabilities   force control: the steps where no equilibrium near the previous one carried
                    the load (`gfmd_contact.core.force`): list of {step, kind, load, δ/U/p̄/a_rel before and
                    after, detached}
    ==============  ===========================================================
    """

    scene: object  # gfmd_contact.core.scene.Scene
    method: str  # e.g. "gfmd-ncg", "gfmd-cg-dual2", "gfmd-fire", "gfmd-verlet", "fe-p2" (GFMD: its chain, gfmd.chains)
    model: str  # the model actually solved, in words
    realization: int
    x: np.ndarray  # node positions (m) along x: (N,) (a 2+1-D surface: (Nx,))
    h: np.ndarray  # indenter profile (m): (N,), or (Nx, Ny) for a 2+1-D surface
    curve: dict = field(default_factory=lambda: {c: [] for c in CURVE_COLUMNS})
    fields: dict = field(default_factory=dict)  # step -> {name: array}
    messages: list = field(default_factory=list)  # failures, e.g. non-converged steps
    notes: list = field(default_factory=list)  # facts of the run that are not failures, e.g. an early stop
    reasons: tuple = ()
    diagnostics: dict = field(default_factory=dict)  # method-specific extras, DIAGNOSTICS keys
    y: np.ndarray | None = None  # 2+1-D: node positions along y (m), (Ny,); None for a 1+1-D profile

    @property
    def seed(self):
        """The random seed of this realization's profile: surface.seed + realization."""
        return self.scene.surface.seed + self.realization

    def append_step(self, **row):
        for c in CURVE_COLUMNS:
            self.curve[c].append(row[c])

    def finalize(self):
        """Convert curve lists to arrays (idempotent)."""
        self.curve = {c: np.asarray(v) for c, v in self.curve.items()}
        return self

    @property
    def all_converged(self):
        return bool(np.all(np.asarray(self.curve["converged"], bool)))
