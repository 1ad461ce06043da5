"""The GFMD solver as algorithms over one problem: the problem's energy, gradient and
Hessian product agree with each other, the chains are data that `relax` walks, and the labels
(`Relaxed.method`, the Result's method, its per-step algorithms) name what ran.

* `Problem.force` is −(1/l) ∇E of `Problem.energy` (central differences of E along random
  directions; the tolerance from the difference's truncation error, measured by halving the step),
  `Problem.tangent_times` the derivative of −force (the same test one order up), and
  `Problem.dual_gap` the gap z_ind − u of u = −G P;
* every chain key is reachable from some Settings and names only algorithm modules; replacing a
  chain in `gfmd.chains.CHAINS` changes what `relax` runs (the dispatch reads the data), and so does
  `relax`'s own chain; a `Link` outside the chain vocabulary is refused where it is built;
* a default cohesive ramp reports "gfmd-ncg" and one label per step, and the hard-wall FIRE and the
  cohesive wall now say "fire" where `Relaxed.method` used to be empty.
"""

import dataclasses

import numpy as np
import pytest

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import indenter_surface
from gfmd_contact.core.model import build_model
from gfmd_contact.core.scene import default_scene
from gfmd import chains
from gfmd.algorithms import coupled_newton
from gfmd.loading import prepare, run_realization
from gfmd.problem import Problem
from gfmd.solver import InterfaceLaw, Relaxed, Settings, relax


def problem(law="cohesive", nodes=256, delta=3e-9, thickness=None, **extra):
    length = 1.28e-6
    kw = {"surface.nodes": nodes, "surface.length": length, "surface.rolloff_wavelength": length / 8,
          "surface.rollon_wavelength": 4 * length / nodes, "interface.law": law,
          "interface.length_normal": 1e-9, **extra}
    if thickness is not None:
        kw["material.thickness"] = thickness
    sc = default_scene().replace(**kw)
    if law == "user":  # seed Eq. 3 through the extension point (gfmd_contact.core.user_law)
        from gfmd_contact.core import laws
        from gfmd_contact.core.user_law import user_law
        phi, dn = sc.work_normal, sc.interface.length_normal
        sc = dataclasses.replace(sc, user_law=user_law(lambda g: laws.potential_normal(g, phi, dn),
                                                       lambda g: laws.traction_normal(g, phi, dn),
                                                       lambda g: laws.stiffness_normal(g, phi, dn), dn))
    h = surfaces.profile(sc.surface, 0)
    model = build_model(sc, h)
    d0 = sc.loading.initial_separation
    return Problem(model, InterfaceLaw(model), indenter_surface(h, d0, d0 + delta), 1e-12 * float(np.ptp(h)))


