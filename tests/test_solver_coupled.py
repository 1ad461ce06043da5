"""The coupled-law (seed Eq. 2) solver path: FIRE, Newton–Krylov fallback, Verlet (gfmd.solver).

The case is the step that failed in `studies/seed/fig8_small.toml` (ν = 0.1, c = 0.5, δt = 1 nm,
φn* = 0.15, surface seed 2, N = 4096): the last load step, δ = 20 nm, deep in the slip regime
(~250 compressed nodes slipping > 2 δt, min Δn ≈ −12 δn). Before the Newton–Krylov fallback FIRE
stalled (2 000 iterations, residual 1.8–8.5 p_ref) and damped Verlet stopped at max_iterations
(198 000, residual 0.04 p_ref), twice (from the extrapolated guess and from the last state).

* the step converges, through "fire→newton", in a few Newton iterations after FIRE's budget;
* the diagnosis, pinned: the step has a static equilibrium, and damped inertial dynamics started
  on it (residual < 1e-8 p_ref) drift away: Verlet grows the residual by orders of magnitude in
  1e4 iterations. The law's non-symmetric tangent makes the equilibrium a flutter point of the
  second-order dynamics, although the eigenvalues of J nearest 0 have Re λ > 0 (no mass or
  damping of the diagonal modes fixes that; a method without dynamics does);
* Newton alone reproduces the state FIRE converged to at the step before (the same equilibrium
  where both converge), and is a fixed point at a converged state (0 iterations);
* a Newton run that cannot converge is reported (converged False, a message), never accepted.
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.core.loading import indenter_surface, realization_steps
from gfmd_contact.core.scene import load_scene
from gfmd import chains, coupled_preconditioner, solver as gs
from gfmd.algorithms import coupled_newton, dynamics
from gfmd.coupled_krylov import FORCING, FORCING_MIN, eisenstat_walker, forcing
from gfmd.loading import prepare, run_realization
from gfmd.coupled_stability import coupled_stability
from gfmd.problem import Problem
from gfmd.stopping import finish

BASE = Path(__file__).resolve().parents[1] / "studies" / "seed" / "fig3_small_base.toml"


class _Stop(Exception):
    pass


@pytest.fixture(scope="module")
def fig8_step():
    """The fig8_small task (ν = 0.1, c = 0.5, seed 2): cell, states after steps 98 and 99, z_ind of 99 and 100."""
    scene = load_scene(BASE).replace(**{"material.poisson_ratio": 0.1, "interface.tangential_ratio": 0.5,
                                        "interface.length_tangential": 1e-9, "interface.phi_n_star": 0.15,
                                        "surface.seed": 2, "surface.realizations": 1})
    saved = {}

    def checkpoint(result, state):
        if state.step == 99:
            assert all(result.curve["converged"]), "the ramp failed before its last step"
            saved.update(current=state.current.copy(), previous=state.previous.copy())
            raise _Stop

    with pytest.raises(_Stop):
        run_realization(scene, 0, checkpoint=checkpoint)
    from gfmd_contact.core import surfaces
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h, 0)
    steps, _ = realization_steps(scene, h, 0)
    z = [indenter_surface(h, scene.loading.initial_separation, steps[k]) for k in (99, 100)]
    return cell, saved["previous"], saved["current"], z


def test_fig8_last_step_converges(fig8_step):
    cell, previous, current, (_, z100) = fig8_step
    guess = 2 * current - previous  # the ramp's extrapolated warm start
    r = gs.relax(cell.physics, cell.law, z100, guess, cell.settings)
    assert r.converged, r.message
    assert r.residual < cell.settings.tolerance
    assert r.method in ("newton", "newton→fire→newton"), r.method
    assert r.iterations < chains.COUPLED_FIRE_BUDGET + 2 * coupled_newton.COUPLED_NEWTON_ITERATIONS
    old = gs.relax(cell.physics, cell.law, z100, guess, replace(cell.settings, coupled="fire"))  # the chain before
    assert old.converged and old.method in ("fire", "fire→newton"), old.method
    # the slip regime the step is in (what makes the dynamics fail)
    dt, dn = cell.scene.interface.length_tangential, cell.scene.interface.length_normal
    assert np.max(np.abs(r.u_x)) > 3 * dt and np.min(r.gap) < -5 * dn


def test_fig8_last_step_is_a_flutter_point_of_damped_dynamics(fig8_step):
    cell, previous, current, (_, z100) = fig8_step
    eq = coupled_newton.solve(Problem(cell.physics, cell.law, z100), 2 * current - previous, cell.settings)
    assert eq.converged and eq.iterations <= 20, eq.message
    drift = dynamics.solve(Problem(cell.physics, cell.law, z100), eq.u_hat,
                            replace(cell.settings, method="verlet", max_iterations=10_000, tolerance=0.0))
    assert drift.residual > 1e3 * cell.settings.tolerance, (
        f"Verlet stayed at the equilibrium (residual {drift.residual:.3g} p_ref): the flutter diagnosis no longer holds")


def test_newton_agrees_with_fire_and_is_a_fixed_point(fig8_step):
    cell, previous, current, (z99, _) = fig8_step
    s = cell.settings
    r = coupled_newton.solve(Problem(cell.physics, cell.law, z99), previous, s)
    assert r.converged, r.message
    fire = finish(Problem(cell.physics, cell.law, z99), current, 0, 0.0, True, "")
    # two states with max nodal residual < tol·p_ref: K(q_1)-bound as in test_solver_ncg, loose factor
    m = cell.physics
    k1 = min(abs(m.k_xx[1]), abs(m.k_zz[1])) - abs(m.k_xz[1])
    bound = 2 * s.tolerance * m.reference_traction * np.sqrt(m.nodes) / k1
    for a, b in ((r.u_z, fire.u_z), (r.u_x, fire.u_x)):
        assert np.max(np.abs(a - b)) < 10 * bound + 1e-6 * cell.scene.interface.length_normal
    again = coupled_newton.solve(Problem(cell.physics, cell.law, z99), r.u_hat, s)
    assert again.converged and again.iterations == 0


def test_newton_failure_is_reported(fig8_step, monkeypatch):
    cell, _previous, current, (_, z100) = fig8_step
    monkeypatch.setattr(coupled_newton, "COUPLED_NEWTON_ITERATIONS", 1)
    r = coupled_newton.solve(Problem(cell.physics, cell.law, z100), current, cell.settings)
    assert not r.converged and "Newton" in r.message and r.residual > cell.settings.tolerance


def test_newton_equilibrium_is_locally_stable(fig8_step):
    """The accepted state passes the FE reference's test on the eigenvalues nearest 0 (measured 0.030 φn/δn²)."""
    cell, previous, current, (_, z100) = fig8_step
    eq = coupled_newton.solve(Problem(cell.physics, cell.law, z100), 2 * current - previous, cell.settings)
    lowest = coupled_stability(cell.physics, cell.law, z100, eq.u_hat)
    assert lowest is not None and 0.01 < lowest / cell.law.k_int_z < 0.1


