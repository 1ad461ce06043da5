"""Tamaas (FFT boundary elements, periodic) behind the solver-adapter protocol.

Translation (each checked in tests/test_peer_adapters.py):

* heights: Tamaas' surface is summits-up and the gap it reports is g = u + s (u its displacement, positive into
  the body); ours is the indenter's lower surface h, so s = −h and Tamaas' gap is our g.
* modulus: Tamaas' basic models take E and ν and use E* = E/(1−ν²) with the half-space kernel E*|q|/2 (plane
  strain on basic_1d); we set E = E*, ν = 0.
* penetration control: Tamaas controls the mean gap; with ⟨u_z⟩ = 0, ⟨g⟩ = ⟨h⟩ − min h − δ. The answer's δ
  is ⟨h⟩ − min h − ⟨g⟩ under either control.
* interfaces: the hard wall is PolonskyKeerRey; "hard-wall+exponential" adds Tamaas' ExponentialAdhesionFunctional
  (V(g) = −w e^{−g/ρ} on the hard wall) to the gap-primal PolonskyKeerRey, the route Tamaas offers for adhesion.
* a hard wall with δ ≤ 0 touches nowhere: that state (p = 0, g = h − min h − δ) is returned without calling
  Tamaas, which cannot solve a problem with no contact node.

Cost: wall time; iterations are the PolonskyKeerRey counts Tamaas prints at log level info (captured).
"""

from __future__ import annotations

import ctypes
import os
import re
import sys
import tempfile
import time

import numpy as np
import tamaas as tm

from .protocol import Answer, Capabilities, Cost, NotConverged, Problem, State

#: PolonskyKeerRey's tolerance (its own relative error measure); at 1e-12 it can stall at its round-off
#: (1.6e-12 after its 1000 iterations on the Westergaard sinusoid at N = 64 and δ = 0.17 h0)
TOLERANCE = 1e-10


def _run_logged(call, *args):
    """(result, iterations): `call(*args)` with Tamaas at log level info, its iteration table read from fds 1, 2."""
    level = tm.get_log_level()
    sys.stdout.flush()
    sys.stderr.flush()
    with tempfile.TemporaryFile() as sink:
        saved = [os.dup(1), os.dup(2)]
        os.dup2(sink.fileno(), 1)
        os.dup2(sink.fileno(), 2)
        tm.set_log_level(tm.LogLevel.info)
        try:
            result = call(*args)
        finally:
            ctypes.CDLL(None).fflush(None)  # C stdio's buffer, where Tamaas' log waits when fd 1 is a file
            tm.set_log_level(level)
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
        sink.seek(0)
        text = sink.read().decode(errors="replace")
    rows = [int(line.split()[0]) for line in text.splitlines() if re.match(r"\s*\d+\s+\S", line)]
    return result, (rows[-1] if rows else None)


def _model(problem: Problem):
    """A Tamaas basic model of the problem's cell with E* = E (ν = 0)."""
    kind = tm.model_type.basic_1d if problem.dimension == 1 else tm.model_type.basic_2d
    model = tm.ModelFactory.createModel(kind, [float(s) for s in problem.lengths], list(np.shape(problem.heights)))
    model.E, model.nu = float(problem.contact_modulus), 0.0
    return model


def _solver(problem: Problem, model, surface):
    """(solver, label, functional): PolonskyKeerRey, gap-primal under penetration control, with the adhesion
    functional where the interface has one."""
    adhesive = problem.interface.kind == "hard-wall+exponential"
    if problem.control == "penetration":
        solver = tm.PolonskyKeerRey(model, surface, TOLERANCE, tm.PolonskyKeerRey.gap, tm.PolonskyKeerRey.gap)
        label = "PolonskyKeerRey (gap primal, mean-gap control)"
    else:
        solver = tm.PolonskyKeerRey(model, surface, TOLERANCE)
        label = "PolonskyKeerRey (pressure primal, mean-pressure control)"
    if adhesive:
        functional = tm.ExponentialAdhesionFunctional(surface)
        functional.parameters = {"rho": float(problem.interface.range),
                                 "surface_energy": float(problem.interface.work_of_adhesion)}
        solver.addFunctionalTerm(functional)
        label += " + ExponentialAdhesionFunctional"
        return solver, label, functional  # the functional must outlive the solve
    return solver, label, None