def converged_state(p, settings=Settings(tolerance=1e-10)):
    r = relax(p.model, p.law, p.z_ind, np.zeros((p.model.components, p.model.nodes // 2 + 1), complex), settings,
              p.wall_tolerance)
    assert r.converged, r.message
    return r


def central_difference(f, x, v, eps):
    return (f(x + eps * v) - f(x - eps * v)) / (2 * eps)


@pytest.mark.parametrize("thickness", [None, 0.32e-6])
def test_force_is_the_negative_energy_gradient(thickness):
    """d/dε E(u + ε v) = −l Σ f·v, checked at a state in contact (the law's nonlinear range)."""
    p = problem(thickness=thickness)
    u_hat = converged_state(p).u_hat
    rng = np.random.default_rng(3)
    spacing = p.model.length / p.model.nodes
    for _ in range(3):
        v = rng.standard_normal(p.model.nodes) * p.model.law.length_normal * 1e-2
        if p.model.half_plane:
            v -= v.mean()
        v_hat = np.fft.rfft(v)[None, :]
        slope = -spacing * float(np.sum(p.force(u_hat) * v))

        def energy(s):
            return p.energy(u_hat + s * v_hat)

        coarse, fine = central_difference(energy, 0.0, 1.0, 1e-1), central_difference(energy, 0.0, 1.0, 5e-2)
        # central differences: error ∝ ε², so |fine − exact| ≈ |coarse − fine| / 3; allow 3× that + round-off
        scale = abs(energy(0.0)) + spacing * float(np.sum(np.abs(p.force(u_hat) * v)))
        assert abs(fine - slope) <= abs(coarse - fine) + 1e-9 * scale, (fine, slope, coarse)


def test_tangent_is_the_derivative_of_minus_the_force():
    p = problem()
    u_hat = converged_state(p).u_hat
    rng = np.random.default_rng(5)
    v = rng.standard_normal((1, p.model.nodes)) * p.model.law.length_normal * 1e-2
    v -= v.mean()
    v_hat = np.fft.rfft(v, axis=-1)
    jv = p.tangent_times(u_hat, v)

    def force(s):
        return p.force(u_hat + s * v_hat)

    coarse, fine = -central_difference(force, 0.0, 1.0, 1e-1), -central_difference(force, 0.0, 1.0, 5e-2)
    error = np.max(np.abs(fine - jv))
    assert error <= np.max(np.abs(coarse - fine)) + 1e-9 * np.max(np.abs(jv)), error


def test_dual_gap_is_the_gap_of_the_pressures_displacement():
    """u = −G P: the gap z_ind − u = z_ind + G P, and K u = −P on every mode but a half-plane's mean."""
    p = problem("hard-wall")
    pressure = np.maximum(np.random.default_rng(2).standard_normal(p.model.nodes), 0.0) * 1e6
    gap = p.dual_gap(pressure)
    u = p.z_ind - gap
    ku = np.fft.irfft(np.real(p.model.k_zz) * np.fft.rfft(u), n=p.model.nodes)
    np.testing.assert_allclose(ku, -(pressure - pressure.mean()), atol=1e-9 * np.max(pressure))


def test_energy_is_infinite_through_the_wall_and_undefined_for_the_coupled_law():
    p = problem("hard-wall")
    u_hat = np.fft.rfft(p.z_ind + 1e-9)[None, :]  # every node 1 nm through the wall
    assert p.energy(u_hat) == np.inf
    coupled = problem(**{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3})
    assert coupled.kind == "coupled"
    with pytest.raises(ValueError, match="no potential"):
        coupled.energy(np.zeros((2, coupled.model.nodes // 2 + 1), complex))


SETTINGS_OF_KEY = {"cg-dual2": Settings(), "cg-dual": Settings(dual_coarse_block=0),
                   "fire": Settings(hard_wall="fire", cohesive="fire", coupled="fire"), "verlet": Settings(method="verlet"),
                   "ncg": Settings(), "handover-near": Settings(),  # "auto" at ν = 0.3
                   "frictionless-first": Settings(coupled="frictionless-first")}
LAW_OF_KIND = {"hard-wall": ("hard-wall", {}), "cohesive": ("cohesive", {}), "cohesive-wall": ("cohesive-wall", {}),
               "coupled": ("cohesive", {"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3}),
               "user": ("user", {})}


@pytest.mark.parametrize("key", sorted(chains.CHAINS))
def test_every_chain_is_reachable_and_labels_what_ran(key):
    kind, name = key
    law, extra = LAW_OF_KIND[kind]
    p = problem(law, **extra)
    settings = SETTINGS_OF_KEY[name]
    assert chains.chain_key(p, settings) == key
    r = converged_state(p, Settings(**{**settings.__dict__, "tolerance": 1e-8}))
    ran = r.method.split("→")
    assert ran and set(ran) <= set(chains.labels(key, settings)), (r.method, chains.labels(key, settings))
    assert ran[0] in chains.labels(key, settings)[:2]  # the first (or, past the dual's limit, the primal)


def test_relax_walks_the_chain_it_is_given(monkeypatch):
    """The chain is data: the cohesive NCG chain replaced by FIRE alone, relax runs FIRE."""
    p = problem()
    assert converged_state(p).method == "ncg"
    monkeypatch.setitem(chains.CHAINS, ("cohesive", "ncg"), (chains.Link("dynamics"),))
    assert converged_state(p).method == "fire"
    monkeypatch.undo()
    guess = np.zeros((p.model.components, p.model.nodes // 2 + 1), complex)
    own = relax(p.model, p.law, p.z_ind, guess, Settings(tolerance=1e-10), p.wall_tolerance,
                chain=(chains.Link("dynamics"),))
    assert own.converged and own.method == "fire"
    with pytest.raises(ValueError, match="chain = "):
        relax(p.model, p.law, p.z_ind, guess, Settings(), p.wall_tolerance, chain=("dynamics",))


def test_a_stall_passes_the_step_on_and_every_iteration_counts(monkeypatch):
    """NCG cut to 3 iterations: FIRE finishes from the guess; iterations add both, the message says why."""
    from gfmd.algorithms import ncg

    p = problem()
    monkeypatch.setattr(ncg, "NCG_BUDGET", 3)
    r = converged_state(p)
    assert r.method == "ncg→fire" and "NCG stopped" in r.message and "FIRE" in r.message
    alone = converged_state(p, Settings(tolerance=1e-10, cohesive="fire"))
    assert r.iterations == alone.iterations + 3
    np.testing.assert_array_equal(r.u_hat, alone.u_hat)  # FIRE from the same guess: the same iterates


@pytest.mark.parametrize("law, settings, label", [
    ("hard-wall", Settings(hard_wall="fire"), "fire"), ("hard-wall", Settings(method="verlet"), "verlet"),
    ("cohesive-wall", Settings(), "fire"), ("cohesive-wall", Settings(method="verlet"), "verlet")])
def test_projected_dynamics_name_themselves(law, settings, label):
    p = problem(law, nodes=128)
    assert converged_state(p, Settings(**{**settings.__dict__, "tolerance": 1e-7})).method == label


def test_ramp_results_name_the_algorithm_of_every_step():
    """A default cohesive ramp: the Result says gfmd-ncg (not gfmd-fire) and one label per step."""
    sc = default_scene().replace(**{"surface.nodes": 256, "surface.length": 320e-9, "surface.realizations": 1,
                                    "surface.rolloff_wavelength": 160e-9, "surface.rollon_wavelength": 10e-9,
                                    "interface.length_normal": 2.5e-9, "loading.steps": 4,
                                    "loading.final_penetration": 4e-9, "loading.initial_separation": 20e-9})
    result = run_realization(sc)
    assert result.method == "gfmd-ncg"
    assert len(result.diagnostics["algorithms"]) == len(result.curve["step"])
    assert set(result.diagnostics["algorithms"]) <= {"ncg", "ncg→fire"}
    assert any("algorithms: ncg (then fire where it stalls)" in r for r in result.reasons)
    hard = sc.replace(**{"interface.law": "hard-wall"})
    assert prepare(hard, surfaces.profile(hard.surface, 0)).method == "gfmd-cg-dual2"
    verlet = sc.replace(**{"solver.method": "verlet"})
    assert prepare(verlet, surfaces.profile(verlet.surface, 0)).method == "gfmd-verlet"


def fake_result(p, u_hat, converged, method, iterations, fft_pairs=0.0, residual=1e-4, why="stalled"):
    """A `Relaxed` an algorithm stubbed into `chains.ALGORITHMS` returns: converged at 1e-9, else at `residual`
    stalled for `why`."""
    fields = np.zeros((p.model.nodes,))
    return Relaxed(u_hat, fields, fields, fields, fields, fields, iterations, 1e-9 if converged else residual,
                   converged, fft_pairs=fft_pairs, method=method, stalled="" if converged else why)


@pytest.mark.parametrize("newton_converged", [False, True])
def test_coupled_fire_restarts_where_newton_stalled_never_from_a_rejected_state(monkeypatch, newton_converged):
    """The coupled chain: FIRE stalled from the guess runs again from the state where the continuation Newton
    stalled (a fold: Fig. 8 at 2^17, seed 2, step 176); a converged Newton state the chain rejected (a jump) is
    never a start (FIRE would keep it without the stability test)."""
    p = problem("cohesive", **{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3})
    settings = Settings(tolerance=1e-8, coupled="handover-near")
    assert chains.chain_key(p, settings) == ("coupled", "handover-near")
    shape = (p.model.components, p.model.nodes // 2 + 1)
    guess, newton_end = np.zeros(shape, complex), np.full(shape, 1e-12 + 0j)
    starts = []

    def record(u_hat, converged, method):
        return fake_result(p, u_hat, converged, method, 5)

    def newton(problem, start, run):
        starts.append(("newton", start is guess))
        return record(newton_end, newton_converged and run.coupled_gmres_give_up, "newton")

    def fire(problem, start, run):
        starts.append(("fire", "guess" if start is guess else "newton end" if start is newton_end else "other"))
        return record(start, start is newton_end, "fire")

    monkeypatch.setitem(chains.ALGORITHMS, "coupled_newton", newton)
    monkeypatch.setitem(chains.ALGORITHMS, "dynamics", fire)
    monkeypatch.setitem(chains.ALGORITHMS, "coupled_ptc", lambda problem, start, run: record(start, False, "ptc"))
    monkeypatch.setattr(chains, "_rejected", lambda problem, link, r, origin, *words:
                        "" if link.accept is chains.Accept.ANY else "a jump")
    r = chains.relax(p.model, p.law, p.z_ind, guess, settings, p.wall_tolerance)
    fires = [s for s in starts if s[0] == "fire"]
    if newton_converged:  # rejected: FIRE and then Verlet from the guess, never from the rejected state
        assert fires == [("fire", "guess"), ("fire", "guess")] and not r.converged
    else:
        assert fires == [("fire", "guess"), ("fire", "newton end")]
        assert r.converged and r.method == "newton→fire" and "FIRE stopped" in r.message


@pytest.mark.parametrize("resumed_converges", [False, True])
def test_a_broken_off_continuation_is_resumed_to_its_stall_before_fire_restarts(monkeypatch, resumed_converges):
    """The continuation Newton breaks off where an iterate jumped (`coupled_newton.BROKE_OFF`); where FIRE then
    stalls from the guess, the chain resumes that Newton without the break-off (Settings.coupled_continuation_jump
    0, from its break-off state) and starts FIRE again where it stalls, the state the whole Newton run reaches (the
    fold of Fig. 8 at 2^17, seed 2, step 176); a resumed run that converges is never a start. Its iterations count,
    the label and the message name it."""
    p = problem("cohesive", **{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3})
    settings = Settings(tolerance=1e-8, coupled="handover-near")
    shape = (p.model.components, p.model.nodes // 2 + 1)
    guess, broken, stalled = (np.full(shape, v + 0j) for v in (0.0, 1e-12, 2e-12))
    calls = []

    def record(u_hat, converged, method, why):
        return fake_result(p, u_hat, converged, method, 7, fft_pairs=11.0, why=why)

    def newton(problem, start, run):
        calls.append(("newton", "guess" if start is guess else "broken" if start is broken else "other",
                      run.coupled_continuation_jump))
        if start is broken:  # resumed with all its GMRES cycles, without the stagnation test
            assert run.coupled_continuation_gmres_cycles == 0 and run.coupled_continuation_stagnation == 0
        if start is broken:
            return record(stalled, resumed_converges, "newton", "line search found no decrease")
        if run.coupled_continuation_jump > 0:
            return record(broken, False, "newton", f"a node moved 2 law lengths: {coupled_newton.BROKE_OFF}")
        return record(start, False, "newton", "line search found no decrease")

    def fire(problem, start, run):
        calls.append(("fire", "guess" if start is guess else "stalled" if start is stalled else "other"))
        return record(start, start is stalled, "fire", "not converged")

    monkeypatch.setitem(chains.ALGORITHMS, "coupled_newton", newton)
    monkeypatch.setitem(chains.ALGORITHMS, "dynamics", fire)
    monkeypatch.setitem(chains.ALGORITHMS, "coupled_ptc", lambda problem, start, run: record(start, False, "ptc", "x"))
    r = chains.relax(p.model, p.law, p.z_ind, guess, settings, p.wall_tolerance)
    assert calls[:3] == [("newton", "guess", chains.COUPLED_JUMP), ("fire", "guess"), ("newton", "broken", 0.0)]
    if resumed_converges:  # another equilibrium: not a start; the chain goes on to its stability-tested Newton
        assert ("fire", "stalled") not in calls and "another equilibrium" in r.message
    else:
        assert calls[3] == ("fire", "stalled") and len(calls) == 4
        assert r.converged and r.method == "newton→fire→newton→fire" and r.iterations == 4 * 7
        assert r.fft_pairs == 4 * 11.0 and "resumed without the break-off" in r.message


@pytest.mark.parametrize("coupled", ["handover-near"])
def test_a_continuation_stalled_at_the_guess_does_not_start_fire_twice(monkeypatch, coupled):
    """Where the continuation Newton stalls at the guess itself (GMRES missed at its first iteration: Fig. 8 at
    2^17, seed 7, step 199), its "stalled end" is the guess, where FIRE ran already: the chain goes on to its
    stability-tested Newton without repeating that FIRE run (a copy of the guess counts as the guess)."""
    p = problem("cohesive", **{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3})
    settings = Settings(tolerance=1e-8, coupled=coupled)
    shape = (p.model.components, p.model.nodes // 2 + 1)
    guess = np.zeros(shape, complex)
    calls = []

    def record(u_hat, converged, method):
        return fake_result(p, u_hat, converged, method, 3, fft_pairs=5.0, residual=2.0)

    def newton(problem, start, run):
        calls.append(("newton", "continuation" if run.coupled_continuation_jump > 0 else "other"))
        return record(start.copy(), False, "newton")  # stalls where it started

    def fire(problem, start, run):
        calls.append(("fire", run.method))
        return record(start, run.method == "verlet", "fire" if run.method == "fire" else "verlet")

    def ptc(problem, start, run):
        calls.append(("ptc", start is guess))
        return record(start, False, "ptc")

    monkeypatch.setitem(chains.ALGORITHMS, "coupled_newton", newton)
    monkeypatch.setitem(chains.ALGORITHMS, "dynamics", fire)
    monkeypatch.setitem(chains.ALGORITHMS, "coupled_ptc", ptc)
    r = chains.relax(p.model, p.law, p.z_ind, guess, settings, p.wall_tolerance)
    assert calls == [("newton", "continuation"), ("fire", "fire"),  # then the fallback Newton from both its starts
                     ("newton", "other"), ("newton", "other"), ("ptc", True), ("fire", "verlet")]
    # + 1.5 pairs: the residual of the state FIRE started from, which `chains._progressed` compares with its end's
    assert r.converged and "stalled at the guess" in r.message and r.fft_pairs == 6 * 5.0 + 1.5


@pytest.mark.parametrize("coupled", ["handover-near"])
@pytest.mark.parametrize("blew_up", [True, False])
def test_a_fire_run_that_blew_up_is_no_start(monkeypatch, coupled, blew_up):
    """The fallback Newton starts from the guess, then from FIRE's end ("finite end") only where FIRE lowered the
    residual of the state it started from (Fig. 8 at 2^17, seed 7, step 199: FIRE from 0.21 to 2.3e7 p_ref, Newton
    from there 47 iterations and 131 s to 2.1e3 p_ref)."""
    from gfmd.coupled_krylov import balance_residual

    p = problem("cohesive", **{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3})
    settings = Settings(tolerance=1e-8, coupled=coupled)
    shape = (p.model.components, p.model.nodes // 2 + 1)
    guess = np.zeros(shape, complex)
    at_guess, _ = balance_residual(p.model, p.law, p.z_ind, guess)
    calls = []

    def newton(problem, start, run):
        calls.append(("newton", "guess" if start is guess else "other"))
        return fake_result(p, start.copy(), False, "newton", 3, fft_pairs=5.0, residual=2.0 * at_guess)

    def fire(problem, start, run):
        calls.append(("fire", run.method))
        end = (1e7 if blew_up else 0.5) * at_guess
        return fake_result(p, start.copy(), run.method == "verlet", "fire", 3, fft_pairs=5.0, residual=end)

    monkeypatch.setitem(chains.ALGORITHMS, "coupled_newton", newton)
    monkeypatch.setitem(chains.ALGORITHMS, "dynamics", fire)
    monkeypatch.setitem(chains.ALGORITHMS, "coupled_ptc", lambda problem, start, run: fake_result(
        p, start, False, "ptc", 3, fft_pairs=5.0, residual=2.0))
    chains.relax(p.model, p.law, p.z_ind, guess, settings, p.wall_tolerance)
    fallback = [c for c in calls[calls.index(("fire", "fire")):] if c[0] == "newton"]
    assert fallback == ([("newton", "guess")] if blew_up else [("newton", "guess"), ("newton", "other")])


@pytest.mark.parametrize("stable", [True, False])
@pytest.mark.parametrize("coupled", ["handover-near"])
def test_ptc_runs_before_verlet_where_fire_and_newton_gave_up(monkeypatch, coupled, stable):
    """Where FIRE and the stability-tested Newton gave up (Fig. 8 at 2^17, ν = 0.1, seed 7, step 199: FIRE's dynamics
    circulate, Newton's line search stalls, damped Verlet then ran 58 min unconverged), the coupled chains run
    Ψtc from the guess before Verlet; its converged state is kept only where locally stable, else Verlet runs."""
    p = problem("cohesive", **{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3})
    shape = (p.model.components, p.model.nodes // 2 + 1)
    guess, settled = np.zeros(shape, complex), np.full(shape, 3e-12 + 0j)
    calls = []

    def newton(problem, start, run):
        calls.append("newton")
        return fake_result(p, start, False, "newton", 3)

    def fire(problem, start, run):
        calls.append(run.method)
        return fake_result(p, start, run.method == "verlet", run.method, 3)

    def ptc(problem, start, run):
        calls.append(("ptc", start is guess))
        return fake_result(p, settled, True, "ptc", 3)

    monkeypatch.setitem(chains.ALGORITHMS, "coupled_newton", newton)
    monkeypatch.setitem(chains.ALGORITHMS, "dynamics", fire)
    monkeypatch.setitem(chains.ALGORITHMS, "coupled_ptc", ptc)
    monkeypatch.setattr(chains, "coupled_stability", lambda model, law, z_ind, u_hat: 1.0 if stable else -1.0)
    r = chains.relax(p.model, p.law, p.z_ind, guess, Settings(tolerance=1e-8, coupled=coupled), p.wall_tolerance)
    assert calls.index(("ptc", True)) == max(i for i, c in enumerate(calls) if c == "newton") + 1
    if stable:
        assert r.converged and r.method.endswith("newton→ptc") and "verlet" not in calls and r.u_hat is settled
    else:
        assert calls[-1] == "verlet" and r.method.endswith("ptc→verlet") and "not locally stable" in r.message


def test_fire_from_the_handover_state_gets_the_crawl_budget(monkeypatch):
    """FIRE going on from its handover state (Newton there not kept) gets COUPLED_FIRE_CRAWL iterations with the
    handover link's, not what is left of COUPLED_FIRE_BUDGET: near a fold it crawls through the ghost of the
    equilibrium it was approaching (Fig. 8 at 2^17, ν = 0.45, seed 8, step 156: 6 220 iterations after the handover,
    where 1 720 left the step to Verlet for over an hour); never more than half of Settings.max_iterations."""
    p = problem("cohesive", **{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3})
    shape = (p.model.components, p.model.nodes // 2 + 1)
    guess = np.zeros(shape, complex)
    handed = np.full(shape, 1e-12 + 0j)
    budgets = []

    def record(u_hat, converged, method):
        return fake_result(p, u_hat, converged, method, 7)

    def newton(problem, start, run):
        return record(start, False, "newton")

    def fire(problem, start, run):
        budgets.append((start is handed, run.max_iterations))
        if run.tolerance == Settings().coupled_handover:  # the handover link reaches its residual
            return record(handed, True, "fire")
        return record(start, start is handed, "fire")

    monkeypatch.setitem(chains.ALGORITHMS, "coupled_newton", newton)
    monkeypatch.setitem(chains.ALGORITHMS, "dynamics", fire)
    for settings, crawl in ((Settings(tolerance=1e-8), chains.COUPLED_FIRE_CRAWL),
                            (Settings(tolerance=1e-8, max_iterations=3000), 1500)):
        budgets.clear()
        r = chains.relax(p.model, p.law, p.z_ind, guess, settings, p.wall_tolerance)
        assert r.converged and r.method == "newton→fire→newton→fire", r.method
        assert budgets == [(False, min(chains.COUPLED_FIRE_BUDGET, settings.max_iterations // 2)), (True, crawl - 7)]


@pytest.mark.parametrize("bad", [{"algorithm": "cg-dual9"}, {"starts": ("guess",)}, {"starts": ()},
                                 {"budget": "rest"}, {"accept": "near"}, {"handover": "yes"},
                                 {"options": (("no_such_field", 1),)}])
def test_a_link_outside_the_vocabulary_is_refused_where_it_is_built(bad):
    """Strings where the chain's types belong, an unknown algorithm or Settings field: refused by `Link` itself."""
    with pytest.raises(ValueError, match=f"Link.{next(iter(bad))}"):
        chains.Link(**{"algorithm": "ncg", **bad})


def test_an_algorithm_with_options_of_its_own_runs_with_them(monkeypatch):
    """The two-level dual CG declares `Options` (scipy's per-method options): the chain hands it those fields of the
    Settings and nothing else; a link setting a field outside them is refused where it is built."""
    from gfmd.algorithms import hard_wall_two_level_cg

    p = problem("hard-wall")
    seen, real = [], chains.ALGORITHMS["hard_wall_two_level_cg"]
    monkeypatch.setitem(chains.ALGORITHMS, "hard_wall_two_level_cg",
                        lambda problem, start, options: seen.append(options) or real(problem, start, options))
    r = converged_state(p, Settings(tolerance=1e-9, dual_coarse_block=8))
    assert r.method.startswith("cg-dual2") and type(seen[0]) is hard_wall_two_level_cg.Options
    assert (seen[0].tolerance, seen[0].dual_coarse_block, seen[0].max_iterations) == (1e-9, 8, Settings().max_iterations)
    with pytest.raises(ValueError, match="Link.options"):
        chains.Link("hard_wall_primal_cg", options=(("method", "verlet"),))
