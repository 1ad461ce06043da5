"""The scene catalogue: every scene a verification case, a study, a unit test or a benchmark runs.

Each factory returns a validated `gfmd_contact.core.scene.Scene` (SI units, `gfmd_contact.core.conventions`);
cases vary them with `.replace(**{"section.key": value})`. Tests, studies and benchmarks
import scenes from here, never from a test module.
"""

from __future__ import annotations

import atexit
import shutil
import tempfile
from pathlib import Path

import numpy as np

from gfmd_contact.core.scene import Scene, default_scene

_MATERIAL = {"material.youngs_modulus": 70e9, "material.poisson_ratio": 0.3}


# ----------------------------------------------------------------------------- adhesive sinusoid on a layer (FE cases)
def cohesive_sinusoid(n):
    """h = −a cos(2πx/L), a = 50 nm, L = 1 µm, layer D = L bonded to a rigid base, E = 70 GPa, ν = 0.3,
    normal-only CZ (c = 0), φn* = 0.01, δn = 1 nm, δ0 = 2 nm, δ from −2 nm to 60 nm in 20 steps
    (a_rel 0.17 … 0.46); fields at steps 4, 8, …, 20."""
    return Scene().replace(**_MATERIAL, **{
        "surface.kind": "sinusoid", "surface.realizations": 1, "surface.nodes": n, "surface.length": 1e-6,
        "surface.amplitude": 50e-9, "material.thickness": 1e-6, "interface.law": "cohesive",
        "interface.phi_n_star": 0.01, "interface.length_normal": 1e-9, "interface.tangential_ratio": 0.0,
        "loading.initial_separation": 2e-9, "loading.final_penetration": 60e-9, "loading.steps": 20,
        "output.field_steps": 5})


#: c = φt*/φn* and the deepest δ (m) of the coupled-law sinusoid (why not deeper: verification/test_fe_coupled.py)
COUPLED_TANGENTIAL_RATIO = 0.5
COUPLED_FINAL_PENETRATION = 18e-9


def coupled_sinusoid(n, nu):
    """`cohesive_sinusoid` with the coupled law (seed Eq. 2), c = 0.5, δn = δt = 1 nm, Poisson ratio nu,
    δ up to 18 nm in 10 steps of 2 nm (a_rel ≈ 0.17–0.30); fields at steps 2, 4, …, 10."""
    return cohesive_sinusoid(n).replace(**{
        "interface.tangential_ratio": COUPLED_TANGENTIAL_RATIO, "material.poisson_ratio": nu,
        "loading.final_penetration": COUPLED_FINAL_PENETRATION, "loading.steps": 10, "output.field_steps": 5})


def jump_in_sinusoid(n):
    """`cohesive_sinusoid` at φn* = 0.15 through a jump into contact: δ0 = 10 nm (≥ 8 δn),
    δ from −10 nm to 40 nm in 25 steps."""
    return cohesive_sinusoid(n).replace(**{"interface.phi_n_star": 0.15, "loading.initial_separation": 10e-9,
                                           "loading.final_penetration": 40e-9, "loading.steps": 25})


def cohesive_self_affine(n, hurst):
    """Self-affine profile (seed Eq. 4), L = 1 µm, λr = 250 nm, λs,H = L/64 (every N ≥ 128 samples the
    same 32 modes), h_rms = 5 nm, seed 3; layer D = L, E = 70 GPa, ν = 0.3; normal-only CZ φn* = 0.01,
    δn = 1 nm; δ0 = 2 nm, δ from −2 nm to 10 nm in 15 steps (a_rel ≈ 0.1 … 0.7); fields at 5, 10, 15."""
    return Scene().replace(**_MATERIAL, **{
        "surface.kind": "self-affine", "surface.realizations": 1, "surface.nodes": n, "surface.length": 1e-6,
        "surface.hurst": hurst, "surface.h_rms": 5e-9, "surface.rolloff_wavelength": 250e-9,
        "surface.rollon_wavelength": 1e-6 / 64, "surface.seed": 3, "material.thickness": 1e-6,
        "interface.law": "cohesive", "interface.phi_n_star": 0.01, "interface.length_normal": 1e-9,
        "interface.tangential_ratio": 0.0, "loading.initial_separation": 2e-9,
        "loading.final_penetration": 10e-9, "loading.steps": 15, "output.field_steps": 3})


