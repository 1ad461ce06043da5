"""Force control: one load step p̄ = P by an outer search on the indenter displacement U.

Units: SI (see `gfmd_contact.core.conventions`). Method: every trial is a displacement-controlled equilibrium that
the method's own cell solves (warm-started from the nearest accepted state), and the outer search moves U
until the mean pressure p̄(U) reaches the prescribed P: march from the last accepted state in the
direction of P (a stable branch has dp̄/dU > 0), first by a probe of PROBE × the first step, then by
secant steps: each trial goes no further than where the secant through the last two states reaches P
(and at most ×1.5 the last step), and is halved (from the last state) where p̄ turns away, down to
MIN_STEP × the first step; a trial within |p̄ − P| ≤ FORCE_TOLERANCE · max|path| is the answer, and
once P is bracketed, regula falsi (Illinois) down to that tolerance. The secant bound keeps the march on
the branch it starts on: where p̄(U) bends towards an extremum (the approach to a pull-off), the secant
reaches P before p̄ does, so no trial jumps across the extremum to an equilibrium with p̄ = P on its far
side, the branch force control cannot hold (a fixed first step of δ0/10 did: tests/test_force_search.py).
Chosen over the mean mode as an extra unknown of GFMD because it is the same for every method (GFMD and
the FE through the one ramp), reuses each method's verified displacement solver and warm starts, and every state it reports
is a converged equilibrium; the cost is a few displacement solves per load step.

Instability: where, marching towards P, p̄ moves away from P even over the shortest step (past an extremum of p̄(U): the end of a
force-controlled branch, e.g. pull-off or a jump-in), no equilibrium near the previous one carries P.
The search records an EVENT and keeps marching in the same direction to the first state with p̄ = P: the
branch the system jumps to. If the marching reaches the start U = 0 (δ = −δ0) without reaching a
tensile P, the body has detached: no equilibrium carries the tensile load (the indenter would fly off);
the step is recorded as the detached state at U = 0 with p̄ ≠ P (row `load` ≠ `p`) and the event says
so. Step 0 is the start itself, the indenter at U = 0 (δ = −δ0, p̄ ≈ 0 from the law's tail), as in the
ramp. A march that would pass the full-contact limit raises SceneError naming loading.path (for the hard
wall on a half-plane the loads ≥ p̄_fc are refused before the run: `gfmd_contact.core.loading.full_contact_pressure`).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from .errors import SceneError

#: |p̄ − P| ≤ FORCE_TOLERANCE · max|loading.path| ends the search
FORCE_TOLERANCE = 1e-4
#: an instability is declared only when p̄ turns away from the load over a U step ≤ MIN_STEP × the first step
MIN_STEP = 1e-3
#: the first trial of a load step moves U by PROBE × the first step: it measures the branch's slope dp̄/dU
#: for the secant steps (1 %: the p̄ change it makes is far above a converged solve's p̄ noise)
PROBE = 1e-2
#: most displacement solves of one load step before it is given up (recorded as not converged)
MAX_TRIALS = 400


@dataclass
class LoadStep:
    """A solved load step: the step solution at displacement U (m) with observables obs, the displacement
    iterations of all its trials, whether p̄ reached P, and the instability event (dict) or None."""

    solved: object
    U: float
    obs: dict
    iterations: int
    converged: bool
    event: dict | None = None
    detached: bool = False


def solve_load(solve, observe, target, base, *, step, tolerance, u_max):
    """Find U with p̄(U) = target from `base` = (U, state, obs, solution) of the last accepted step.

    solve(U, guess, fallback) → StepSolution; observe(solution) → {p, a_rel, ...}; step: the first trial
    increment of U (m); tolerance: on |p̄ − P| (Pa); u_max: the largest U allowed (full-contact limit;
    inf for a layer). Returns a `LoadStep` (module docstring).
    """
    U0, state0, obs0, sol0 = base
    s = 1.0 if target > obs0["p"] else -1.0
    if abs(obs0["p"] - target) <= tolerance and sol0 is not None:
        return LoadStep(sol0, U0, obs0, 0, True)
    iterations, h, unstable, slope, last = 0, PROBE * step, False, None, None
    cur, prev = (U0, state0, obs0, sol0), None
    for _ in range(MAX_TRIALS):
        d = h if slope is None else min(h, abs(target - cur[2]["p"]) / slope)  # not past the secant's P
        U1 = cur[0] + s * d
        if U1 > u_max and cur[0] < u_max:
            U1 = u_max  # try the limit itself before giving up
        elif U1 > u_max:
            raise SceneError(f"loading.path: the load p̄ = {target:.6g} Pa is beyond full contact: the indenter "
                             f"reaches its full-contact limit (U = {u_max:.6g} m, 0.998 of mean(h) − min(h) past "
                             f"the surface) at p̄ = {cur[2]['p']:.6g} Pa; lower the path's largest load below that")
        if U1 <= 0.0 and s < 0:  # pulled back to the start: detached (module docstring)
            sol = solve(0.0, cur[1], cur[1])
            iterations += sol.iterations
            obs = observe(sol)
            if (obs["p"] - target) * s < 0 or not sol.converged:  # P not reached at the start: detached
                event = _event(target, base, (0.0, obs)) if U0 > 0 else None  # not again once detached
                if event is not None:
                    event.update(detached=True)
                loaded = LoadStep(sol, 0.0, obs, iterations, bool(sol.converged), event, detached=True)
                return loaded if sol.converged else _gave_up(loaded, target, "solve", "at the start U = 0")
            U1 = 0.0
        else:
            sol = solve(U1, cur[1], cur[1])
            iterations += sol.iterations
            last = (U1, sol)
            if not sol.converged:
                h = 0.5 * d
                if h < 1e-6 * step:
                    return _gave_up(LoadStep(sol, U1, observe(sol), iterations, False), target, "solve",
                                    "at every shorter trial step")
                continue
            obs = observe(sol)
        d = abs(U1 - cur[0])
        p1 = obs["p"]
        if (p1 - target) * s >= 0 or abs(p1 - target) <= tolerance:  # reached, or bracketed between cur and U1
            found = _refine(solve, observe, target, cur, (U1, sol.state, obs, sol), tolerance)
            U, sol, obs, its, ok = found
            event = _event(target, base, (U, obs)) if unstable else None
            return _refined(LoadStep(sol, U, obs, iterations + its, ok, event), target)
        if (p1 - cur[2]["p"]) * s < 0 and not unstable:  # p̄ turned away from P: a step too long, or the branch ends
            if d > MIN_STEP * step:
                h = 0.5 * d  # retry shorter from the last state: the branch may reach P before it turns
                continue
            if prev is not None:  # the extremum may lie behind cur: search [prev, U1] for it
                ext, its = _extremum(solve, observe, target, s, prev, (U1, sol.state, obs, sol), step)
                iterations += its
                if ext is not None and (ext[2]["p"] - target) * s >= 0:  # it reaches P: bracketed
                    U, sol, obs, its, ok = _refine(solve, observe, target, prev, ext, tolerance)
                    return _refined(LoadStep(sol, U, obs, iterations + its, ok), target)
            unstable, slope = True, None  # past an extremum of p̄(U) within MIN_STEP·step: no equilibrium near the previous one
            h = step  # then march on, growing, to the branch it jumps to
        else:
            rise = (p1 - cur[2]["p"]) * s / d if d > 0 else 0.0  # secant dp̄/dU towards P
            slope = rise if rise > 0 else None
            h = 1.5 * max(d, h if unstable else 0.0)  # grows ×1.5 from the last step (beyond an event: from h)
        prev, cur = (cur if not unstable else None), (U1, sol.state, obs, sol)
    if cur[3] is None and last is not None:  # no trial accepted: the step records the last one tried
        cur = (last[0], last[1].state, observe(last[1]), last[1])
    return _gave_up(LoadStep(cur[3], cur[0], cur[2], iterations, False), target, "search",
                    f"after MAX_TRIALS = {MAX_TRIALS} displacement solves")


def _refined(loaded, target):
    """A bracketed step: given up if regula falsi stopped on a solve that failed, or on its iteration budget."""
    if loaded.converged:
        return loaded
    if not loaded.solved.converged:
        return _gave_up(loaded, target, "solve", "while the load was bracketed")
    return _gave_up(loaded, target, "search", "in the bracket's regula falsi")


def _gave_up(loaded, target, what, when):
    """`loaded`, not converged, with a message that names what failed: the outer `search` on U (every solve
    converged, the load was not reached) or a displacement `solve`, and the load the step reached."""
    if loaded.solved is None:
        return loaded
    why = ("the outer search on U gave up " + when + " (each solve converged)" if what == "search"
           else "a displacement solve did not converge " + when)
    message = (f"force control did not reach the load P = {target:.6g} Pa: {why}; the step records p̄ = "
               f"{loaded.obs['p']:.6g} Pa at U = {loaded.U:.6g} m (not converged)")
    loaded.solved = dataclasses.replace(loaded.solved, messages=tuple(loaded.solved.messages) + (message,))
    return loaded


def _refine(solve, observe, target, a, b, tolerance, max_iter=80):
    """Illinois regula falsi on f(U) = p̄(U) − P between the bracket ends a, b = (U, state, obs, solution);
    each trial warm-starts from the nearer end. Returns (U, solution, obs, iterations, converged)."""
    fa, fb = a[2]["p"] - target, b[2]["p"] - target
    if abs(fb) <= tolerance:
        return b[0], b[3], b[2], 0, True
    its = 0
    for _ in range(max_iter):
        U = (a[0] * fb - b[0] * fa) / (fb - fa)
        near = a if abs(U - a[0]) < abs(U - b[0]) else b
        sol = solve(U, near[1], near[1])
        its += sol.iterations
        obs = observe(sol)
        if not sol.converged:
            return U, sol, obs, its, False
        f = obs["p"] - target
        if abs(f) <= tolerance:
            return U, sol, obs, its, True
        if f * fb < 0:
            a, fa = b, fb
        else:
            fa *= 0.5  # Illinois: the end that stays has its value halved
        b, fb = (U, sol.state, obs, sol), f
    return b[0], b[3], b[2], its, False


def _extremum(solve, observe, target, s, a, b, step, tol_rel=MIN_STEP):
    """Golden-section search on [a, b] (states (U, state, obs, solution)) for the extremum of p̄(U) towards
    the load (max of (p̄ − P)·s); returns (best state, iterations) or (None, its) if a solve failed."""
    g = (np.sqrt(5.0) - 1.0) / 2.0
    lo, hi = a, b
    its, best = 0, max((a, b), key=lambda x: (x[2]["p"] - target) * s)

    def at(U, near):
        nonlocal its
        sol = solve(U, near[1], near[1])
        its += sol.iterations
        return (U, sol.state, observe(sol), sol) if sol.converged else None

    x1 = at(hi[0] - g * (hi[0] - lo[0]), lo)
    x2 = at(lo[0] + g * (hi[0] - lo[0]), hi)
    while x1 is not None and x2 is not None and abs(hi[0] - lo[0]) > tol_rel * step:
        for x in (x1, x2):
            if (x[2]["p"] - target) * s > (best[2]["p"] - target) * s:
                best = x
        if (best[2]["p"] - target) * s >= 0:
            return best, its
        if (x1[2]["p"] - target) * s > (x2[2]["p"] - target) * s:
            hi, x2 = x2, x1
            x1 = at(hi[0] - g * (hi[0] - lo[0]), lo)
        else:
            lo, x1 = x1, x2
            x2 = at(lo[0] + g * (hi[0] - lo[0]), hi)
    if x1 is None or x2 is None:
        return None, its
    return max((best, x1, x2), key=lambda x: (x[2]["p"] - target) * s), its


def _event(target, base, after):
    """The instability event: load P (Pa), δ-defining U (m), p̄ and a_rel before (last accepted step)
    and after (the state the system jumped to)."""
    U0, _, obs0, _ = base
    U1, obs1 = after
    return {"kind": "jump-in" if obs1["a_rel"] > obs0["a_rel"] else "jump-out", "load": float(target),
            "U_before": float(U0), "U_after": float(U1), "p_before": float(obs0["p"]), "p_after": float(obs1["p"]),
            "a_rel_before": float(obs0["a_rel"]), "a_rel_after": float(obs1["a_rel"]), "detached": False}


def first_step(loading):
    """First trial increment of U (m) for a load step: δ0/10, at least 1e-12 m."""
    return max(loading.initial_separation / 10.0, 1e-12)


def tolerance(loading):
    """|p̄ − P| (Pa) accepted as P."""
    return FORCE_TOLERANCE * float(np.max(np.abs(loading.path)))
