"""A chain's vocabulary as typed data: the algorithms by name, their options and `Link`, one algorithm of a chain.

A link says which algorithm runs (a key of `ALGORITHMS`), with which options changed, from which
states (`Start`, tried in turn until a run is kept), with how many iterations (`Budget`) and which
converged state it keeps (`Accept`). `gfmd.chains` declares the chains and walks them; a link with a
value outside this vocabulary is refused where it is built, not where a chain runs it.

Options, as scipy.optimize's per-method ``options``: an algorithm module that declares a frozen
dataclass `Options` runs with it (`options_for`: the `Settings` fields of its field names), the others
with the whole `Settings`.
"""

from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass, fields
from enum import Enum

from . import algorithms
from .settings import Settings

#: the algorithm modules by name: every module of `gfmd.algorithms` (one each, `solve(problem, start, options) ->
#: Relaxed`), so a new algorithm is its file and the chain entries that run it
MODULES = {info.name: importlib.import_module(f"{algorithms.__name__}.{info.name}")
           for info in pkgutil.iter_modules(algorithms.__path__)}
#: their `solve` by name (what a chain runs; tests put stand-ins here)
ALGORITHMS = {name: module.solve for name, module in MODULES.items()}
#: the options dataclass of each algorithm that declares one
OPTIONS = {name: module.Options for name, module in MODULES.items() if hasattr(module, "Options")}


def options_for(algorithm, settings):
    """What `algorithm` runs with: its own `Options` with the `settings` fields of those names, else `settings`."""
    kind = OPTIONS.get(algorithm)
    return settings if kind is None else kind(**{f.name: getattr(settings, f.name) for f in fields(kind)})


class Start(Enum):
    """Where a link starts."""

    GUESS = "guess"  # the step's guess
    END = "end"  # where the link before stopped
    FINITE_END = "finite end"  # that, where its residual is finite and below that of the state it started from
    #: where the chain's first link, the continuation Newton, stopped without converging at a finite residual,
    #: resumed to its stall where it broke off at a jump (never a converged state the chain rejected); skipped
    #: where that is the guess itself, from which FIRE ran already
    STALLED_END = "stalled end"
    HANDOVER = "handover"  # the state the last handover link reached; skipped where it reached none

    @property
    def words(self):
        return {"guess": "the step's guess", "end": "the end state of the one before",
                "finite end": "the end state of the one before", "stalled end": "where the continuation Newton stalled",
                "handover": "FIRE's handover state"}[self.value]


class Budget(Enum):
    """A link's iterations."""

    ALL = "all"  # Settings.max_iterations
    LEFT = "left"  # what the links before left
    REST = "rest"  # that, at least 1
    COUPLED_FIRE = "coupled fire"  # min(COUPLED_FIRE_BUDGET, max_iterations // 2)
    #: min(COUPLED_FIRE_CRAWL, max_iterations // 2) less the handover link's iterations, at least 1
    COUPLED_CRAWL = "coupled crawl"


class Accept(Enum):
    """Which converged state a link keeps (the distances in law lengths, `gfmd.coupled_rules`)."""

    ANY = "any"
    CONTINUATION = "continuation"  # no node moved COUPLED_JUMP from the step's start
    PREDICTED = "predicted"  # none moved COUPLED_PREDICTION_MOVE from the frictionless prediction
    NEAR = "near"  # none moved COUPLED_HANDOVER_MOVE from the handover state
    LOCALLY_STABLE = "locally stable"  # the tangent's eigenvalues nearest 0 have Re λ > 0

    @property
    def stability(self):
        """Whether the kept state must be locally stable (`gfmd.coupled_stability`)."""
        return self is Accept.LOCALLY_STABLE


_SETTINGS_FIELDS = frozenset(f.name for f in fields(Settings))


@dataclass(frozen=True)
class Link:
    """One algorithm of a chain.

    algorithm: a key of `ALGORITHMS`; options: the fields of the algorithm's options (its `Options`, else `Settings`)
    this link sets, e.g. (("method", "verlet"),);
    starts: where it starts, tried in turn until a run is kept; budget: its iterations; accept: which converged state
    it keeps; handover: it runs to the looser residual `Settings.coupled_handover` and hands the state it reaches to
    the links after it (start `Start.HANDOVER`); frictionless: it runs on the frictionless reduction of the coupled
    problem (`gfmd.problem.frictionless`), its u_z returned with the start's u_x.
    """

    algorithm: str
    options: tuple = ()
    starts: tuple = (Start.GUESS,)
    budget: Budget = Budget.ALL
    accept: Accept = Accept.ANY
    handover: bool = False
    frictionless: bool = False

    def __post_init__(self):
        if self.algorithm not in ALGORITHMS:
            raise ValueError(f"Link.algorithm = {self.algorithm!r}: expected one of {', '.join(ALGORITHMS)}")
        if not (isinstance(self.starts, tuple) and self.starts and all(isinstance(s, Start) for s in self.starts)):
            raise ValueError(f"Link.starts = {self.starts!r}: expected a non-empty tuple of gfmd.links.Start")
        for name, kind in (("budget", Budget), ("accept", Accept)):
            if not isinstance(getattr(self, name), kind):
                raise ValueError(f"Link.{name} = {getattr(self, name)!r}: expected a gfmd.links.{kind.__name__}")
        for name in ("handover", "frictionless"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"Link.{name} = {getattr(self, name)!r}: expected True or False")
        known = {f.name for f in fields(OPTIONS[self.algorithm])} if self.algorithm in OPTIONS else _SETTINGS_FIELDS
        bad = [o for o in self.options if not (isinstance(o, tuple) and len(o) == 2 and o[0] in known)]
        if bad:
            raise ValueError(f"Link.options: {bad!r} are not (field, value) pairs of {self.algorithm}'s options")