def _untouched(h, delta):
    """The hard wall's state at δ ≤ 0: no contact, no load."""
    gap = h - h.min() - delta
    return State(pressure=np.zeros_like(h), gap=gap, mean_pressure=0.0, penetration=float(delta),
                 contact=np.zeros(h.shape, bool))


def _state(model, h, gap_primal):
    """The model's fields as a `State`; contact is PolonskyKeerRey's active set: g = 0 with the gap primal (its
    dual, the pressure, is ~ tolerance·p̄ off contact, not 0), p > 0 with the pressure primal."""
    p = np.array(model.traction, float).reshape(h.shape)
    g = np.array(model["gap"], float).reshape(h.shape)
    contact = g <= 0.0 if gap_primal else p > 0.0
    return State(pressure=p, gap=g, mean_pressure=float(p.mean()),
                 penetration=float(h.mean() - h.min() - g.mean()), contact=contact)


class TamaasSolver:
    """Tamaas' PolonskyKeerRey on a periodic half-plane (basic_1d) or half-space (basic_2d)."""

    name = "tamaas"
    capabilities = Capabilities(
        dimensions=frozenset({1, 2}), boundaries=frozenset({"periodic"}),
        interfaces=frozenset({"hard-wall", "hard-wall+exponential"}),
        controls=frozenset({"penetration", "pressure"}), warm_start=True,
        why_not={"free": "Tamaas' boundary-element models are periodic (FFT influence coefficients on the cell); "
                         "there is no free (non-periodic) half-space in tamaas 2.9",
                 "exponential-cz": "Tamaas' adhesion is a functional added to the hard-wall solver: the interface "
                                   "is always a hard wall plus V(g); a cohesive law without the hard wall "
                                   "(seed Eq. 3) is not offered",
                 "lj93": "tamaas 2.9 has no Lennard-Jones 9-3 functional (its adhesion functionals: exponential, "
                         "Maugis, squared exponential)"})

    def refuses(self, problem: Problem) -> str | None:
        """The combination Tamaas cannot do: adhesion under pressure control."""
        if problem.control == "pressure" and problem.interface.kind == "hard-wall+exponential":
            return ("pressure control with 'hard-wall+exponential': Tamaas' adhesion functional works with the "
                    "gap-primal PolonskyKeerRey only (mean-gap control); its pressure-primal solver returns a "
                    "non-equilibrium state with it")
        return None

    def solve(self, problem: Problem) -> Answer:
        if reason := self.refuses(problem):
            raise ValueError(f"problem {problem.name!r}: {reason}")
        h = np.asarray(problem.heights, float)
        adhesive = problem.interface.kind == "hard-wall+exponential"
        model, surface = _model(problem), np.ascontiguousarray(-h)
        solver, label, _functional = _solver(problem, model, surface)
        states, iterations, worst = [], 0, 0.0
        t0 = time.perf_counter()
        for k, value in enumerate(problem.path):
            value = float(value)
            if problem.control == "penetration" and not adhesive and value <= 0.0:
                states.append(_untouched(h, value))
                continue
            if problem.control == "pressure" and value <= 0.0:
                raise ValueError(f"problem {problem.name!r}: path[{k}] = {value:g} Pa: a hard wall carries no "
                                 "tensile mean pressure, and p̄ = 0 leaves δ undetermined (use penetration control)")
            target = h.mean() - h.min() - value if problem.control == "penetration" else value
            error, its = _run_logged(solver.solve, target)
            iterations += its or 0
            worst = max(worst, float(error))
            state = _state(model, h, problem.control == "penetration")
            if not (np.isfinite(error) and (error <= TOLERANCE or adhesive and not state.contact.any())):
                raise NotConverged(f"{problem.name or 'problem'}: step {k} (path value {value:.6g}): Tamaas' "
                                   f"{label} ended with error {error:.3g} > {TOLERANCE:g}")
            states.append(state)
        ran = (f"tamaas {tm.__version__}, {label}, tolerance {TOLERANCE:g}, basic_{problem.dimension}d model "
               f"(E = E*, ν = 0), warm start along the path; largest final error {worst:.2g}")
        return Answer(states=states, cost=Cost(wall_s=time.perf_counter() - t0, iterations=iterations or None),
                      ran=ran)
