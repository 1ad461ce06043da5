"""GFMD equilibria satisfy the discrete force balance, recomputed independently.

For every load step of an adhesive sinusoid pushed through contact, the test
rebuilds — without gfmd_contact.core.kernels, gfmd_contact.core.laws or gfmd.solver — the indenter
z_ind = h − min h + δ0 − U, the gap Δn = z_ind − u_z, the elastic traction
t_el = −irfft(K rfft(u)) with the kernel written out from reference-formulas §1,
and the CZ traction T(Δ) from seed Eqs. 2–3, and checks

    max_j |t_el + T − (mean of T, half-plane only)| ≤ tolerance · p_ref,
    p = −⟨t_n⟩,  t_n = T_n(Δn),

with p_ref = E* ḡ (seed Eq. 6, recomputed). On a half-plane the q = 0 mode is
clamped (⟨u⟩ = 0), so the uniform part of the interface traction is carried by
the far field and is subtracted; on a layer it is balanced by k(0) = M/D.

Tolerance: the solver stops when its own residual, the same quantity, is below
TOL·p_ref (checked every 10 iterations). The independent recomputation differs
from the solver's only by FFT round-off: measured |r_test − r_solver| ≤ 1e-13 p_ref,
so `max|r| ≤ TOL·p_ref·(1 + 1e-3)` leaves a margin of 1e4 over round-off and
none for an unconverged state (a step stopped at residual 2·TOL fails).
"""

import numpy as np
import pytest
import scipy.fft

from gfmd_contact.core import surfaces
from gfmd_contact.core.loading import displacement_steps
from gfmd.loading import run_realization
from gfmd_contact.core.scene import default_scene
from gfmd.solver import Settings

TOL = 1e-9
H0 = 10e-9  # m, sinusoid amplitude
LENGTH = 1e-6  # m, one wavelength per cell
NODES = 512
PHI_STAR = 0.05


def scene(**extra):
    """Adhesive sinusoid, 8 steps of 1 nm from 2 nm apart to 6 nm penetration (through jump-in)."""
    kw = {"surface.kind": "sinusoid", "surface.nodes": NODES, "surface.length": LENGTH, "surface.amplitude": H0,
          "surface.realizations": 1, "interface.law": "cohesive", "interface.phi_n_star": PHI_STAR,
          "loading.initial_separation": 2e-9, "loading.final_penetration": 6e-9, "loading.steps": 8,
          "solver.tolerance": TOL, "output.field_steps": 8}
    kw.update(extra)
    return default_scene().replace(**kw)


# --- independent ingredients (reference-formulas §1, seed Eqs. 2, 3, 6) ---------------------------

def wavenumbers(n, length):
    return 2 * np.pi * np.fft.rfftfreq(n, d=length / n)


def e_star(sc):
    m = sc.material
    return m.youngs_modulus / (1 - m.poisson_ratio**2)


def kernel(sc):
    """(K_xx, K_xz, K_zz) on the rfft half-spectrum (Pa/m), §1.1–1.3, §1.5; K_zx = conj(K_xz)."""
    n, length = sc.surface.nodes, sc.surface.length
    e, nu, d = sc.material.youngs_modulus, sc.material.poisson_ratio, sc.material.thickness
    q = wavenumbers(n, length)
    f = e_star(sc) * q / 2
    s = np.sign(q)
    coupled = sc.interface.tangential_ratio > 0 and (nu < 0.5 or np.isfinite(d))
    if np.isinf(d):
        if not coupled:
            return None, None, f.astype(complex)
        beta = (1 - 2 * nu) / (2 * (1 - nu))
        kd = f / (1 - beta**2)
        kxz = 1j * beta * s * kd
        kxz[-1] = 0.0  # Nyquist (even N): coupling zeroed, §1.6
        return kd.astype(complex), kxz, kd.astype(complex)
    assert not coupled, "layer + coupled law not needed here"
    k3 = 3 - 4 * nu
    big = np.minimum(q * d, 40.0)  # beyond qD = 40 the layer equals the half-plane to 1e-30
    num = k3 * np.cosh(2 * big) + 2 * big**2 + 5 - 12 * nu + 8 * nu**2
    den = k3 * np.sinh(2 * big) - 2 * big
    with np.errstate(invalid="ignore", divide="ignore"):
        kzz = np.where(q * d > 40, f, f * num / den)
    kzz[0] = e * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * d)  # M/D
    return None, None, kzz.astype(complex)