# ----------------------------------------------------------------------------- speed–accuracy scenes
_SELF_AFFINE = {"surface.kind": "self-affine", "surface.realizations": 1, "surface.length": 1e-6,
                "surface.hurst": 0.8, "surface.h_rms": 5e-9, "surface.rolloff_wavelength": 250e-9,
                "surface.rollon_wavelength": 1e-6 / 16, "surface.seed": 3, "surface.nodes": 1024}
_PROFILE_DIR = []


def centred_self_affine_path(n):
    """Path of a .npy file with the self-affine profile of `_SELF_AFFINE` (m) at N = n nodes, translated so
    that its lowest point is the node x = 0 of every grid.

    Why: z_ind = h − min_nodes h + δ0 − U uses the minimum over the *nodes*; for a profile whose lowest point
    falls between nodes, min_nodes h, hence the indenter position at equal U, changes with N (a rigid shift
    of 1.9e-4 in p(δ) between N ≤ 1024 and N ≥ 2048, not discretisation). The profile has 16 modes
    (λs = L/16), so its Fourier series is exact on every N ≥ 64 and is evaluated directly.
    """
    from gfmd_contact.core import surfaces
    if not _PROFILE_DIR:  # one folder per process, removed at exit (the profile is rebuilt from _SELF_AFFINE)
        _PROFILE_DIR.append(Path(tempfile.mkdtemp(prefix="speed_accuracy_profiles_")))
        atexit.register(shutil.rmtree, _PROFILE_DIR[0], ignore_errors=True)
    path = _PROFILE_DIR[0] / f"self_affine_{n}.npy"
    if not path.exists():
        base = Scene().replace(**_SELF_AFFINE).surface
        h = surfaces.profile(base)
        length = base.length
        coef = np.fft.rfft(h) / h.size
        k = np.flatnonzero(np.abs(coef) > 1e-12 * np.abs(coef).max())
        amp, q = np.where(k == 0, 1.0, 2.0) * coef[k], 2 * np.pi * k / length

        def series(x, derivative=0):  # h(x) and its x-derivatives; samples start at x = −L/2
            phase = np.exp(1j * np.outer(np.atleast_1d(x) + length / 2, q))
            return ((1j * q) ** derivative * amp * phase).real.sum(axis=1)

        x_grid = surfaces.grid(h.size, length)
        x_min = x_grid[np.argmin(h)]
        for _ in range(20):  # Newton on h'(x) = 0 from the lowest node
            step = series(x_min, 1)[0] / series(x_min, 2)[0]
            x_min -= step
            if abs(step) < 1e-15 * length:
                break
        np.save(path, series(surfaces.grid(n, length) + x_min))
    return str(path)


def _centred_self_affine(n):
    return {"surface.kind": "file", "surface.path": centred_self_affine_path(n), "surface.facing": "valleys",
            "surface.nodes": n,
            "surface.length": _SELF_AFFINE["surface.length"], "surface.realizations": 1,
            "material.thickness": 1e-6}


def adhesive_sinusoid(n):
    """(a) of the speed–accuracy study: `cohesive_sinusoid` with the fields of the last step only."""
    return cohesive_sinusoid(n).replace(**{"output.field_steps": 1})


def adhesive_self_affine(n):
    """(b) self-affine H = 0.8, h_rms = 5 nm, L = 1 µm, λr = 250 nm, λs = L/16 (the same 16 modes at every
    N ≥ 64), seed 3, lowest point on the node x = 0 (`centred_self_affine_path`), layer D = L, E = 70 GPa,
    ν = 0.3, normal CZ φn* = 0.01, δn = 1 nm, δ from −5 nm to 10 nm in 15 steps.

    δ0 = 5 nm > δ_jump = 4.0 δn (gfmd_contact.core.model.jump_in_separation): from inside the jump-in range
    (δ0 = 2 nm) the jump at the first steps picked N-dependent equilibria."""
    return Scene().replace(**_MATERIAL, **_centred_self_affine(n), **{
        "interface.law": "cohesive", "interface.phi_n_star": 0.01,
        "interface.length_normal": 1e-9, "interface.tangential_ratio": 0.0, "loading.initial_separation": 5e-9,
        "loading.final_penetration": 10e-9, "loading.steps": 15, "output.field_steps": 1})