def test_stability_solvers_agree(fig8_step, monkeypatch):
    """The stability test's solves by the Newton's two-level GMRES (the default) and by scipy's GMRES under M⁻¹ (the
    earlier test) give the same lowest Re λ, within ARPACK's requested relative tolerance (1e-4); an
    unknown solver is refused by name."""
    from gfmd import coupled_stability as stability

    cell, previous, current, (_, z100) = fig8_step
    eq = coupled_newton.solve(Problem(cell.physics, cell.law, z100), 2 * current - previous, cell.settings)
    got = {}
    for solver in ("newton", "scipy"):
        monkeypatch.setattr(stability, "SOLVER", solver)
        got[solver] = coupled_stability(cell.physics, cell.law, z100, eq.u_hat)
    assert abs(got["newton"] - got["scipy"]) <= 1e-4 * abs(got["scipy"])
    monkeypatch.setattr(stability, "SOLVER", "lanczos")
    with pytest.raises(ValueError, match="SOLVER = 'lanczos'"):
        coupled_stability(cell.physics, cell.law, z100, eq.u_hat)


def test_unstable_newton_equilibrium_is_rejected(fig8_step, monkeypatch):
    """A Newton state that fails the stability test is not accepted: the step goes on to Verlet, says why."""
    cell, previous, current, (_, z100) = fig8_step
    monkeypatch.setattr(chains, "coupled_stability", lambda *a: -1.0 * cell.law.k_int_z)
    s = replace(cell.settings, max_iterations=4000, coupled="fire")
    r = gs.relax(cell.physics, cell.law, z100, 2 * current - previous, s)
    assert not r.converged and r.method == "fire→newton→verlet"
    assert "not locally stable" in r.message and "Verlet" in r.message


