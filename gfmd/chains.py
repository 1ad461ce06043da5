"""Which GFMD algorithms relax a load step: one chain per law kind and key, declared once as typed data.

A chain is a tuple of `gfmd.links.Link`s: the first algorithm relaxes the step; where it stalls
(`Relaxed.stalled`) or its converged state fails the link's acceptance test, the next one runs, from
the step's guess or from where the one before stopped, with the iterations left. `relax` walks the
chain; `Relaxed.method` names the algorithms that ran, joined by "→" ("ncg→fire": the NCG stalled,
FIRE finished the step). `chain_key` reads the key from `Settings.method` (the scene's
solver.method), `hard_wall`, `cohesive`, `coupled` and `dual_coarse_block`. Only chains a scene or
the verification suite reaches are here; a test or benchmark walks a chain of its own with
`relax(..., chain=...)`. The measurements that chose them: docs/design/solvers.md. An algorithm has
one name, its module's `LABEL` (what `Relaxed.method`, curve.csv's algorithm column and the docs say;
the module's file name says what it does: `hard_wall_two_level_cg` is "cg-dual2"); a chain's key is
the label of its first algorithm (the Result's method "gfmd-" + key), or a coupled chain's own name.

* hard wall, method "fire" (keys "cg-dual2", "cg-dual"): the two-level dual CG ("cg-dual2") while
  the contact set holds at most `Settings.dual_contact_limit` of the nodes, then the primal CG
  ("cg"); on a 2+1-D surface, or with `dual_coarse_block = 0`, the dual CG with its band or window
  preconditioner ("cg-dual") in its place; ``hard_wall = "fire"``: projected FIRE; method "verlet":
  projected Verlet.
* a normal-only law with a potential (seed Eq. 3, a user law), method "fire": the NCG, FIRE after a
  stall (``cohesive = "fire"``: FIRE alone); "verlet": Verlet.
* coupled law (seed Eq. 2, no potential), method "fire", ``coupled = "auto"``: "frictionless-first"
  on a body that barely couples u_x and u_z (`gfmd.problem.elastic_coupling` ≤
  `COUPLED_FRICTIONLESS_COUPLING`), else "handover-near". Both start from the better of the step's
  guess and the last state (`relax`'s `previous`) with the continuation Newton–Krylov, kept only as
  a continuation of the ramp's branch; it gives up early (a missed GMRES solve, a jump, a stagnating
  residual, `gfmd.coupled_rules`). On such an event step "frictionless-first" runs the NCG on the
  frictionless reduction (a potential, whose line searches cross the snap) to
  `Settings.coupled_handover`, then Newton from that prediction, kept where it polished it;
  otherwise, and in "handover-near" at once, FIRE to `Settings.coupled_handover`, Newton from the
  state it hands over, kept near it (the equilibrium FIRE was approaching), else FIRE goes on from
  there (through a fold's ghost, `COUPLED_FIRE_CRAWL`); FIRE from where the continuation stalled (a
  jump-in fold); Newton from the guess and from FIRE's end, kept where locally stable; Ψtc, kept
  where locally stable; Verlet. ``coupled = "fire"``: FIRE, then the stability-tested Newton, then
  Verlet (what the verification suite runs as FIRE itself).
* cohesive wall: projected FIRE, or Verlet (method "verlet").

Why the coupled chain: FIRE's restarts test the power f·v, a descent test only for forces f = −∇E;
the coupled law has no potential, and at strongly non-symmetric states (large slip under
compression) FIRE's weakly damped inertia circulates: started at the FE equilibrium of such a state
it drifts away (residual 8e-3 → 0.19 p_ref in 3e4 iterations) while per-mode critically damped
Verlet converges in 410. Deeper in the slip regime Verlet fails the same way: fig8_small (ν = 0.1,
c = 0.5, φn* = 0.15, seed 2, N = 4096) at δ = 20 nm has a static equilibrium (Newton: 8 iterations)
whose eigenvalues of J nearest 0 all have Re λ > 0, but damped inertial dynamics started on it drift
off: the tangent's antisymmetric part (circulatory forces at the slipping, compressed contact edge)
makes the equilibrium a flutter point of second-order dynamics (tests/test_solver_coupled.py).
Newton converges to unstable equilibria as well, hence the acceptance test.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .algorithms import coupled_newton
from .blas import on_one_thread
from .coupled_krylov import balance_residual, better_start
from .coupled_rules import (COUPLED_BETTER_START, COUPLED_CONTINUATION_GMRES_CYCLES,  # read (and patched by the
                            COUPLED_CONTINUATION_ITERATIONS, COUPLED_CONTINUATION_STAGNATION,  # tests) as gfmd.chains
                            COUPLED_FIRE_BUDGET, COUPLED_FIRE_CRAWL, COUPLED_FRICTIONLESS_COUPLING, COUPLED_HANDOVER_MOVE,
                            COUPLED_JUMP, COUPLED_PREDICTION_MOVE, COUPLED_START_MARGIN)
from .coupled_stability import coupled_stability
from .links import ALGORITHMS, MODULES, Accept, Budget, Link, Start, options_for
from .problem import Problem, elastic_coupling, flat_problem, frictionless
from .stopping import finish

_VERLET = (("method", "verlet"),)
_GIVE_UP = (("coupled_gmres_give_up", True),)  # Newton stops at a missed GMRES solve
#: the continuation Newton: stops at a GMRES solve missed within COUPLED_CONTINUATION_GMRES_CYCLES, once an iterate
#: moved COUPLED_JUMP law lengths, once its residual stagnates (COUPLED_CONTINUATION_STAGNATION) and after
#: COUPLED_CONTINUATION_ITERATIONS iterations; its state kept only as a continuation of the ramp's branch
_CONTINUATION = Link("coupled_newton", accept=Accept.CONTINUATION,
                     options=_GIVE_UP + (("coupled_continuation_jump", COUPLED_JUMP),
                                         ("coupled_continuation_iterations", COUPLED_CONTINUATION_ITERATIONS),
                                         ("coupled_continuation_gmres_cycles", COUPLED_CONTINUATION_GMRES_CYCLES),
                                         ("coupled_continuation_stagnation", COUPLED_CONTINUATION_STAGNATION)))
#: Newton from the guess, then from where the link before stopped, kept only where locally stable
_STABLE_NEWTON = Link("coupled_newton", starts=(Start.GUESS, Start.FINITE_END), accept=Accept.LOCALLY_STABLE)
_LAST_VERLET = Link("dynamics", options=_VERLET, budget=Budget.REST)
#: the coupled chains' last resort before damped Verlet: Ψtc, kept only where locally stable (deep in the slip
#: regime FIRE's dynamics circulate and Newton's line search stalls: Fig. 8 at 2^17, ν = 0.1, seed 7, step 199: Ψtc
#: converged in 24 iterations, 1 672 FFT pairs, ≈ 3.4 min with its stability test; Verlet: 58 min, not converged)
_LAST_RESORT = (Link("coupled_ptc", accept=Accept.LOCALLY_STABLE), _LAST_VERLET)
#: FIRE to the handover residual, Newton from there (kept near FIRE's state: the same equilibrium), else FIRE goes on
#: from its handover state (up to COUPLED_FIRE_CRAWL in all); FIRE from where the continuation stalled (a fold); then
#: the stability-tested Newton, Ψtc and Verlet
_HANDOVER_NEAR = (Link("dynamics", budget=Budget.COUPLED_FIRE, handover=True),
                  Link("coupled_newton", options=_GIVE_UP, starts=(Start.HANDOVER,), accept=Accept.NEAR), Link("dynamics", starts=(Start.HANDOVER,), budget=Budget.COUPLED_CRAWL),
                  Link("dynamics", starts=(Start.STALLED_END,), budget=Budget.COUPLED_FIRE), _STABLE_NEWTON,
                  *_LAST_RESORT)
_FIRE = (Link("dynamics"),)
#: {(law kind, key): chain}: the law kinds of `gfmd.problem.Problem.kind`, the keys of `chain_key`: the label of the
#: chain's first algorithm, or for the coupled law's Newton-first chains the chain's own name
CHAINS = {
    ("hard-wall", "cg-dual2"): (Link("hard_wall_two_level_cg"),
                                Link("hard_wall_primal_cg", starts=(Start.END,), budget=Budget.LEFT)),
    ("hard-wall", "cg-dual"): (Link("hard_wall_dual_cg"),
                               Link("hard_wall_primal_cg", starts=(Start.END,), budget=Budget.LEFT)),
    ("hard-wall", "fire"): (Link("hard_wall_dynamics"),),
    ("hard-wall", "verlet"): (Link("hard_wall_dynamics"),),
    ("cohesive", "ncg"): (Link("ncg"), Link("dynamics", budget=Budget.REST)),
    ("cohesive", "fire"): _FIRE,
    ("cohesive", "verlet"): _FIRE,
    ("coupled", "fire"): (Link("dynamics", budget=Budget.COUPLED_FIRE), _STABLE_NEWTON, _LAST_VERLET),
    ("coupled", "handover-near"): (_CONTINUATION, *_HANDOVER_NEAR),
    # the frictionless reduction's NCG through the event (its energy minimum, u_x of the guess), Newton from there kept
    # where it polished that prediction; else on as "handover-near"
    ("coupled", "frictionless-first"): (_CONTINUATION, Link("ncg", frictionless=True, handover=True),
                                        Link("coupled_newton", options=_GIVE_UP, starts=(Start.HANDOVER,),
                                             accept=Accept.PREDICTED), *_HANDOVER_NEAR),
    ("coupled", "verlet"): _FIRE,
    ("cohesive-wall", "fire"): (Link("cohesive_wall"),),
    ("cohesive-wall", "verlet"): (Link("cohesive_wall"),),
}

#: the algorithms' labels (`Relaxed.method`) in words, for messages and reports
WORDS = {"cg-dual2": "the two-level dual CG", "cg-dual": "the dual CG", "cg": "the primal CG", "ncg": "NCG",
         "fire": "FIRE", "verlet": "damped Verlet", "newton": "Newton–Krylov", "ptc": "pseudo-transient continuation",
         "ncg-frictionless": "NCG on the frictionless reduction"}
#: Settings.coupled's chains (`chain_key`)
COUPLED_KEYS = ("auto", "fire", "handover-near", "frictionless-first")


#: why a 2+1-D surface is normal-only (`refuse_tangential_surface`)
SURFACE_NORMAL_ONLY = (
    "2+1-D surfaces are normal-only in GFMD: the coupled law (seed Eq. 2, tangential unknowns u_x) would need "
    "the 3×3 kernel of the 2-D wavevector, which is not built (the seed finds friction and compressibility "
    "negligible); use interface.tangential_ratio = 0 and solver.unknowns = \"auto\" (or a profile, "
    "surface.nodes_y = 0)")


def refuse_tangential_surface(model):
    """ValueError (`SURFACE_NORMAL_ONLY`) for a 2+1-D model with tangential unknowns."""
    if len(model.grid) > 1 and model.tangential:
        raise ValueError(SURFACE_NORMAL_ONLY)


def chain_key(problem, settings):
    """(law kind, key) of `CHAINS` for this problem and settings; ValueError naming a bad Settings field
    (or a tangential 2+1-D model: `refuse_tangential_surface`)."""
    refuse_tangential_surface(problem.model)
    kind = problem.kind
    if kind == "cohesive-wall":
        return kind, "verlet" if settings.method == "verlet" else "fire"
    if kind == "hard-wall":
        if settings.method == "fire" and settings.hard_wall == "cg":
            if not 0.0 < settings.dual_contact_limit <= 1.0:
                raise ValueError(f"Settings.dual_contact_limit = {settings.dual_contact_limit!r}: expected a fraction "
                                 "of the nodes in (0, 1] (the primal CG alone: relax's chain (Link('hard_wall_primal_cg'),))")
            if not (isinstance(settings.dual_coarse_block, (int, np.integer)) and settings.dual_coarse_block >= 0):
                raise ValueError(f"Settings.dual_coarse_block = {settings.dual_coarse_block!r}: expected a whole "
                                 "number of nodes ≥ 0 (0: the dual CG with the band preconditioner alone)")
            # the two-level coarse blocks are runs of consecutive nodes of a profile; a 2+1-D surface
            # keeps the dual CG with its periodic window preconditioner (`hard_wall_dual_cg`)
            return kind, "cg-dual2" if settings.dual_coarse_block > 0 and not problem.surface else "cg-dual"
        if settings.hard_wall not in ("cg", "fire"):
            raise ValueError(f"Settings.hard_wall = {settings.hard_wall!r}: expected 'cg' or 'fire'")
        return kind, "verlet" if settings.method == "verlet" else "fire"
    if kind == "coupled":
        if settings.method == "fire" and settings.coupled not in COUPLED_KEYS:
            raise ValueError(f"Settings.coupled = {settings.coupled!r}: expected one of {', '.join(COUPLED_KEYS)}")
        if settings.method != "fire":
            return kind, "verlet"
        key = settings.coupled
        if key == "auto":  # the frictionless predictor where the body barely couples u_x and u_z
            weak = elastic_coupling(problem.model) <= COUPLED_FRICTIONLESS_COUPLING
            key = "frictionless-first" if weak else "handover-near"
        if key in ("handover-near", "frictionless-first"):
            h = settings.coupled_handover
            if not (isinstance(h, (float, int)) and settings.tolerance < h < 1.0):
                raise ValueError(f"Settings.coupled_handover = {h!r}: expected a residual (× p_ref) between "
                                 f"Settings.tolerance = {settings.tolerance:g} and 1")
        return kind, key
    if settings.method == "fire" and settings.cohesive not in ("ncg", "fire"):
        raise ValueError(f"Settings.cohesive = {settings.cohesive!r}: expected 'ncg' or 'fire'")
    if settings.method == "fire" and settings.cohesive == "ncg" and problem.law.law.has_potential:
        return kind, "ncg"
    return kind, "verlet" if settings.method == "verlet" else "fire"


def labels(key, settings):
    """The `Relaxed.method` labels of the chain `CHAINS[key]`'s algorithms in order, e.g. ("ncg", "fire")."""
    return tuple(_label(link, settings) for link in CHAINS[key])