def hard_wall_self_affine(n):
    """(c) the profile of (b), frictionless hard wall, layer D = L, δ from 0 to 12 nm in 12 steps."""
    return Scene().replace(**_MATERIAL, **_centred_self_affine(n), **{
        "interface.law": "hard-wall", "loading.initial_separation": 0.0,
        "loading.final_penetration": 12e-9, "loading.steps": 12, "output.field_steps": 1})


#: speed–accuracy scenes by name: factory(N)
SPEED_ACCURACY = {"adhesive-sinusoid": adhesive_sinusoid, "adhesive-self-affine": adhesive_self_affine,
                  "hard-wall-self-affine": hard_wall_self_affine}


# ----------------------------------------------------------------------------- extremes base scene
EXTREMES_BASE = {
    "surface.kind": "self-affine", "surface.nodes": 512, "surface.length": 256e-9, "surface.hurst": 0.8,
    "surface.h_rms": 4e-9, "surface.rolloff_wavelength": 64e-9, "surface.rollon_wavelength": 4e-9,
    "surface.seed": 1, "surface.realizations": 1, "material.youngs_modulus": 70e9,
    "material.poisson_ratio": 0.45, "material.thickness": "inf", "interface.law": "cohesive",
    "interface.phi_n_star": 0.15, "interface.length_normal": 1e-9, "interface.tangential_ratio": 0.0,
    "loading.initial_separation": 8e-9, "loading.final_penetration": 4e-9, "loading.steps": 24,
    "solver.tolerance": 1e-8, "output.field_steps": 4}


def extremes_base(**overrides):
    """Cohesive self-affine scene, small for CI: L = 256 nm, N = 512 (l = 0.5 nm, δn = 2 l), H = 0.8,
    h_rms = 4 nm, λr = 64 nm, λs,H = 4 nm, seed 1; half-plane, E = 70 GPa, ν = 0.45; normal-only CZ
    φn* = 0.15, δn = 1 nm; δ0 = 8 nm = 8 δn, δ from −8 nm to 4 nm in 24 steps (ΔU = 0.5 nm); FIRE,
    tolerance 1e-8. `overrides`: "section.key" values replacing the base's."""
    return Scene().replace(**{**EXTREMES_BASE, **overrides})


#: the load–unload path (δ in m) and steps per segment of `cycle_self_affine` (Δδ = 0.25 nm loading,
#: 0.05 nm = δn/5 unloading: an unloading step of 2 δn leaves the attached branch at once)
CYCLE_PATH, CYCLE_STEPS = (-8e-9, 4e-9, -8e-9), (48, 240)


def cycle_self_affine(n, length_normal=0.25e-9, path=CYCLE_PATH, steps=CYCLE_STEPS):
    """The extremes base profile (L = 256 nm, H = 0.8, h_rms = 4 nm, λr = 64 nm, λs,H = 4 nm, seed 1,
    half-plane ν = 0.45, φn* = 0.15) on N = n nodes, stickier (δn = 0.25 nm), driven along the
    displacement path `path` (m; δ0 = −path[0]) in `steps` steps per segment; no fields saved."""
    base = {k: v for k, v in EXTREMES_BASE.items()
            if k not in ("loading.initial_separation", "loading.final_penetration", "loading.steps")}
    return Scene().replace(**{**base, "surface.nodes": n, "interface.length_normal": length_normal,
                              "loading.path": list(path), "loading.steps": list(steps), "output.field_steps": 0})


# ----------------------------------------------------------------------------- analytic cases (default half-plane)
ANALYTIC_TOLERANCE = 1e-10  # solver tolerance (× p_ref) of every analytic case


def _indenter(kind, shape, nodes, length, law, steps, final, initial, extra):
    d = {"surface.kind": kind, "surface.nodes": int(nodes), "surface.length": length, "surface.realizations": 1,
         "interface.law": law, "loading.initial_separation": initial, "loading.final_penetration": final,
         "loading.steps": steps, "solver.tolerance": ANALYTIC_TOLERANCE, "output.field_steps": steps, **shape}
    d.update(extra)
    return default_scene().replace(**d)