def cz_tractions(sc, gap_n, gap_t):
    """(T_n, T_t) of seed Eq. 2 (Eq. 3 for Δt = 0), Pa."""
    i, e = sc.interface, sc.material.youngs_modulus
    phi_n = i.phi_n_star * i.length_normal * e
    phi_t = i.tangential_ratio * i.phi_n_star * i.length_tangential * e
    sn, st = gap_n / i.length_normal, gap_t / i.length_tangential
    common = np.exp(-sn - st**2)
    return (phi_n / i.length_normal) * sn * common, 2 * (phi_t / i.length_tangential) * st * common


def reference_traction(sc, h):
    l = sc.surface.length / sc.surface.nodes
    g2 = 0.5 * (((h - np.roll(h, -1)) / l) ** 2 + ((h - np.roll(h, 1)) / l) ** 2)
    return e_star(sc) * np.sqrt(np.mean(g2))


def force_residual(sc, h, U, u_z, u_x):
    """(max nodal |r| (Pa), T_n, Δn) of a state u, recomputed from scratch."""
    n = sc.surface.nodes
    z_ind = h - h.min() + sc.loading.initial_separation - U
    gap_n = z_ind - u_z
    gap_t = -u_x
    t_n, t_t = cz_tractions(sc, gap_n, gap_t)
    kxx, kxz, kzz = kernel(sc)
    uz_hat, ux_hat = scipy.fft.rfft(u_z), scipy.fft.rfft(u_x)
    if kxx is None:
        r = [-scipy.fft.irfft(kzz * uz_hat, n=n) + t_n]
    else:
        r = [-scipy.fft.irfft(kxx * ux_hat + kxz * uz_hat, n=n) + t_t,
             -scipy.fft.irfft(np.conj(kxz) * ux_hat + kzz * uz_hat, n=n) + t_n]
    if sc.material.half_plane:
        r = [c - c.mean() for c in r]  # uniform part carried by the far field (q = 0 clamped)
    return max(float(np.max(np.abs(c))) for c in r), t_n, gap_n


def check_equilibrium(sc, settings=None):
    result = run_realization(sc, settings=settings)
    assert result.all_converged, result.messages
    h = surfaces.profile(sc.surface)
    p_ref = reference_traction(sc, h)
    U = displacement_steps(sc.loading)
    worst = 0.0
    for k in range(1, sc.loading.steps + 1):
        f = result.fields[k]
        if sc.material.half_plane:  # clamped mean (gfmd_contact.core.conventions)
            assert abs(np.mean(f["u_z"])) <= 1e-12 * H0 and abs(np.mean(f["u_x"])) <= 1e-12 * H0
        r, t_n, gap = force_residual(sc, h, U[k], f["u_z"], f["u_x"])
        worst = max(worst, r / p_ref)
        assert r <= TOL * p_ref * (1 + 1e-3), (k, r / p_ref)
        # the solver's own residual record agrees with the recomputation (round-off only)
        assert abs(r / p_ref - result.curve["residual"][k]) <= 1e-3 * TOL, (k, r / p_ref, result.curve["residual"][k])
        # returned fields are those of the law at the returned gap; p = −⟨t_n⟩
        np.testing.assert_allclose(f["gap"], gap, rtol=0, atol=1e-12 * H0)
        np.testing.assert_allclose(f["t_n"], t_n, rtol=1e-10, atol=1e-12 * p_ref)
        assert result.curve["p"][k] == pytest.approx(-np.mean(t_n), rel=1e-10, abs=1e-12 * p_ref)
    # the ramp really goes through contact: tension somewhere at the end, and a jump-in
    assert np.min(result.fields[sc.loading.steps]["gap"]) < sc.interface.length_normal
    return result, worst


