"""The loading protocol every method shares (seed §2): load steps, indenter position, stops, warnings.

Units: SI (see `gfmd_contact.core.conventions`). The indenter starts with its closest point
δ0 above the undeformed surface; U goes from 0 to δ0 + final_penetration in
`steps` equal increments (step 0 is U = 0), each step warm-started from the
previous equilibrium (`RampState`). A half-plane realization stops early below its
own full-contact limit (`realization_steps`). Warnings of the protocol: a start
inside the contact range (`start_warning`) and the coupled law's slip regime
(`slip_warning`); `preflight` makes every check before a run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import surfaces
from .laws import law_from_scene
from .model import build_model, softest_normal_stiffness


def piecewise_path(corners, steps, offset=0.0):
    """A piecewise-linear path at every step: corners[0], then each segment's `steps[s]` equal increments to the
    next corner (all + offset)."""
    parts = [np.array([corners[0] + offset])]
    for s, n in enumerate(steps):
        parts.append(np.linspace(corners[s] + offset, corners[s + 1] + offset, n + 1)[1:])
    return np.concatenate(parts)


def path_values(loading, offset=0.0):
    """The path's value at every step k = 0 … steps: each segment's equal increments between its corners
    (+ offset); δ (m) under displacement control, p̄ (Pa) under force control."""
    return piecewise_path(loading.path, loading.segment_steps, offset)


def displacement_steps(loading):
    """Imposed indenter displacements U_k (m), k = 0 … steps: the ramp's equal increments from 0, or
    along a path (loading.path, corners of δ) each segment's equal increments, U = δ + δ0, δ0 = −path[0]."""
    if loading.path:
        return path_values(loading, loading.initial_separation)
    total = loading.initial_separation + loading.final_penetration
    return np.linspace(0.0, total, loading.steps + 1)


def step_segments(loading):
    """Per step k = 0 … steps: the index of the path segment it ends (step 0: segment 0; the ramp: all 0)."""
    if not loading.path:
        return np.zeros(loading.steps + 1, int)
    return np.concatenate([[0]] + [np.full(n, s) for s, n in enumerate(loading.segment_steps)]).astype(int)


def step_branches(loading):
    """(branch, cycle) per step k = 0 … steps: branch "loading" where δ grows (step 0 too), "unloading"
    where it falls; a cycle is a loading run and the unloading run after it (cycle 0, 1, ...: a new
    cycle begins where δ turns from falling to growing)."""
    segment = step_segments(loading)
    if not loading.path:
        return np.full(segment.size, "loading", dtype=object), np.zeros(segment.size, int)
    rising = [b > a for a, b in zip(loading.path[:-1], loading.path[1:])]
    seg_cycle, c = [], 0
    for s, up in enumerate(rising):
        if s > 0 and up and not rising[s - 1]:
            c += 1
        seg_cycle.append(c)
    branch = np.array(["loading" if rising[s] else "unloading" for s in segment], dtype=object)
    branch[0] = "loading"
    return branch, np.array([seg_cycle[s] for s in segment], int)


def extrapolation_allowed(loading, k):
    """Whether step k may be warm-started by linear extrapolation from steps k−1 and k−2: they and k
    lie on one segment of equal increments (never across a corner of a path, where the direction may
    turn: an unloading step then starts from the last state, not from a guess beyond the turning point)."""
    if k < 2:
        return False
    if not loading.path:
        return True
    segment = step_segments(loading)
    return bool(segment[k] == segment[k - 1] == segment[k - 2])


def field_step_indices(loading, count):
    """Indices of the `count` evenly spaced steps whose fields are saved (last step included)."""
    if count <= 0:
        return set()
    return set(np.unique(np.round(np.linspace(0, loading.steps, count + 1)[1:]).astype(int)).tolist())


def indenter_surface(h, initial_separation, displacement):
    """z_ind(x) = h − min h + δ0 − U (m), gfmd_contact.core.conventions."""
    return h - np.min(h) + initial_separation - displacement


#: a half-plane realization is loaded up to (1 − FULL_CONTACT_MARGIN) of its own full-contact limit
#: δ_max = mean(h) − min(h): at δ_max the mean pressure diverges and no equilibrium exists; just below
#: it one does, and the hard wall converges there (verification/test_analytic_westergaard.py loads the
#: sinusoid to 0.995 δ_max, P = p̄/p* ≈ 0.85), so only the last 0.2 % are left out
FULL_CONTACT_MARGIN = 0.002