def sinusoid(nodes, amplitude, length, law="hard-wall", steps=6, final=1e-9, initial=0.0, **extra):
    """h = −a cos(2πx/L) on the default half-plane (E = 70 GPa, ν = 0.45), fields at every step."""
    return _indenter("sinusoid", {"surface.amplitude": amplitude}, nodes, length, law, steps, final, initial, extra)


def cylinder(nodes, radius, length, law="hard-wall", steps=4, final=1e-9, initial=0.0, **extra):
    """Parabolic cylinder h = x²/(2R) centred in a periodic cell on the default half-plane."""
    return _indenter("cylinder", {"surface.radius": radius}, nodes, length, law, steps, final, initial, extra)


def sphere(nodes, radius, length, law="hard-wall", steps=4, final=1e-9, initial=0.0, **extra):
    """2+1-D: paraboloid h = (x² + y²)/(2R) centred in a square periodic L × L cell of N × N nodes on the
    default half-space (E = 70 GPa, ν = 0.45), fields at every step."""
    return _indenter("sphere", {"surface.radius": radius, "surface.nodes_y": int(nodes)}, nodes, length, law,
                     steps, final, initial, extra)


def egg_box(nodes, amplitude, length, law="hard-wall", steps=6, final=1e-9, initial=0.0, **extra):
    """2+1-D: egg-box h = a cos(2πx/L) cos(2πy/L) on a square L × L cell of N × N nodes, default half-space."""
    return _indenter("egg-box", {"surface.amplitude": amplitude, "surface.nodes_y": int(nodes)}, nodes, length,
                     law, steps, final, initial, extra)


def embedded_sinusoid(nodes, amplitude, length, nodes_y, length_y, law="hard-wall", steps=6, final=1e-9,
                      initial=0.0, **extra):
    """2+1-D: the 1-D sinusoid h = −a cos(2πx/L) constant along y on an L × Ly cell of N × Ny nodes
    (`sinusoid` with `surface.nodes_y`, `surface.length_y`)."""
    return _indenter("sinusoid", {"surface.amplitude": amplitude, "surface.nodes_y": int(nodes_y),
                                  "surface.length_y": length_y}, nodes, length, law, steps, final, initial, extra)


# ----------------------------------------------------------------------------- GFMD self-consistency
def small_sinusoid(law):
    """Sinusoid A = 5 nm, L = 1 µm, N = 256 on the default half-plane, δ to 4 nm in 10 steps; law
    "hard-wall" or "cohesive" (normal CZ φn* = 0.15)."""
    return default_scene().replace(**{
        "surface.kind": "sinusoid", "surface.amplitude": 5e-9, "surface.nodes": 256, "surface.length": 1e-6,
        "surface.realizations": 1, "interface.law": law, "loading.steps": 10,
        "loading.final_penetration": 4e-9})


# ----------------------------------------------------------------------------- the shared ramp's records
def ramp_check_layer(n=64):
    """`jump_in_sinusoid` (layer D = L, φn* = 0.15, δn = 1 nm) through one load–unload cycle, δ: −10 → 30 →
    −10 nm in 20 + 30 steps (jump-in on loading, jump-out on unloading), fields at every step 1 … 50."""
    return jump_in_sinusoid(n).replace(**{"loading.path": [-10e-9, 30e-9, -10e-9], "loading.steps": [20, 30],
                                          "output.field_steps": 50})


def ramp_check_half_plane(n=256):
    """Johnson's adhesive sinusoid of verification.studies.jkr_cycle at d/λ = 0.04 (h0 = 10 nm, L = 1 µm,
    half-plane ν = 0.45, w = 3.898 J/m², δn = 0.553 nm) through δ: −6 → 6 → −6 nm in 30 + 40 steps,
    fields at every step 1 … 70."""
    s = sinusoid(n, 10e-9, 1e-6, law="cohesive", **{
        "interface.work_normal": 3.8983390424365494, "interface.length_normal": 5.532822053374735e-10})
    return s.replace(**{"loading.path": [-6e-9, 6e-9, -6e-9], "loading.steps": [30, 40], "output.field_steps": 70})