def test_newton_first_keeps_only_a_continuation(fig8_step, monkeypatch):
    """The Newton-first chain (Settings.coupled = "newton", the default) keeps Newton's state where no node moved
    COUPLED_JUMP law lengths from the step's start (step 99 from step 98's state); a larger move hands the step to
    the FIRE chain, whose Newton is stability-tested."""
    cell, previous, current, (z99, _) = fig8_step
    r = gs.relax(cell.physics, cell.law, z99, previous, cell.settings)
    move = np.max(np.abs(np.stack([r.u_x, r.u_z]) - np.fft.irfft(previous, n=cell.physics.nodes)))
    assert r.converged and r.method == "newton", (r.method, r.message)
    assert move < chains.COUPLED_JUMP * cell.law.law.length_scale
    monkeypatch.setattr(chains, "COUPLED_JUMP", 0.5 * move / cell.law.law.length_scale)  # now it "jumped"
    tested = []
    monkeypatch.setattr(chains, "coupled_stability", lambda *a: tested.append(1) or cell.law.k_int_z)
    jumped = gs.relax(cell.physics, cell.law, z99, previous, cell.settings)
    assert jumped.converged and jumped.method.startswith("newton→fire"), jumped.method
    assert "snap or slip event" in jumped.message
    assert tested or jumped.method == "newton→fire"  # a Newton state after FIRE was stability-tested


def test_continuation_gives_up_at_a_missed_gmres_solve(fig8_step, monkeypatch):
    """`coupled_newton.solve` with Settings.coupled_gmres_give_up (the Newton-first chain's first link) stops at
    the first GMRES solve that misses its tolerance; without it (the FIRE chain's fallback Newton) it goes on with
    the inexact direction. GMRES is starved here (one restart of one product) to make it miss on a step whose
    Newton otherwise converges."""
    cell, previous, _current, (z99, _) = fig8_step
    problem = Problem(cell.physics, cell.law, z99)
    monkeypatch.setattr(coupled_newton, "COUPLED_GMRES_RESTART", 1)
    monkeypatch.setattr(coupled_newton, "COUPLED_GMRES_CYCLES", 1)
    cont = coupled_newton.solve(problem, previous, replace(cell.settings, coupled_gmres_give_up=True))
    assert not cont.converged and cont.iterations == 1 and "GMRES missed" in cont.stalled, cont.message
    plain = coupled_newton.solve(problem, previous, cell.settings)
    assert plain.iterations > 1 and "GMRES" not in plain.message, plain.message


def test_continuation_breaks_off_where_an_iterate_jumps(fig8_step, monkeypatch):
    """`coupled_newton.solve` with Settings.coupled_continuation_jump (the Newton-first chain's first link: the
    continuation's COUPLED_JUMP) gives the step up as soon as an unconverged iterate has moved a node that many law
    lengths from the start, the move the continuation's acceptance test would reject; 0 never breaks off (and
    Settings.coupled_continuation_iterations caps its iterations: the continuation's cap). Step 99
    from step 98's state moves its nodes less than a law length; a break-off at a tenth of its largest first-
    iteration move must stop at the first iterate it tests, JUMP_FROM_ITERATION (the first may overshoot)."""
    cell, previous, _current, (z99, _) = fig8_step
    problem = Problem(cell.physics, cell.law, z99)
    length = cell.law.law.length_scale
    plain = coupled_newton.solve(problem, previous, cell.settings)
    assert plain.converged and plain.iterations > 1, plain.message
    whole = coupled_newton.solve(problem, previous, replace(cell.settings, coupled_continuation_jump=chains.COUPLED_JUMP))
    assert whole.converged and whole.iterations == plain.iterations  # a continuation: no break-off
    with monkeypatch.context() as m:
        m.setattr(coupled_newton, "COUPLED_NEWTON_ITERATIONS", 1)
        first = coupled_newton.solve(problem, previous, cell.settings)
    moved = np.max(np.abs(problem.displacements(first.u_hat - previous))) / length
    cut = coupled_newton.solve(problem, previous, replace(cell.settings, coupled_continuation_jump=0.1 * moved))
    assert not cut.converged and "law lengths from the start" in cut.stalled, cut.message
    assert cut.iterations == coupled_newton.JUMP_FROM_ITERATION == 2
    assert dict(chains._CONTINUATION.options)["coupled_continuation_jump"] == chains.COUPLED_JUMP
    capped = coupled_newton.solve(problem, previous, replace(cell.settings, coupled_continuation_iterations=1))
    assert not capped.converged and capped.iterations == 1 and "after 1 Newton iterations" in capped.stalled
    assert dict(chains._CONTINUATION.options)["coupled_continuation_iterations"] == chains.COUPLED_CONTINUATION_ITERATIONS