def realization_label(scene, realization):
    """How a realization is named in messages: its index and, for random profiles, its seed."""
    if scene.surface.kind != "self-affine":
        return f"realization {realization}"
    return f"realization {realization} (seed {scene.surface.seed + realization})"


def has_full_contact_limit(scene):
    """Does the indenter reach full contact at a finite δ = ⟨h⟩ − min h? A periodic half-plane or half-space
    does; a layer does not (its mean mode has a finite stiffness), nor does a free body (it sinks as it is loaded)."""
    return scene.material.half_plane and scene.surface.boundary == "periodic"


def realization_steps(scene, h, realization=0):
    """(U_k (m), note): the load steps this realization runs, and why it stops early (None if it does not).

    On a half-plane δ is measured from the mean plane (gfmd_contact.core.conventions): the indenter's
    mean height above it is ⟨h⟩ − min h − δ, so full contact, and an unbounded pressure,
    is reached at δ_max = ⟨h⟩ − min h (m), which differs between realizations. A
    realization whose δ_max·(1 − FULL_CONTACT_MARGIN) lies below loading.final_penetration
    runs the common steps up to that δ and stops there; a layer has no such limit.
    """
    if scene.loading.control == "force":  # the loads p̄_k (Pa); the δ limit is checked as the ramp goes
        return path_values(scene.loading), None
    steps = displacement_steps(scene.loading)
    if not has_full_contact_limit(scene):
        return steps, None
    limit = float(np.mean(h) - np.min(h))
    stop = (1.0 - FULL_CONTACT_MARGIN) * limit
    d0 = scene.loading.initial_separation
    if scene.loading.final_penetration <= stop or not np.any(steps - d0 > stop):
        return steps, None
    below = steps - d0 <= stop
    kept = steps[:int(np.argmin(below))]  # up to the first step beyond the limit (a path may come back below it)
    note = (f"{realization_label(scene, realization)} stops at step {kept.size - 1} (δ = {kept[-1] - d0:.4g} m) of "
            f"{steps.size - 1}: its full-contact limit mean(h) − min(h) = {limit:.4g} m lies below "
            f"loading.final_penetration = {scene.loading.final_penetration:.4g} m; a half-plane realization is "
            f"loaded to at most {1 - FULL_CONTACT_MARGIN:g} of its own limit (gfmd_contact.core.loading.FULL_CONTACT_MARGIN)")
    return kept, note


def preflight(scene):
    """Every check made before a run: (warnings, notes), the same for `gfmd run` and `gfmd scene --check`.

    First the memory one process of the run needs (`gfmd_contact.core.cost.check_memory`, refused above what the
    machine allows; `gfmd run` and `gfmd_contact.run` check it again for their worker count);
    warnings: the model's check findings (gfmd_contact.core.model.scene_warnings; with
    solver.checks = "error" build_model raises ModelCheckError instead), then the unit-slip warnings
    (`gfmd_contact.core.plausibility`, never a refusal); notes: the
    realizations that stop early below their full-contact limit (`realization_steps`).
    """
    from .cost import check_memory
    from .plausibility import unit_slip_warnings

    check_memory(scene, workers=1)  # one process at least, before any array is allocated (runs check their workers)
    warnings, notes = [], []
    for i in range(scene.surface.realizations):
        h = surfaces.profile(scene.surface, i)
        if i == 0:
            warnings = list(build_model(scene, h).warnings)
        steps, note = realization_steps(scene, h, i)
        if note:
            notes.append(note)
        check_step_in_law_range(scene, steps, i)
        check_force_path_below_full_contact(scene, h, i)
    return warnings + unit_slip_warnings(scene), notes