def test_equilibrium_half_plane_normal_cz():
    result, worst = check_equilibrium(scene())
    assert "normal-only CZ" in result.model and "half-plane" in result.model
    print(f"max residual {worst:.3g} p_ref; p = {result.curve['p']}")


def test_equilibrium_layer():
    result, worst = check_equilibrium(scene(**{"material.thickness": LENGTH}))
    assert "layer" in result.model
    print(f"max residual {worst:.3g} p_ref")


def test_equilibrium_coupled_law():
    result, worst = check_equilibrium(scene(**{"interface.tangential_ratio": 0.5, "material.poisson_ratio": 0.3}))
    assert "coupled CZ" in result.model
    # the coupling is active: a tangential gap develops (otherwise this case tests nothing new)
    assert np.max(np.abs(result.fields[8]["u_x"])) > 1e-3 * np.max(np.abs(result.fields[8]["u_z"]))
    print(f"max residual {worst:.3g} p_ref")


def test_unconverged_step_is_recorded():
    """max_iterations = 3: every loaded step is returned unconverged, with its residual and a message."""
    sc = scene()
    result = run_realization(sc, settings=Settings(method="fire", tolerance=TOL, max_iterations=3))
    conv = np.asarray(result.curve["converged"])
    res = np.asarray(result.curve["residual"])
    assert not result.all_converged
    bad = np.flatnonzero(conv == 0)
    assert bad.size >= 1
    assert np.all(np.isfinite(res[bad])) and np.all(res[bad] > TOL), res[bad]
    assert len(result.messages) == bad.size
    for k, msg in zip(bad, result.messages):
        assert f"step {k}" in msg and "not converged" in msg, msg
    # converged steps (if any: e.g. the first, out of contact) do satisfy the tolerance
    assert np.all(res[conv == 1] < TOL)


def test_fire_and_verlet_agree_cohesive():
    """Same adhesive scene, both integrators: the equilibria agree to the solver tolerance.

    Each state leaves a nodal residual ≤ TOL·p_ref; their difference is the response of
    the (linearised) surface to at most 2·TOL·p_ref, whose softest elastic mode has
    compliance 1/k_1 = 2/(E* q_1). Bound: max|Δu_z| ≤ 2·TOL·p_ref/k_1 (measured 0.92 of
    TOL·p_ref/k_1, i.e. margin 2.2) and |Δp| ≤ 2·TOL·p_ref (measured 0.085·TOL·p_ref).
    Unlike the hard wall (one FIRE routine serves both methods), the cohesive steps run
    two different integrators here (FIRE ≈ 200, Verlet ≈ 1000–2000 iterations a step).
    """
    sc = scene()
    h = surfaces.profile(sc.surface)
    p_ref = reference_traction(sc, h)
    k1 = e_star(sc) * wavenumbers(NODES, LENGTH)[1] / 2
    fire = run_realization(sc, settings=Settings(method="fire", tolerance=TOL))
    verlet = run_realization(sc, settings=Settings(method="verlet", tolerance=TOL))
    assert fire.all_converged and verlet.all_converged, (fire.messages, verlet.messages)
    assert np.all(np.asarray(verlet.curve["iterations"]) != np.asarray(fire.curve["iterations"]))
    for k in range(1, sc.loading.steps + 1):
        du = np.max(np.abs(fire.fields[k]["u_z"] - verlet.fields[k]["u_z"]))
        assert du <= 2 * TOL * p_ref / k1, (k, du * k1 / (TOL * p_ref))
        assert abs(fire.curve["p"][k] - verlet.curve["p"][k]) <= 2 * TOL * p_ref