def test_continuation_breaks_off_where_its_residual_stagnates(fig8_step, monkeypatch):
    """Settings.coupled_continuation_stagnation (the continuation's COUPLED_CONTINUATION_STAGNATION) gives the step up
    once two Newton iterations in a row each left more than that fraction of the residual before them, as a
    break-off (BROKE_OFF: the chain resumes it without the test where it needs the stall); 0 never does. Step 99
    converges with it; with every Newton step capped at 0.01 law lengths each iteration removes a sliver of the
    residual, and the test stops at iteration 2, where without it Newton crawls on to its cap."""
    cell, previous, _current, (z99, _) = fig8_step
    problem = Problem(cell.physics, cell.law, z99)
    threshold = chains.COUPLED_CONTINUATION_STAGNATION
    assert dict(chains._CONTINUATION.options)["coupled_continuation_stagnation"] == threshold and 0 < threshold < 1
    plain = coupled_newton.solve(problem, previous, cell.settings)
    tested = coupled_newton.solve(problem, previous, replace(cell.settings, coupled_continuation_stagnation=threshold))
    assert plain.converged and tested.converged and tested.iterations == plain.iterations, tested.message
    assert np.array_equal(tested.u_hat, plain.u_hat)
    monkeypatch.setattr(coupled_newton, "COUPLED_NEWTON_MAX_MOVE", 1e-2)
    crawl = replace(cell.settings, coupled_continuation_iterations=5)
    on = coupled_newton.solve(problem, previous, replace(crawl, coupled_continuation_stagnation=threshold))
    assert not on.converged and on.iterations == 2 and coupled_newton.BROKE_OFF in on.stalled, on.message
    assert "stagnated" in on.message
    off = coupled_newton.solve(problem, previous, crawl)
    assert not off.converged and off.iterations == 5 and "after 5 Newton iterations" in off.message, off.message
    assert off.fft_pairs > on.fft_pairs


def test_coupled_chain_starts_from_the_last_state_where_the_extrapolation_overshoots(fig8_step, monkeypatch):
    """relax(previous=the last state) on the coupled law starts from whichever of the extrapolated guess and the last
    state has the smaller force residual (COUPLED_BETTER_START). The ramp's own extrapolation to step 100 wins: the
    run from it, bit for bit, in at most the two residuals' FFT pairs more (one each; a Newton from the chosen start
    takes its evaluation, `Problem.start_state`, and spends none on it). A guess carried on too far (the last increment ten
    times over, as an extrapolation through a snap carries the snapped nodes into the indenter) loses: the run from
    the last state, bit for bit, its message saying so. Off, the guess always."""
    cell, previous, current, (_, z100) = fig8_step
    s = cell.settings
    good, bad = 2 * current - previous, current + 10 * (current - previous)
    from_good = gs.relax(cell.physics, cell.law, z100, good, s)
    picked = gs.relax(cell.physics, cell.law, z100, good, s, previous=current)
    assert picked.converged and np.array_equal(picked.u_hat, from_good.u_hat)
    assert picked.fft_pairs <= from_good.fft_pairs + 2 and "last state" not in picked.message
    from_last = gs.relax(cell.physics, cell.law, z100, current, s)
    over = gs.relax(cell.physics, cell.law, z100, bad, s, previous=current)
    assert over.converged and np.array_equal(over.u_hat, from_last.u_hat), over.message
    assert over.message.startswith("started from the last state"), over.message
    monkeypatch.setattr(chains, "COUPLED_BETTER_START", False)
    off = gs.relax(cell.physics, cell.law, z100, bad, s, previous=current)
    assert "last state" not in off.message and not np.array_equal(off.u_hat, from_last.u_hat)


