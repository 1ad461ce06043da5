"""The coupled NCG (`gfmd.algorithms.coupled_ncg`, Settings.coupled = "ncg-first", `gfmd.chains`).

Kernel: the line search's trial pass against the law's own formulas (`gfmd_contact.core.law_equations`, Eq. 2 and its
tangent), both backends. Line search: it stops where the force along the direction, computed afresh from the
interface law, has fallen to its tolerance. Chain: test_coupled_handover's ramp (bench_adhesion_scaling's coupled
class at N = 2^12) at its first event step, against "handover-near".
"""

from dataclasses import replace

import numpy as np
import pytest

from gfmd_contact.core.law_equations import MAX_COMPRESSION, jacobian_coupled, traction_coupled
from gfmd import chains
from gfmd.algorithms import coupled_ncg
from gfmd.kernels import numba
from gfmd.problem import InterfaceLaw
from gfmd.settings import Settings

from test_coupled_handover import _event_step, bound, ramps  # noqa: F401  (ramps: the module fixture)

PARAMS = (0.05, 1e-9, 0.025, 1e-9)  # φn (J/m²), δn, φt, δt (m)
BACKENDS = ["numpy"] + (["numba"] if numba is not None else [])


def _state(n=500, seed=0):
    rng = np.random.default_rng(seed)
    u = rng.normal(size=(2, n)) * 1e-9
    d = rng.normal(size=(2, n)) * 1e-10
    z = u[1] + rng.uniform(-1.5e-9, 4e-9, n)
    return u, d, z


@pytest.mark.parametrize("backend", BACKENDS)
def test_trial_pass_is_the_laws_traction_and_tangent(backend):
    u, d, z = _state()
    lowest = -MAX_COMPRESSION * PARAMS[1]
    trial = coupled_ncg._trial(backend)
    for alpha in (0.0, 0.7, 3.0):
        t, e = np.empty_like(u), np.empty(u.shape[1])
        td, dd, bad = trial(u, d, alpha, z, *PARAMS, lowest, t, e)
        v = u + alpha * d
        t_n, t_t = traction_coupled(z - v[1], -v[0], *PARAMS)
        d_nn, d_nt, d_tn, d_tt = jacobian_coupled(z - v[1], -v[0], *PARAMS)
        assert bad == 0
        assert np.allclose(t[1], t_n, rtol=1e-13, atol=1e-13 * np.max(np.abs(t_n)))
        assert np.allclose(t[0], t_t, rtol=1e-13, atol=1e-13 * np.max(np.abs(t_t)))
        assert td == pytest.approx(np.sum(t_t * d[0] + t_n * d[1]), rel=1e-11)
        # dᵀ D d with D's rows and columns (x, z): ∂T_t/∂Δt, ∂T_t/∂Δn; ∂T_n/∂Δt, ∂T_n/∂Δn
        assert dd == pytest.approx(np.sum(d_tt * d[0] ** 2 + (d_tn + d_nt) * d[0] * d[1] + d_nn * d[1] ** 2),
                                   rel=1e-11)
    z_deep = z.copy()
    z_deep[3] = u[1, 3] + 2 * lowest  # one node far beyond the law's compression range
    assert trial(u, d, 0.0, z_deep, *PARAMS, lowest, np.empty_like(u), np.empty(u.shape[1]))[2] == 1


def test_line_search_stops_where_the_force_along_the_direction_vanishes(ramps):
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    model, law = cell.physics, InterfaceLaw(cell.physics)
    u = np.fft.irfft(guess, n=model.nodes, axis=1)
    ku = np.fft.irfft(np.stack([model.k_xx * guess[0] + model.k_xz * guess[1],
                                np.conj(model.k_xz) * guess[0] + model.k_zz * guess[1]]), n=model.nodes, axis=1)

    def force(v, kv):
        t, _ = law.traction(v, z)
        return t - t.mean(axis=1, keepdims=True) - kv

    f = force(u, ku)
    d = f / np.max(np.abs(f)) * 0.1 * cell.scene.interface.length_normal  # along the force, zero-mean
    kd = np.fft.irfft(np.stack([model.k_xx * np.fft.rfft(d[0]) + model.k_xz * np.fft.rfft(d[1]),
                                np.conj(model.k_xz) * np.fft.rfft(d[0]) + model.k_zz * np.fft.rfft(d[1])]),
                      n=model.nodes, axis=1)
    slope0 = float(np.sum(f * d))
    assert slope0 > 0
    eta = Settings().line_search_tol
    alpha, f_alpha = coupled_ncg._line_search(law, z, u, ku, d, kd, slope0, True, eta, 0.5e-9)
    assert alpha > 0
    reference = force(u + alpha * d, ku + alpha * kd)
    assert np.allclose(f_alpha, reference, rtol=0, atol=1e-9 * np.max(np.abs(reference)))
    assert abs(np.sum(reference * d)) <= eta * slope0 * (1 + 1e-9)


def test_event_step_is_fires_state_in_fewer_pairs(ramps):
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    near = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="handover-near"))
    ncg = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="ncg-first"))
    assert near.method == "newton→fire→newton" and ncg.method == "newton→coupled-ncg→newton", ncg.method
    assert ncg.converged and ncg.residual < cell.settings.tolerance
    assert np.max(np.abs(ncg.u_z - near.u_z)) < bound(cell) and np.max(np.abs(ncg.u_x - near.u_x)) < bound(cell)
    assert ncg.fft_pairs < near.fft_pairs


def test_a_stalled_or_rejected_coupled_ncg_goes_on_as_handover_near(ramps, monkeypatch):
    cell, default, _ = ramps
    z, guess = _event_step(cell, default)
    near = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="handover-near"))
    monkeypatch.setattr(coupled_ncg, "COUPLED_NCG_BUDGET", 2)  # the NCG stalls before the handover residual
    stalled = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="ncg-first"))
    assert stalled.method == "newton→coupled-ncg→fire→newton", stalled.method
    assert "coupled NCG stopped (not converged after 2 iterations" in stalled.message
    assert stalled.converged and np.max(np.abs(stalled.u_z - near.u_z)) < bound(cell)
    monkeypatch.setattr(coupled_ncg, "COUPLED_NCG_BUDGET", 400)
    monkeypatch.setattr(chains, "COUPLED_HANDOVER_MOVE", 0.0)  # every Newton state "moved too far"
    far = chains.relax(cell.physics, cell.law, z, guess, replace(cell.settings, coupled="ncg-first"))
    assert far.method.startswith("newton→coupled-ncg→newton→fire"), far.method
    assert "from the coupled NCG's handover state (another equilibrium), rejected" in far.message, far.message
    assert far.converged and np.max(np.abs(far.u_z - near.u_z)) < bound(cell)


def test_chain_key_checks_the_handover_residual(ramps):
    cell, _, _ = ramps
    problem = chains.Problem(cell.physics, cell.law, np.zeros(cell.physics.nodes))
    assert chains.chain_key(problem, replace(cell.settings, coupled="ncg-first")) == ("coupled", "ncg-first")
    with pytest.raises(ValueError, match="Settings.coupled_handover"):
        chains.chain_key(problem, replace(cell.settings, coupled="ncg-first", coupled_handover=cell.settings.tolerance))