def full_contact_pressure(h, length, youngs_modulus, poisson_ratio, length_y=None):
    """p̄_fc (Pa): the least mean pressure at which a hard wall with profile h (m) is in full contact
    with a frictionless half-plane (reference-formulas §1.1, k(q) = E*|q|/2); a 2+1-D surface h of shape
    (Nx, Ny) with cell length × length_y on a half-space, k(q) = E*|q|/2 at |q| of the rfft2 half-spectrum.

    In full contact the surface follows the indenter, û_q = −ĥ_q on every q ≠ 0, so the contact pressure is
    p(x) = p̄ + p_h(x) with p_h = −F⁻¹[k(q) ĥ_q] (zero mean, largest under the lowest points of h); a hard
    wall carries no tension, so p(x) ≥ 0 everywhere needs p̄ ≥ p̄_fc = max_x F⁻¹[k ĥ](x). Sinusoid of
    amplitude a, wavelength λ: p̄_fc = π E* a/λ = p* (Westergaard). On the grid the discrete transform is
    exact for the nodal problem GFMD solves.
    """
    from .kernels import halfplane_normal, wavevector_magnitudes

    h = np.asarray(h, float)
    if h.ndim == 2:
        q = wavevector_magnitudes(h.shape[0], length, h.shape[1], length_y)
        k = halfplane_normal(q, youngs_modulus, poisson_ratio)
        return float(np.max(np.fft.irfft2(k * np.fft.rfft2(h), s=h.shape)))
    q = 2 * np.pi * np.fft.rfftfreq(h.size, d=length / h.size)
    return float(np.max(np.fft.irfft(halfplane_normal(q, youngs_modulus, poisson_ratio) * np.fft.rfft(h),
                                     n=h.size)))


def check_force_path_below_full_contact(scene, h, realization=0):
    """Refuse (SceneError naming loading.path) a force path whose largest load a hard-wall half-plane
    realization cannot carry below full contact: max(path) ≥ p̄_fc (`full_contact_pressure`).

    Why it is exact before the run: on a half-plane δ is measured from the mean plane, so the hard wall is in
    full contact only at δ_max = mean(h) − min(h), where p̄(δ) reaches p̄_fc (below it some gap is open, p̄ <
    p̄_fc); every load ≥ p̄_fc needs δ_max, which the ramp does not reach (FULL_CONTACT_MARGIN), and
    `gfmd_contact.core.force` would refuse it while running. For a cohesive law no pre-run bound is known: the law's
    tension and its soft repulsion move p̄ at δ_max by amounts only the solution gives; the run-time refusal
    (`gfmd_contact.core.force.solve_load`) stays for every law, also for loads just below p̄_fc that need δ > 0.998 δ_max.
    A layer has no full-contact limit (its mean mode has a finite stiffness).
    """
    from .errors import SceneError

    lo = scene.loading
    if lo.control != "force" or not has_full_contact_limit(scene) or scene.interface.law != "hard-wall":
        return
    m = scene.material
    p_fc = full_contact_pressure(h, scene.surface.length, m.youngs_modulus, m.poisson_ratio,
                                 scene.surface.length_y if scene.surface.two_d else None)
    top = float(np.max(lo.path))
    if top >= p_fc:
        raise SceneError(
            f"loading.path: the largest load p̄ = {top:.6g} Pa is beyond full contact: {realization_label(scene, realization)} "
            f"is in full contact (hard wall on the half-plane) at p̄_fc = {p_fc:.6g} Pa (max of F⁻¹[E*|q|/2 ĥ], "
            f"gfmd_contact.core.loading.full_contact_pressure), reached only at δ_max = mean(h) − min(h), which the ramp does "
            f"not reach; lower the path's largest load below {p_fc:.6g} Pa")


def check_step_in_law_range(scene, steps, realization=0):
    """Refuse (SceneError naming loading.steps) a cohesive ramp that presses beyond the law's range.

    The cohesive law is evaluated for Δn ≥ −MAX_COMPRESSION δn only (`gfmd_contact.core.laws`: e^600 is finite,
    e^710 is not). A step starts from the last equilibrium, whose contact nodes sit within a few δn of
    Δn = 0, and lowers the indenter by ΔU = (δ0 + final)/steps; so the last step of a ramp that reaches
    δ_last > 0 (past the closest points) starts some node at Δn ≈ −min(ΔU, δ_last) or deeper. Beyond the
    range no method can evaluate that start, and every later step fails as well. `steps`: the
    displacements U this realization runs (`realization_steps`, cut at its own full-contact limit).
    Measured: verification/studies/length_normal_limit.py (data/length_normal_limit.json).
    """
    from .errors import SceneError
    from .laws import MAX_COMPRESSION

    if scene.interface.law != "cohesive" or not np.size(steps):
        return
    lo, dn, d0 = scene.loading, scene.interface.length_normal, scene.loading.initial_separation
    step = (d0 + lo.final_penetration) / lo.steps
    last = float(steps[-1]) - d0
    if last > 0 and min(step, last) > MAX_COMPRESSION * dn:
        need = int(np.ceil((d0 + lo.final_penetration) / (MAX_COMPRESSION * dn)))
        raise SceneError(
            f"loading.steps = {lo.steps}: a load step ΔU = (δ0 + final_penetration)/steps = {step:.3g} m is "
            f"{step / dn:.3g} δn (interface.length_normal = {dn:.3g} m), and {realization_label(scene, realization)} "
            f"is pressed to δ = {last / dn:.3g} δn: a step would press the surface beyond the cohesive law's range "
            f"Δn ≥ −{MAX_COMPRESSION:g} δn, where the exponential repulsion overflows, so no step in contact can be "
            f"solved. Use loading.steps ≥ {need}, or a larger interface.length_normal")