def _label(link, settings):
    """The link's label: its module's `LABEL`, or for the dynamics the integrator ("fire" or "verlet")."""
    label = getattr(MODULES[link.algorithm], "LABEL", None) or (
        "verlet" if dict(link.options).get("method", settings.method) == "verlet" else "fire")
    return label + ("-frictionless" if link.frictionless else "")


def describe(key, settings):
    """The chain in words: "ncg (then fire where it stalls)"."""
    first, *rest = labels(key, settings)
    return first + (f" (then {' → '.join(rest)} where it stalls)" if rest else "")


def _budget(link, settings, used, handover_used=0):
    """The link's iterations, `used` by the links before it, `handover_used` by the last handover link."""
    if link.budget is Budget.ALL:
        return settings.max_iterations
    if link.budget is Budget.COUPLED_FIRE:
        return min(COUPLED_FIRE_BUDGET, settings.max_iterations // 2)
    if link.budget is Budget.COUPLED_CRAWL:  # with the handover link's iterations
        return max(min(COUPLED_FIRE_CRAWL, settings.max_iterations // 2) - handover_used, 1)
    left = settings.max_iterations - used
    return left if link.budget is Budget.LEFT else max(left, 1)


def _move(problem, r, origin):
    """The largest nodal move from `origin` to r's state, in law lengths (min(δn, δt))."""
    return float(np.max(np.abs(problem.displacements(r.u_hat - origin)))) / problem.law.law.length_scale


def _stall_point(problem, link, before, settings):
    """(the state where `link`, the chain's first link, stalled (its result `before`): not converged, at a finite
    residual, or None; the resumed run or None). A continuation Newton that broke off where an iterate jumped,
    its residual stagnated or a GMRES solve missed within the continuation's cycles (`coupled_newton.BROKE_OFF`) is
    first resumed from there without the break-off and with all GMRES cycles, to where its line search stalls: the
    state the whole run would have stopped at (its iterates depend on the state alone, but for Eisenstat–Walker's
    first forcing term), which FIRE needs at a jump-in fold (Fig. 8 at 2^17, seed 2, step 176); a resumed run that
    converges reached another equilibrium, never a start."""
    if before is None or before.converged or not np.isfinite(before.residual):
        return None, None
    if coupled_newton.BROKE_OFF not in before.stalled:
        return before, None
    options = dict(link.options)
    limit = options.get("coupled_continuation_iterations") or coupled_newton.COUPLED_NEWTON_ITERATIONS
    run = replace(settings, **{**options, "coupled_continuation_jump": 0.0,  # the whole run's iterations left
                               "coupled_continuation_gmres_cycles": 0,  # and its GMRES cycles
                               "coupled_continuation_stagnation": 0.0,  # without the stagnation test
                               "coupled_continuation_iterations": max(limit - before.iterations, 1)})
    resumed = ALGORITHMS[link.algorithm](problem, before.u_hat, options_for(link.algorithm, run))
    stop = None if resumed.converged or not np.isfinite(resumed.residual) else resumed
    return stop, resumed


def _progressed(problem, end, origin, count_pairs):
    """Whether a run's end state is a start (`Start.FINITE_END`): its residual finite and below that of the state it
    started from (a FIRE run that blew up, Fig. 8 at 2^17, seed 7, step 199: 0.21 → 2.3e7 p_ref, is none; Newton
    from there ran 47 iterations, 131 s, to 2.1e3 p_ref). The start's residual costs one FFT pair, counted."""
    if not np.isfinite(end.residual):
        return False
    start, pairs = balance_residual(problem.model, problem.law, problem.z_ind, origin)
    count_pairs(pairs)
    return end.residual < start


def _rejected(problem, link, r, origin, handed=Start.HANDOVER.words):
    """Why a converged state fails the link's acceptance test ("" if it passes); handed: the handover state in words."""
    if link.accept is Accept.CONTINUATION:  # kept only where no node moved COUPLED_JUMP law lengths from the start
        move = _move(problem, r, origin)
        return (f"a node moved {move:.3g} law lengths from the step's start (a snap or slip event: left to the "
                "chain that tests stability)") if move >= COUPLED_JUMP else ""
    if link.accept is Accept.PREDICTED:  # Newton polished the predicted state, it did not leave it for another
        move = _move(problem, r, origin)
        return (f"a node moved {move:.3g} law lengths from the frictionless prediction (another equilibrium), "
                "rejected") if move >= COUPLED_PREDICTION_MOVE else ""
    if link.accept is Accept.NEAR:  # the equilibrium the handover state was approaching, not another one
        move = _move(problem, r, origin)
        if move >= COUPLED_HANDOVER_MOVE:
            return f"a node moved {move:.3g} law lengths from {handed} (another equilibrium), rejected"
    if not link.accept.stability:
        return ""
    lowest = coupled_stability(problem.model, problem.law, problem.z_ind, r.u_hat)
    if lowest is not None and lowest <= 0.0:  # not the state damped dynamics would settle in
        return (f"reached an equilibrium that is not locally stable (an eigenvalue of the tangent with Re λ = "
                f"{lowest / problem.law.k_int_z:.3g} φn/δn²: a slip or snap-through instability), rejected")
    return ""


@on_one_thread
def relax(model, law, z_ind, u_hat, settings, wall_tolerance=0.0, previous=None, chain=None):
    """Relax one load step from the initial guess `u_hat` (c, N//2+1) along its chain; returns `Relaxed`.

    z_ind: indenter surface z_ind(x) (m) at this step; wall_tolerance (m): gap below which a wall node
    counts as touching the wall. iterations and fft_pairs add up every algorithm that ran. previous: the last
    converged state where `u_hat` was extrapolated from it; the coupled chains start from it where the guess's force
    residual is more than COUPLED_START_MARGIN times its own (COUPLED_BETTER_START; the message then says so).
    2+1-D surface (model.shape (Nx, Ny)): u_hat (c, Nx, Ny//2+1), z_ind (Nx, Ny); the algorithms run on the
    flat view (`gfmd.problem.flat_problem`) and the result's spectra and fields come back on the grid.
    Runs with one BLAS thread (`gfmd.blas.one_thread`). chain: a tuple of `Link`s walked in place of the table's
    (a test's or benchmark's own, e.g. the primal CG alone); the settings are checked as for the table's.
    """
    problem = Problem(model, law, z_ind, wall_tolerance)
    key = chain_key(problem, settings)
    if chain is not None and not (isinstance(chain, tuple) and chain and all(isinstance(k, Link) for k in chain)):
        raise ValueError(f"chain = {chain!r}: expected a non-empty tuple of gfmd.links.Link")
    chain = CHAINS[key] if chain is None else chain
    if problem.surface:
        _check_surface_shapes(model, z_ind, u_hat)
        flat = flat_problem(problem)
        result = _relax(flat, chain, np.reshape(u_hat, (u_hat.shape[0], -1)), settings)
        return _on_grid(result, model)
    if previous is None or not COUPLED_BETTER_START or problem.kind != "coupled":
        return _relax(problem, chain, u_hat, settings)
    start, residuals, pairs, state = better_start(problem, u_hat, previous, COUPLED_START_MARGIN)
    result = _relax(replace(problem, start_state=(start, state)) if state is not None else problem, chain, start,
                    settings)
    result.fft_pairs += pairs
    if start is previous:
        note = (f"started from the last state (force residual {residuals[1]:.3g} p_ref; the extrapolated guess's "
                f"{residuals[0]:.3g})")
        result.message = note + (f"; {result.message}" if result.message else "")
    return result


def _check_surface_shapes(model, z_ind, u_hat):
    """ValueError naming the array whose shape does not fit a 2+1-D model's grid."""
    if np.shape(z_ind) != model.grid:
        raise ValueError(f"z_ind has shape {np.shape(z_ind)}: the surface model needs its grid (Nx, Ny) = {model.grid}")
    expected = (model.components,) + model.spectrum_shape
    if np.shape(u_hat) != expected:
        raise ValueError(f"u_hat has shape {np.shape(u_hat)}: the surface model's state is (components, Nx, Ny//2+1) "
                         f"= {expected}")


def _on_grid(result, model):
    """A flat 2+1-D `Relaxed` with its spectra (c, Nx, Ny//2+1) and fields (Nx, Ny) on the grid."""
    result.u_hat = result.u_hat.reshape((result.u_hat.shape[0],) + model.spectrum_shape)
    for name in ("u_z", "u_x", "gap", "t_z", "t_x"):
        value = getattr(result, name)
        if value is not None:
            setattr(result, name, np.reshape(value, model.grid))
    return result


def _run(problem, link, origin, settings):
    """The link's algorithm from `origin`; a frictionless link's on `gfmd.problem.frictionless`'s reduction, its u_z
    with origin's u_x returned as the coupled state."""
    options = options_for(link.algorithm, settings)
    if not link.frictionless:
        return ALGORITHMS[link.algorithm](problem, origin, options)
    r = ALGORITHMS[link.algorithm](frictionless(problem), origin[-1:], options)
    r.u_hat = np.concatenate([origin[:-1], r.u_hat[-1:]])
    r.method += "-frictionless"
    return r


@dataclass
class _Walk:
    """What the walk along a chain carries from link to link."""

    problem: Problem
    chain: tuple
    guess: np.ndarray  # the step's guess (Start.GUESS)
    settings: object
    used: int = 0  # the iterations of every run
    pairs: float = 0.0  # and their FFT pairs
    names: list = field(default_factory=list)  # the labels that ran, in order
    notes: list = field(default_factory=list)  # why runs were not kept
    run: object = None  # the last run and the state it started from
    origin: object = None
    before: object = None  # the link before's last run (Start.END) and the state it started from
    before_origin: object = None
    first: object = None  # the first link's last run
    stall: tuple = None  # (where the first link stalled, or None,): Start.STALLED_END, found once per step
    handed: object = None  # the run of the last handover link that reached its residual (Start.HANDOVER)
    handover_used: int = 0  # its iterations
    handed_words: str = Start.HANDOVER.words  # its state in words

    def count(self, r):
        """Every run adds its iterations, FFT pairs and label."""
        self.used += r.iterations
        self.pairs += r.fft_pairs
        if r.method and (not self.names or self.names[-1] != r.method):
            self.names.append(r.method)

    def count_pairs(self, more):
        self.pairs += more


def _relax(problem, chain, u_hat, settings):
    """`relax` along `chain` on a 1+1-D problem or a surface's flat view."""
    walk = _Walk(problem, chain, u_hat, settings)
    for i, link in enumerate(chain):
        result = _walk_link(walk, i, link)
        if result is not None:
            return _answer(walk, result)
        walk.before, walk.before_origin = walk.run, walk.origin
        if i == 0:
            walk.first = walk.run
    walk.run.converged = False  # every link stalled or was rejected: the last state is the answer, not converged
    return _answer(walk, walk.run)


def _walk_link(walk, i, link):
    """The chain's i-th link from its starts in turn: the run kept (the step's answer), or None (on to the next)."""
    run = _link_settings(link, walk.settings, walk.used, walk.handover_used)
    if link.handover:  # a later Start.HANDOVER starts from this link's state or not at all
        walk.handed = None
    for start in link.starts:
        origin = _origin(walk, start)
        if origin is None:
            continue
        r = _run(walk.problem, link, origin, run)
        walk.count(r)
        walk.run, walk.origin = r, origin
        label = WORDS.get(r.method) or WORDS.get(_label(link, run), link.algorithm)
        if link.handover and r.converged:  # the looser residual: handed on, not the answer
            walk.handed, walk.handover_used, walk.handed_words = r, r.iterations, _handed_words(link)
            walk.notes.append(f"{label} handed over at residual {r.residual:.3g} p_ref")
            return None
        why = _rejected(walk.problem, link, r, origin, walk.handed_words) if r.converged else ""
        if r.converged and not why or not r.converged and (i == len(walk.chain) - 1 or not r.stalled):
            return r
        words = walk.handed_words if start is Start.HANDOVER else start.words
        where = "" if start is Start.GUESS or i == 0 else f" from {words}"
        walk.notes.append(f"{label}{where} stopped ({why or r.stalled})")
    return None


def _link_settings(link, settings, used, handover_used):
    """The Settings the link's algorithm runs with: its options, its budget, a handover link's residual."""
    options = dict(link.options)
    budget = _budget(link, settings, used, handover_used)
    if budget != settings.max_iterations:
        options["max_iterations"] = budget
    if link.handover:
        options["tolerance"] = settings.coupled_handover
    return replace(settings, **options) if options else settings


def _origin(walk, start):
    """The state `start` names, or None where it names none (the start is skipped)."""
    if start is Start.GUESS:
        return walk.guess
    if start is Start.HANDOVER:
        return None if walk.handed is None else walk.handed.u_hat
    if start is Start.STALLED_END:  # a fold's neighbourhood, where Newton stalled: FIRE carries the snap
        if walk.stall is None:
            walk.stall = (_stalled_end(walk),)
        return None if walk.stall[0] is None else walk.stall[0].u_hat
    if start is Start.END or _progressed(walk.problem, walk.before, walk.before_origin, walk.count_pairs):
        return walk.before.u_hat
    return None


def _stalled_end(walk):
    """Where the chain's first link stalled (`_stall_point`), or None; its resumed run counts and is noted."""
    stop, resumed = _stall_point(walk.problem, walk.chain[0], walk.first, walk.settings)
    if resumed is not None:
        walk.count(resumed)
        walk.notes.append(f"{WORDS[resumed.method]} resumed without the break-off "
                          f"({resumed.stalled or 'converged: another equilibrium, not a start'})")
    if stop is not None and np.array_equal(stop.u_hat, walk.guess):  # e.g. GMRES missed at iteration 1
        walk.notes.append("the continuation stalled at the guess, where FIRE ran already: not run again")
        stop = None
    return stop


def _handed_words(link):
    """A handover link's state in words."""
    return "the frictionless prediction" if link.frictionless else Start.HANDOVER.words


def _answer(walk, result):
    """The step's `Relaxed`: `result` with its fields, every run's iterations and FFT pairs, the labels that ran and
    why the runs before it were not kept."""
    if result.u_z is None:  # a stall has no fields yet
        result = finish(walk.problem, result.u_hat, result.iterations, result.residual, False, result.stalled)
    if walk.notes:
        result.message = "; ".join(walk.notes) + f"; restarted with {WORDS.get(walk.names[-1], walk.names[-1])}: " + (
            result.message or "converged")
    result.iterations, result.fft_pairs = walk.used, walk.pairs
    result.method, result.stalled = "→".join(walk.names), ""
    return result
