"""Our methods' step solvers (a `gfmd_contact.core.ramp` Cell: GFMD's or the FE's) driven along a `Problem`'s
path with the heights held in memory: penetration control solves each δ in turn, warm-started from the last
state; pressure control finds δ for each p̄ with `gfmd_contact.core.force.solve_load`, as the ramp does.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.core.force import first_step, solve_load
from gfmd_contact.core.force import tolerance as load_tolerance
from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.observables import contact_mask, mean_pressure
from gfmd_contact.core.ramp import force_u_max

from .protocol import NotConverged, State


def _state(scene, law, h, delta0, U, sol):
    gap, t_z = np.asarray(sol.gap, float), np.asarray(sol.t_n, float)
    return State(pressure=-t_z, gap=gap, mean_pressure=mean_pressure(t_z), penetration=float(U - delta0),
                 contact=np.asarray(contact_mask(law, gap, t_z), bool))


def _check(sol, converged, problem, k):
    if not converged:
        raise NotConverged(f"{problem.name or 'problem'}: step {k} (path value {problem.path[k]:.6g}) did not "
                           f"converge: {'; '.join(sol.messages) or 'no message'}")


def run_path(cell, scene, h, problem):
    """(states, iterations): one `State` per path value, and the solver iterations of the whole path."""
    law, delta0 = law_from_scene(scene), scene.loading.initial_separation
    current = cell.initial_state()
    states, iterations = [], 0
    if problem.control == "penetration":
        for k, delta in enumerate(problem.path):
            U = float(delta) + delta0
            sol = cell.solve(U, current, current)
            iterations += sol.iterations
            _check(sol, sol.converged, problem, k)
            current = sol.state
            states.append(_state(scene, law, h, delta0, U, sol))
        return states, iterations

    def observe(sol):  # what solve_load reads
        return {"p": mean_pressure(sol.t_n), "a_rel": float(np.mean(contact_mask(law, sol.gap, sol.t_n)))}

    start = cell.solve(0.0, current, current)  # out of contact, δ = −δ0
    _check(start, start.converged, problem, 0)
    base = (0.0, start.state, observe(start), start)
    u_max = force_u_max(scene, h)  # the ramp's own bound on U: a periodic half-plane's full contact, else none
    for k, target in enumerate(problem.path):
        loaded = solve_load(cell.solve, observe, float(target), base, step=first_step(scene.loading),
                            tolerance=load_tolerance(scene.loading), u_max=u_max)
        iterations += loaded.iterations
        _check(loaded.solved, loaded.converged, problem, k)
        base = (loaded.U, loaded.solved.state, loaded.obs, loaded.solved)
        states.append(_state(scene, law, h, delta0, loaded.U, loaded.solved))
    return states, iterations