def start_warning(scene, model, min_gap):
    """Warning (str) if step 0 did not start out of contact on the stable branch, else None.

    min_gap: smallest normal gap Δn (m) of the relaxed step 0 (U = 0). With δ0 < δn the
    indenter starts on the rising branch of the law (in contact); with δ0 ≥ δn and a
    relaxed gap below δn (past the traction peak) the surface jumped into contact
    during the first relaxation.
    """
    law = law_from_scene(scene)
    if not law.adhesive:  # nothing to jump to, no rising branch to start on
        return None
    d0, dn = scene.loading.initial_separation, law.length_normal
    safe = max(law.jump_in_separation(softest_normal_stiffness(model)), 2 * dn)
    fix = f"raise loading.initial_separation to ≥ {safe / dn:.3g} δn = {safe:.3g} m"
    if d0 < dn:
        return (f"start in contact: loading.initial_separation δ0 = {d0 / dn:.3g} δn < δn puts the closest point on "
                f"the law's rising branch at step 0; the approach is not recorded: {fix}")
    if min_gap < dn:
        return (f"jump at start: the surface jumped into contact during step 0 (U = 0): smallest gap "
                f"{min_gap / dn:.3g} δn after relaxation, δ0 = {d0 / dn:.3g} δn; the approach and the jump are not "
                f"recorded: {fix}")
    return None


#: |Δt|/δt beyond which the coupled law (seed Eq. 2) is flagged under compression. Measured in
#: verification/test_fe_coupled.py: GFMD–FE agree (t_n ≤ 4e-4, N = 128) up to slip 2.0 δt; from
#: 2.2–3.2 δt the factor e^{−Δt²/δt²} collapses the repulsion, the body passes into the indenter
#: and the methods part (9e-3 at 3.0 δt, ν = 0.1; 9e-2 at 3.2 δt, ν = 0.3, N = 64).
SLIP_LIMIT = 2.5


def slip_warning(scene, step, delta, gap, u_x):
    """Warning (str) if the coupled law is in its slip regime at this step, else None.

    gap: normal gaps Δn (m); u_x: tangential displacements (m), Δt = −u_x. Flags nodes
    under compression (Δn < 0) with |Δt| > SLIP_LIMIT·δt, where Eq. 2's normal repulsion
    is scaled down by e^{−Δt²/δt²}: results there are set by the law, not verified.
    """
    law = law_from_scene(scene)
    if not law.tangential:  # the scene's law has no slip (hard wall, or c = 0)
        return None
    slip = np.abs(np.asarray(u_x)) / law.length_tangential
    bad = (np.asarray(gap) < 0) & (slip > SLIP_LIMIT)
    if not np.any(bad):
        return None
    return (f"coupled law in its slip regime from step {step} (δ = {delta:.4g} m): {int(bad.sum())} compressed "
            f"nodes slip |Δt| > {SLIP_LIMIT:g} δt (max {slip[bad].max():.3g} δt, min gap {np.min(gap):.3g} m); "
            f"Eq. 2 scales their repulsion by e^(−Δt²/δt²) ≤ {np.exp(-SLIP_LIMIT**2):.2g}, the body may pass into "
            "the indenter and GFMD–FE agreement is verified only to slip ≤ 2 δt (verification/test_fe_coupled.py)")


@dataclass
class RampState:
    """What the load ramp carries from one step to the next: enough to continue it exactly.

    step: the last completed step; current, previous: the method's unknowns of the last two
    converged steps (an array each: GFMD's rfft displacements, the FE's surface
    unknowns; the warm start extrapolates from them); slip_warned: the slip-regime
    warning has been given.
    """

    step: int
    current: np.ndarray
    previous: np.ndarray
    slip_warned: bool = False