def test_newton_forcing_is_eisenstat_walker(fig8_step, monkeypatch):
    """Each GMRES solve of the coupled Newton gets forcing(tolerance, r_k, η_k), η_k by Eisenstat–Walker from the
    residuals r_k, r_k−1 at the solve (η_0 = FORCING, the first solve loose); with the rule off
    (COUPLED_NEWTON_EISENSTAT_WALKER False, the earlier rule) the floor alone, the first solve at
    FORCING_MIN. Both reach the same equilibrium, within the tolerance's bound."""
    cell, previous, _current, (z99, _) = fig8_step
    problem = Problem(cell.physics, cell.law, z99)
    calls, inner = [], coupled_newton.newton_direction

    def spy(model, law, z_ind, u, f, stiff, fft, rtol, *args):
        calls.append((float(np.max(np.abs(f))) / model.reference_traction, rtol))
        return inner(model, law, z_ind, u, f, stiff, fft, rtol, *args)

    monkeypatch.setattr(coupled_newton, "newton_direction", spy)
    tol = cell.settings.tolerance
    ew = coupled_newton.solve(problem, previous, cell.settings)
    assert ew.converged and len(calls) == ew.iterations >= 2, ew.message
    residuals = [r for r, _ in calls]
    expected = [forcing(tol, r, eisenstat_walker(r, residuals[k - 1] if k else None)) for k, r in enumerate(residuals)]
    assert [rtol for _, rtol in calls] == pytest.approx(expected, rel=1e-12)
    assert calls[0][1] == FORCING
    calls.clear()
    monkeypatch.setattr(coupled_newton, "COUPLED_NEWTON_EISENSTAT_WALKER", False)
    floor = coupled_newton.solve(problem, previous, cell.settings)
    assert floor.converged, floor.message
    assert [rtol for _, rtol in calls] == pytest.approx([forcing(tol, r) for r, _ in calls], rel=1e-12)
    assert calls[0][1] == FORCING_MIN
    m = cell.physics
    k1 = min(abs(m.k_xx[1]), abs(m.k_zz[1])) - abs(m.k_xz[1])
    bound = 2 * tol * m.reference_traction * np.sqrt(m.nodes) / k1
    for a, b in ((ew.u_z, floor.u_z), (ew.u_x, floor.u_x)):
        assert np.max(np.abs(a - b)) < 10 * bound + 1e-6 * cell.scene.interface.length_normal


def test_two_level_newton_needs_fewer_products(fig8_step, monkeypatch):
    """The coupled Newton with the two-level preconditioner (`gfmd.coupled_preconditioner`, the default) reaches the
    state it reaches with K⁻¹ alone (step 99 from step 98's state, within the tolerance's bound) in fewer FFT pairs
    (measured: 102.5 against 163)."""
    cell, previous, _current, (z99, _) = fig8_step
    problem = Problem(cell.physics, cell.law, z99)
    runs = {}
    for choice in ("stiffness", "two-level"):
        monkeypatch.setattr(coupled_preconditioner, "CHOICE", choice)
        runs[choice] = coupled_newton.solve(problem, previous, cell.settings)
        assert runs[choice].converged, (choice, runs[choice].message)
    assert runs["two-level"].fft_pairs < 0.8 * runs["stiffness"].fft_pairs, {k: r.fft_pairs for k, r in runs.items()}
    m, tol = cell.physics, cell.settings.tolerance
    k1 = min(abs(m.k_xx[1]), abs(m.k_zz[1])) - abs(m.k_xz[1])
    bound = 2 * tol * m.reference_traction * np.sqrt(m.nodes) / k1  # as in test_newton_forcing_is_eisenstat_walker
    a, b = runs["stiffness"], runs["two-level"]
    for x, y in ((a.u_z, b.u_z), (a.u_x, b.u_x)):
        assert np.max(np.abs(x - y)) < 10 * bound + 1e-6 * cell.scene.interface.length_normal


def test_continuation_gmres_cycles_break_off_a_solve_that_needs_more(fig8_step, monkeypatch):
    """Settings.coupled_continuation_gmres_cycles (the continuation's COUPLED_CONTINUATION_GMRES_CYCLES) gives each
    GMRES solve fewer restart cycles; a solve that misses within them breaks the step off (BROKE_OFF, so that the
    chain can resume it with all cycles), where all COUPLED_GMRES_CYCLES reach the tolerance and Newton converges.
    Restarts of 8 products at the forcing floor alone (every solve to FORCING_MIN): step 99's first solve needs
    more than one and fewer than five (3 with the two-level preconditioner, `gfmd.coupled_preconditioner`)."""
    cell, previous, _current, (z99, _) = fig8_step
    problem = Problem(cell.physics, cell.law, z99)
    monkeypatch.setattr(coupled_newton, "COUPLED_GMRES_RESTART", 8)
    monkeypatch.setattr(coupled_newton, "COUPLED_NEWTON_EISENSTAT_WALKER", False)
    cont = replace(cell.settings, coupled_gmres_give_up=True)
    whole = coupled_newton.solve(problem, previous, replace(cont, coupled_continuation_gmres_cycles=0))
    assert whole.converged, whole.message
    one = coupled_newton.solve(problem, previous, replace(cont, coupled_continuation_gmres_cycles=1))
    assert not one.converged and one.iterations == 1 and coupled_newton.BROKE_OFF in one.stalled, one.message
    assert one.fft_pairs < 0.5 * whole.fft_pairs
    assert dict(chains._CONTINUATION.options)["coupled_continuation_gmres_cycles"] == chains.COUPLED_CONTINUATION_GMRES_CYCLES


