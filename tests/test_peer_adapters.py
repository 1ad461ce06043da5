"""The peer-code adapters (verification/solvers/tamaas.py, contactmechanics.py) on small analytic cases.

Each test is skipped with the install hint where its package is absent (the `peers` extra brings both).

Tolerances:
* Westergaard (hard wall, 1+1-D, 6 loads to δ = 0.995 h0, N = 64 … 1024): the peers solve the same nodal FFT
  discretisation as GFMD, whose errors vs N are stored (verification/data/westergaard.json); the bounds are
  those of verification/test_analytic_westergaard.py: least-squares orders p̄(ḡ) ≥ 1.5, a ≥ 0.7 and the
  N = 1024 errors ≤ 3× GFMD's stored ones.
* control round trip: pressure control at the p̄ a penetration-controlled step returned must give back its δ to
  the codes' own tolerance (δ error ≤ 1e-6 h0, far above both solvers' 1e-10 … 1e-12 and far below the
  discretisation error 1e-5 h0 that a wrong mapping would add at the least).
* Hertz sphere on ContactMechanics' free half-space, N = 32 and 64 across L = 1 µm, a = 0.1 … 0.2 L: the load
  error vs (4/3)E*√R δ^{3/2} at N = 64 ≤ 3× the 2.0e-3 measured there (ContactMechanics 1.8.3; 7.3e-3 at N = 32,
  2.4e-4 at N = 128) and below half the N = 32 error (order ≥ 1): E instead of E* (ν = 0.3) is 10 % off.
* adhesive laws: away from contact a converged state balances the elastic pressure with the law, node by node;
  the residual is the solver's gradient, accepted by the ContactMechanics adapter up to 1e-6 × the pressure scale
  per node (`ACCEPT × GRADIENT_TOLERANCE`), which bounds |p − p_law|, the codes' difference in p̄, and on the LJ
  9-3 wall the node-by-node difference from our GFMD (measured 2e-7; a 2 % error in w gives 1.3e-2).
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from reference.analytic import hertz_sphere as HS
from reference.analytic import westergaard as W
from verification.metrics import fitted_order
from verification.solvers.protocol import Interface, Problem, not_applicable
from verification.studies import westergaard as wg

ADAPTERS = {"tamaas": (("tamaas",), "verification.solvers.tamaas", "TamaasSolver"),
            "contactmechanics": (("ContactMechanics", "Adhesion"), "verification.solvers.contactmechanics",
                                 "ContactMechanicsSolver")}
E_STAR = 70e9 / (1 - 0.45**2)
H0, LENGTH = wg.H0, wg.LENGTH
DELTAS = tuple(0.995 * H0 * k / wg.STEPS for k in range(1, wg.STEPS + 1))
FACTOR, MIN_ORDER = 3.0, {"p̄(ḡ)": 1.5, "a": 0.7}
ROUND_TRIP = 1e-6  # δ error / h0 of pressure control at a penetration-controlled step's p̄
RESIDUAL = 1e-6  # |p − p_law| / pressure scale: the ContactMechanics adapter's accepted gradient


def adapter(name):
    """The adapter, or a skip naming the extra that brings its code."""
    packages, module, cls = ADAPTERS[name]
    for package in packages:
        pytest.importorskip(package, reason=f"{package} is not installed (the {name} adapter): "
                                            "pip install '.[peers]'")
    return getattr(importlib.import_module(module), cls)()


def sinusoid(nodes, shift=0.0):
    x = (np.arange(nodes) - nodes // 2) * LENGTH / nodes
    return H0 * (1.0 - np.cos(2 * np.pi * (x - shift) / LENGTH))


HARD_WALL = Interface("hard-wall")


def problem(h, control, path, lengths=(LENGTH,), interface=HARD_WALL, boundary="periodic"):
    return Problem(heights=h, lengths=lengths, contact_modulus=E_STAR, interface=interface, boundary=boundary,
                   control=control, path=tuple(path), name="peer-adapter test")


def westergaard_errors(states, nodes):
    """{metric: max over the loads}: |p̄ − p̄_W(ḡ)|/p* and |a − a_W(p̄)|/λ (a = contact nodes · l/2)."""
    ps = W.full_contact_pressure(H0, LENGTH, E_STAR)
    e_p, e_a = [], []
    for st in states:
        gbar = float(np.mean(st.gap))
        e_p.append(abs(st.mean_pressure - wg._pressure_at_mean_gap(gbar, ps, E_STAR)) / ps)
        a = 0.5 * LENGTH / nodes * np.count_nonzero(st.contact)
        e_a.append(abs(a - W.half_width(st.mean_pressure, H0, LENGTH, E_STAR)) / LENGTH)
    return {"p̄(ḡ)": max(e_p), "a": max(e_a)}


@pytest.mark.parametrize("name", sorted(ADAPTERS))
def test_westergaard_convergence(name):
    solver = adapter(name)
    nodes = np.array(wg.NODES["ci"])
    errors = {m: [] for m in MIN_ORDER}
    for n in nodes:
        answer = solver.solve(problem(sinusoid(n), "penetration", DELTAS))
        assert len(answer.states) == len(DELTAS) and answer.cost.wall_s > 0
        for m, e in westergaard_errors(answer.states, n).items():
            errors[m].append(e)
    stored, stored_nodes = wg.measured_errors("ci")
    for m, bound_order in MIN_ORDER.items():
        order = -fitted_order(nodes, errors[m])
        bound = FACTOR * stored[m][stored_nodes.index(int(nodes[-1]))]
        assert order >= bound_order, f"{name}: {m} order {order:.2f} < {bound_order} ({errors[m]})"
        assert errors[m][-1] <= bound, f"{name}: {m} error {errors[m][-1]:.3g} at N = {nodes[-1]} > {bound:.3g}"


@pytest.mark.parametrize("name", sorted(ADAPTERS))
def test_pressure_control_returns_the_penetration(name):
    solver, h = adapter(name), sinusoid(256)
    forward = solver.solve(problem(h, "penetration", DELTAS[1:5:2]))
    back = solver.solve(problem(h, "pressure", [st.mean_pressure for st in forward.states]))
    for delta, there, st in zip(DELTAS[1:5:2], forward.states, back.states):
        assert st.mean_pressure == pytest.approx(there.mean_pressure, rel=1e-9)
        assert abs(st.penetration - delta) <= ROUND_TRIP * H0, (name, st.penetration, delta)
        assert abs(there.penetration - delta) <= ROUND_TRIP * H0, (name, there.penetration, delta)


@pytest.mark.parametrize("name", sorted(ADAPTERS))
def test_first_contact_is_where_h_is_smallest(name):
    """The indenter's lowest point is off-centre: a shallow δ touches there (a code fed h summits-down would
    touch at the highest point instead)."""
    solver, n = adapter(name), 128
    shift = 0.3 * LENGTH
    h = sinusoid(n, shift)
    st = solver.solve(problem(h, "penetration", [0.01 * H0])).states[0]
    touching = np.flatnonzero(st.contact)
    assert touching.size > 0 and np.argmin(h) in touching
    x = (np.arange(n) - n // 2) * LENGTH / n
    assert np.all(np.abs((x[touching] - shift + LENGTH / 2) % LENGTH - LENGTH / 2) < 0.1 * LENGTH)
    assert st.gap.min() >= -1e-10 * np.ptp(h)  # the CG's pentol (Tamaas' gap is ≥ 0 exactly)
    assert st.penetration == pytest.approx(0.01 * H0, rel=1e-6)


@pytest.mark.parametrize("name", sorted(ADAPTERS))
def test_surface_on_a_non_square_cell(name):
    """2+1-D: the sinusoid along x on an L × L/4 cell (N × 8 nodes) is Westergaard's plane-strain contact: the
    same bounds as the profile at N = 256 (swapped axes or lengths would put the wave along y or stretch it)."""
    solver, n = adapter(name), 256
    h = np.repeat(sinusoid(n)[:, None], 8, axis=1)
    answer = solver.solve(problem(h, "penetration", DELTAS, lengths=(LENGTH, LENGTH / 4)))
    profiles = [type(st)(pressure=st.pressure[:, 0], gap=st.gap[:, 0], mean_pressure=st.mean_pressure,
                         penetration=st.penetration, contact=st.contact[:, 0]) for st in answer.states]
    for st in answer.states:
        assert np.ptp(st.pressure, axis=1).max() <= 1e-9 * W.full_contact_pressure(H0, LENGTH, E_STAR)
    stored, stored_nodes = wg.measured_errors("ci")
    for m, e in westergaard_errors(profiles, n).items():
        assert e <= FACTOR * stored[m][stored_nodes.index(n)], (name, m, e)


def test_tamaas_declares_no_free_boundary():
    solver = adapter("tamaas")
    reason = not_applicable(solver, problem(np.zeros((8, 8)), "penetration", [0.0], lengths=(1.0, 1.0),
                                            boundary="free"))
    assert reason and "periodic" in reason


REFUSED = {"tamaas": [("pressure", Interface("hard-wall+exponential", 0.5, 1e-9), 2, "periodic", "gap-primal")],
           "contactmechanics": [("pressure", Interface("hard-wall+exponential", 0.5, 1e-9), 2, "periodic",
                                 "given offset"),
                                ("pressure", Interface("lj93", 0.5, 1e-9), 1, "periodic", "given offset"),
                                ("penetration", HARD_WALL, 1, "free", "no 1D Green's function")]}


@pytest.mark.parametrize("name, control, interface, dimension, boundary, words",
                         [(n, *c) for n, cases in REFUSED.items() for c in cases])
def test_a_combination_the_code_cannot_do_is_not_applicable(name, control, interface, dimension, boundary, words):
    """Each value allowed by the capabilities, the combination refused by `refuses`: n/a with the reason (the case
    is then recorded n/a, not failed), and `solve` stops with the same reason."""
    from verification.cross_code import outcomes
    from verification.cross_code.cases import Case
    solver = adapter(name)
    h = sinusoid(16) if dimension == 1 else np.repeat(sinusoid(16)[:, None], 4, axis=1)
    case = problem(h, control, [1e6 if control == "pressure" else 1e-9], lengths=(LENGTH,) * dimension,
                   interface=interface, boundary=boundary)
    reason = not_applicable(solver, case)
    assert reason and words in reason, reason
    records = outcomes.run_case(solver, Case("refused", "none", lambda: [case], None, dict, "none"))
    assert [(r["passed"], r["reason"]) for r in records] == [(None, reason)]
    with pytest.raises(ValueError, match=words):
        solver.solve(case)


def test_hertz_sphere_on_a_free_half_space():
    solver = adapter("contactmechanics")
    radius, errors = 1e-6, []
    deltas = (0.01e-6, 0.02e-6, 0.04e-6)  # a = √(Rδ) = 0.1 … 0.2 L
    for n in (32, 64):
        x = (np.arange(n) - n // 2) * LENGTH / n
        h = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius)
        answer = solver.solve(problem(h, "penetration", deltas, lengths=(LENGTH, LENGTH), boundary="free"))
        errors.append(max(abs(st.mean_pressure * LENGTH**2 / HS.load_from_approach(d, radius, E_STAR) - 1)
                          for d, st in zip(deltas, answer.states)))
    assert errors[1] <= 3 * 2.0e-3 and errors[1] <= errors[0] / 2, errors


def test_free_penetration_agrees_with_our_gfmd():
    """Our GFMD's δ on a free half-space is the approach from the far field (δ − s of its padded cell), the
    protocol's δ, which ContactMechanics' FreeFFTElasticHalfSpace controls directly: at the δ GFMD reports under
    pressure control ContactMechanics carries the same load, to ROUND_TRIP (the two agree to ~1e-10 on the same
    discretisation; the mean-plane δ, without s, is 5–9 % smaller here and would miss the load by ~10 %)."""
    cm = adapter("contactmechanics")
    from verification.solvers.gfmd import GFMDSolver
    n, radius = 32, 1e-6
    x = (np.arange(n) - n // 2) * LENGTH / n
    h = (x[:, None] ** 2 + x[None, :] ** 2) / (2 * radius)
    loads = [HS.load_from_contact_radius(f * LENGTH / 8, radius, E_STAR) / LENGTH**2 for f in (0.5, 1.0)]
    ours = GFMDSolver().solve(problem(h, "pressure", loads, lengths=(LENGTH, LENGTH), boundary="free")).states
    theirs = cm.solve(problem(h, "penetration", [st.penetration for st in ours], lengths=(LENGTH, LENGTH),
                              boundary="free")).states
    for a, b in zip(ours, theirs):
        assert b.mean_pressure == pytest.approx(a.mean_pressure, rel=ROUND_TRIP), (a.penetration, b.penetration)


def exponential_law_residual(st, w, rho):
    """max |p − p_law(g)| off contact, p_law = −(w/ρ)e^{−g/ρ} (the attractive traction, tensile p < 0)."""
    off = ~st.contact
    return float(np.max(np.abs(st.pressure[off] + w / rho * np.exp(-st.gap[off] / rho)), initial=0.0))


ADHESION = Interface("hard-wall+exponential", work_of_adhesion=0.5, range=1e-9)


@pytest.mark.parametrize("name", sorted(ADAPTERS))
def test_exponential_functional_balances_the_law(name):
    solver = adapter(name)
    scale = max(E_STAR * 2 * H0 / LENGTH, ADHESION.work_of_adhesion / ADHESION.range)
    answer = solver.solve(problem(sinusoid(256), "penetration", (-2e-9, 2e-9, 6e-9), interface=ADHESION))
    for delta, st in zip((-2e-9, 2e-9, 6e-9), answer.states):
        assert exponential_law_residual(st, ADHESION.work_of_adhesion, ADHESION.range) <= RESIDUAL * scale
        assert st.penetration == pytest.approx(delta, abs=1e-6 * H0)
        assert st.gap.min() >= 0.0
    assert answer.states[0].mean_pressure < 0 < answer.states[2].mean_pressure


def test_exponential_functional_agrees_across_codes():
    tamaas, cm = adapter("tamaas"), adapter("contactmechanics")
    scale = max(E_STAR * 2 * H0 / LENGTH, ADHESION.work_of_adhesion / ADHESION.range)
    case = problem(sinusoid(256), "penetration", (-2e-9, 2e-9, 6e-9), interface=ADHESION)
    for a, b in zip(tamaas.solve(case).states, cm.solve(case).states):
        assert abs(a.mean_pressure - b.mean_pressure) <= RESIDUAL * scale
        assert np.array_equal(a.contact, b.contact)


def test_lj93_balances_the_law():
    """ContactMechanics' LJ 9-3 (ε, σ from w and z0) against the wall of gfmd_contact.core.law_lj93 written out:
    T_n = (9w/(2z))(x³ − x⁹), x = z0/z, z = z0 + Δn; p = −T_n at every node (no hard wall)."""
    solver = adapter("contactmechanics")
    w, z0 = 0.5, 1e-9
    scale = max(E_STAR * 2 * H0 / LENGTH, w / z0)
    answer = solver.solve(problem(sinusoid(256), "penetration", (-2e-9, 2e-9, 6e-9),
                                  interface=Interface("lj93", w, z0)))
    for delta, st in zip((-2e-9, 2e-9, 6e-9), answer.states):
        z = z0 + st.gap
        x3 = (z0 / z) ** 3
        law = 4.5 * w / z * (x3 - x3**3)
        assert np.max(np.abs(st.pressure + law)) <= RESIDUAL * scale
        assert st.penetration == pytest.approx(delta, abs=1e-6 * H0)
    assert answer.states[-1].contact.any() and not answer.states[0].contact.any()


def test_lj93_agrees_with_our_gfmd():
    """The LJ 9-3 wall has no analytic reference here; ContactMechanics (its own law and L-BFGS-B) is a second
    route to our GFMD's states on the same nodes: the pressures agree node by node within the residual that either
    code's convergence leaves (the ContactMechanics adapter's accepted gradient; GFMD's tolerance is tighter)."""
    cm = adapter("contactmechanics")
    from verification.solvers.gfmd import GFMDSolver
    w, z0 = 0.5, 1e-9
    scale = max(E_STAR * 2 * H0 / LENGTH, w / z0)
    case = problem(sinusoid(256), "penetration", (-2e-9, 0.0, 2e-9, 6e-9), interface=Interface("lj93", w, z0))
    for ours, theirs in zip(GFMDSolver().solve(case).states, cm.solve(case).states):
        assert np.max(np.abs(ours.pressure - theirs.pressure)) <= RESIDUAL * scale
        assert ours.penetration == pytest.approx(theirs.penetration, abs=1e-6 * H0)