def test_missed_gmres_hands_the_step_to_fire_with_the_same_state(fig8_step, monkeypatch):
    """Where the continuation gives up (GMRES starved as above), the chain's FIRE relaxes the step from the guess
    to the state the Newton continuation keeps unstarved, within the solver tolerance's bound; the label and the
    message say what ran and why."""
    cell, previous, _current, (z99, _) = fig8_step
    s = cell.settings
    kept = gs.relax(cell.physics, cell.law, z99, previous, s)
    assert kept.converged and kept.method == "newton", (kept.method, kept.message)
    monkeypatch.setattr(coupled_newton, "COUPLED_GMRES_RESTART", 1)
    monkeypatch.setattr(coupled_newton, "COUPLED_GMRES_CYCLES", 1)
    fell = gs.relax(cell.physics, cell.law, z99, previous, s)
    assert fell.converged and fell.method.startswith("newton→fire"), (fell.method, fell.message)
    assert "GMRES missed" in fell.message and "FIRE" in fell.message
    m = cell.physics
    k1 = min(abs(m.k_xx[1]), abs(m.k_zz[1])) - abs(m.k_xz[1])
    bound = 2 * s.tolerance * m.reference_traction * np.sqrt(m.nodes) / k1  # as in test_newton_agrees_with_fire
    for a, b in ((kept.u_z, fell.u_z), (kept.u_x, fell.u_x)):
        assert np.max(np.abs(a - b)) < 10 * bound + 1e-6 * cell.scene.interface.length_normal


def test_nodal_newton_reports_its_states_own_residual(fig8_step, monkeypatch):
    """The Newton iterates on the nodes (u, K u moved by δu, K δu from GMRES's parts, `newton_direction`), yet its
    verdict is the returned state's: the residual it reports is `balance_residual` of its u_hat (a separate route
    through rfft(t) − K û) to the round-off of one FFT pair on the tractions (eps · log2 N · max|t| / p_ref); and
    each direction's K δu is K applied to δu by FFT to round-off (eps · log2 N · the largest term, ‖K‖ max|δu|)."""
    from gfmd.coupled_krylov import balance_residual
    from gfmd.fft import Fft
    from gfmd.problem import stiffness_operator

    cell, previous, _current, (z99, _) = fig8_step
    problem = Problem(cell.physics, cell.law, z99)
    model, law = cell.physics, cell.law
    fft, stiff = Fft(model.nodes), stiffness_operator(model)
    seen, inner = [], coupled_newton.newton_direction

    def spy(*args):
        du, kdu, info = inner(*args)
        seen.append((du, kdu))
        return du, kdu, info

    monkeypatch.setattr(coupled_newton, "newton_direction", spy)
    out = coupled_newton.solve(problem, previous, cell.settings)
    assert out.converged and out.iterations >= 2 and len(seen) == out.iterations, out.message
    own, _ = balance_residual(model, law, z99, out.u_hat)
    eps_fft = np.finfo(float).eps * np.log2(model.nodes)
    t_max = max(np.max(np.abs(out.t_z)), np.max(np.abs(out.t_x))) / model.reference_traction
    assert abs(own - out.residual) <= eps_fft * t_max
    k_max = max(np.max(np.abs(model.k_xx)), np.max(np.abs(model.k_zz))) + np.max(np.abs(model.k_xz))
    for du, kdu in seen:
        du_hat = fft.rfft(du)
        du_hat[:, 0] = 0.0
        by_fft = fft.irfft(stiff.stiffness(du_hat))
        assert np.max(np.abs(kdu - by_fft)) <= eps_fft * k_max * np.max(np.abs(du))
