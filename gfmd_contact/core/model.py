"""Model choice: only what a scene requires (unknowns, kernel, law), and why.

Units: SI (see `gfmd_contact.core.conventions`). `build_model(scene)` returns a `Model`
holding the Fourier-space stiffness on the rfft half-spectrum and a
human-readable statement of the model solved, with the reasons.

Rules
-----
* Tangential unknowns u_x only if the law needs them (`needs_tangential` of the law
  object, `gfmd_contact.core.laws`): the coupled cohesive law with c = φt*/φn* > 0 *and* a kernel
  that couples normal and tangential motion (half-plane: ν < 1/2; bonded layer:
  always). Otherwise u_x ≡ 0 solves the tangential equations
  exactly (T_t(Δt = 0) = 0, and with c = 0 no tangential traction exists),
  and the normal problem uses the effective normal stiffness 1/G_zz.
* Half-plane (thickness "inf"): q = 0 clamped. Layer: bonded-base kernel with
  its q = 0 stiffness (reference-formulas §1.3, §1.5).
* Hard wall: a constraint Δn ≥ 0 (projection), no CZ parameters used.
* `solver.unknowns = "coupled"` forces u_x and u_z (coupled kernel) even where the
  rules above would drop u_x (c = 0, or ν = 1/2 on a half-plane): the reduced model
  can then be compared with the full one (verification/test_reduced_models.py).
  The hard wall is always normal-only (frictionless: no tangential equations).
  With c = 0 the full model runs the coupled law (seed Eq. 2) with φt = 0, whose T_n
  still carries exp(−Δt²/δt²), so it differs from Eq. 3 by that factor (measured
  2.7e-4 E*ḡ at ν = 0.45, 2.7e-3 at ν = 0.3); at ν = 1/2 the reduction is exact.

Checks (`scene_warnings`): a scene with an adhesive law is checked before any work for

* resolution of the cohesive length, δn ≥ MIN_LENGTH_NORMAL_NODES·l (l = L/N);
* a start inside the jump-in range, δ0 < δ_jump (the law's `jump_in_separation`);
* resolution of the process zone, l_pz = E* w/σ_max² ≥ a measured limit in nodes
  (`gfmd_contact.core.stickiness.resolution_warnings`; the limit: verification/data/process_zone.json).

They are warnings by default (`solver.checks = "warn"`): the model's reasons carry
them (printed by the CLI, written to meta.json, tagged in the description) and the
run goes on, since convergence studies deliberately run coarse grids.
`solver.checks = "error"` refuses such a scene with a `ModelCheckError` instead.

Resolution threshold, measured (self-affine profile, H = 0.8, h_rms = 4 nm,
L = 256 nm, λr = 64 nm, ν = 0.45, δn = 1 nm, δ0 = 8 nm, δ from −8 to 4 nm in 24
steps; the same continuum profile sampled on N = 64 … 4096 nodes, N = 4096 as the
reference). Max over the steps of |Δa_rel| and of |Δp|/max|p|:

    δn/l                    0.25    0.5     1       2       4       8
    φn* = 0.15, λs = 8 nm
      |Δa_rel|              0.037   0.033   0.018   0.0044  0.0020  0.0010
      |Δp|/max|p|           0.44    0.029   0.035   0.0022  0.0022  <1e-4
    φn* = 0.01, λs = 8 nm
      |Δa_rel|              0.037   0.032   0.019   0.0056  0.0020  0.0010
      |Δp|/max|p|           0.12    0.027   0.028   0.0018  0.0018  <1e-4
    φn* = 0.15, λs = 32 nm (smoother: ḡ = 0.38 instead of 0.61)
      |Δa_rel|              0.024   0.011   0.0046  0.0027  0.0017  0.0005
      |Δp|/max|p|           0.0061  0.012   0.0035  0.0006  0.0003  <1e-4
    φn* = 0.01, λs = 32 nm
      |Δa_rel|              0.027   0.011   0.0073  0.0024  0.0017  0.0007
      |Δp|/max|p|           0.015   0.015   0.0044  0.0007  0.0004  <1e-4

From δn = 2 l on, every case has |Δp|/max|p| ≤ 0.22 % and |Δa_rel| ≤ 0.006 (about
three nodes of N = 512 at the contact edges); below it the pressure error grows to
0.4–3.5 % (the steps at which asperities jump into contact move), the size depending
on the profile (λs/l) as much as on δn/l. Hence MIN_LENGTH_NORMAL_NODES = 2, and a
warning rather than a refusal: how wrong a coarser grid is depends on the scene.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from . import kernels, memo, stickiness
from .laws import jump_in_separation, law_from_scene  # noqa: F401 (jump_in_separation: kept importable here)
from .observables import rms_gradient

#: smallest δn/l (cohesive length in node spacings) that counts as resolved (module docstring)
MIN_LENGTH_NORMAL_NODES = 2.0
#: prefix of the warnings among a model's / result's reasons
WARNING = "WARNING: "


class ModelCheckError(ValueError):
    """A scene fails a resolution/stability check and `solver.checks = "error"`."""


@dataclass(frozen=True)
class Model:
    nodes: int
    length: float
    law: object  # the law object solved (gfmd_contact.core.laws: HardWall, NormalCohesive or CoupledCohesive)
    tangential: bool  # u_x solved?
    half_plane: bool  # q = 0 clamped?
    q: np.ndarray  # rfft wavenumbers (1/m)
    k_xx: np.ndarray | None  # Pa/m, complex, None when normal-only
    k_xz: np.ndarray | None
    k_zz: np.ndarray  # Pa/m (effective normal stiffness when normal-only)
    contact_modulus: float  # E* (Pa)
    reference_traction: float  # residual scale p_ref (Pa)
    description: str
    reasons: tuple[str, ...] = field(default=())
    warnings: tuple[str, ...] = field(default=())  # the check findings, also among `reasons`
    # 2+1-D surfaces: shape = (Nx, Ny), nodes = Nx·Ny, length = Lx, length_y = Ly, q = |q| of shape
    # (Nx, Ny//2 + 1) (`gfmd_contact.core.kernels.wavevector_magnitudes`); () for a 1+1-D profile
    shape: tuple = field(default=())
    length_y: float = 0.0
    # surface.boundary = "free": the region's grid (N,) or (Nx, Ny) inside the padded cell the fields above
    # describe (`gfmd_contact.core.free_boundary`); () for a periodic cell
    region: tuple = field(default=())

    @property
    def components(self):
        """Number of displacement components solved (1: z; 2: x, z)."""
        return 2 if self.tangential else 1

    @property
    def grid(self):
        """Shape of a real surface field: (N,) for a profile (1+1-D), (Nx, Ny) for a surface (2+1-D)."""
        return tuple(self.shape) if self.shape else (self.nodes,)

    @property
    def spectrum_shape(self):
        """Shape of its rfft (1-D) / rfft2 (2-D, over the last two axes) half-spectrum, = q.shape."""
        g = self.grid
        return g[:-1] + (g[-1] // 2 + 1,)

    @property
    def free(self):
        """True for a free (non-periodic) body: the grid is the padded cell, `region` the scene's nodes."""
        return bool(self.region)

    @property
    def node_area(self):
        """Length (1+1-D, m) or area (2+1-D, m²) per node: L/N or Lx Ly/(Nx Ny)."""
        return self.length / self.nodes if not self.shape else self.length * self.length_y / self.nodes


def build_model(scene, h=None):
    """Choose and assemble the model for `scene`; `h` (m) sets the residual scale.

    reference_traction p_ref = E* ḡ (ḡ of the profile, seed Eq. 5–6), the scale of
    contact pressures in full contact; for a flat profile the law's `reference_traction`:
    its peak traction φn/(e δn) (cohesive) or E* (hard wall).

    Model.law is the law object as solved on the chosen unknowns (`gfmd_contact.core.laws.law_from_scene`
    with tangential = Model.tangential): Eq. 2 where u_x is solved, else Eq. 3 or the hard wall.
    The choice (law, unknowns, kernels, checks) is made once per scene object (`chosen_model`); only
    p_ref follows h.
    """
    model = chosen_model(scene)
    s = scene.surface
    g = rms_gradient(h, s.spacings if s.two_d else s.spacing, s.boundary == "periodic") if h is not None else 0.0
    return dataclasses.replace(model, reference_traction=model.contact_modulus * g) if g > 0 else model


#: the model chosen for the scene asked for last (its kernels are large: one scene's at a time)
_CHOSEN = memo.LastOwner()


def chosen_model(scene):
    """The model `build_model` returns for a flat profile (p_ref the law's), chosen once per scene object;
    its arrays are read-only, as every realization shares them."""
    return _CHOSEN.get(scene, "model", lambda: _read_only(choose_model(scene)))


def _read_only(model):
    for value in (model.q, model.k_xx, model.k_xz, model.k_zz):
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    return model


def choose_model(scene):
    """`chosen_model` made anew: the unknowns, kernels and checks of `scene` (1+1-D or 2+1-D); on a free boundary
    the periodic model's law and unknowns on the padded cell (`gfmd_contact.core.free_boundary.padded_model`)."""
    if scene.surface.boundary == "free":
        from .free_boundary import padded_model

        padded = padded_model(scene, _periodic_model(scene))
        return _checked(scene, padded, padded.description)
    return _periodic_model(scene)


def _periodic_model(scene):
    """The model of the periodic cell of `scene`'s nodes."""
    s, m, i = scene.surface, scene.material, scene.interface
    if s.two_d:
        return _build_model_2d(scene)
    n, length = s.nodes, s.length
    q = kernels.wavenumbers(n, length)
    e, nu, thick = m.youngs_modulus, m.poisson_ratio, m.thickness
    half_plane = m.half_plane
    reasons = []
    law = law_from_scene(scene)
    if scene.solver.unknowns == "coupled":  # a method choice (the scene refuses it for a hard wall)
        tangential = True
        reasons.append(f"solver.unknowns = coupled: u_x and u_z solved although c = {i.tangential_ratio:g}, "
                       f"ν = {nu:g} would allow the normal-only model (full model, for comparison)")
        note = law.forced_tangential_reason()
        if note:
            reasons.append(note)
    else:
        tangential = law.needs_tangential(m)
        reasons.append(law.tangential_reason(m))
    solved = law_from_scene(scene, tangential=tangential)
    if half_plane:
        reasons.append("thickness = inf: half-plane kernel, mean displacement clamped (δ from the mean plane)")
        if tangential:
            k_xx, k_xz, k_zz = kernels.halfplane_coupled(q, e, nu, nodes=n)
        else:
            k_xx = k_xz = None
            k_zz = kernels.halfplane_normal(q, e, nu)
    else:
        reasons.append(f"thickness = {thick:g} m: layer on a bonded rigid base, q = 0 stiffness M/D")
        if tangential:
            k_xx, k_xz, k_zz = kernels.layer_coupled(q, e, nu, thick, nodes=n)
        else:
            k_xx = k_xz = None
            k_zz = kernels.layer_normal(q, e, nu, thick)
    e_star = m.contact_modulus
    p_ref = solved.reference_traction(e_star)
    body = "half-plane" if half_plane else f"layer D = {thick:g} m"
    unknowns = "u_x, u_z" if tangential else "u_z"
    description = f"{solved.name}, {body}, {n} nodes, unknowns {unknowns}"
    model = Model(nodes=n, length=length, law=solved, tangential=tangential, half_plane=half_plane, q=q,
                  k_xx=k_xx, k_xz=k_xz, k_zz=np.asarray(k_zz), contact_modulus=e_star, reference_traction=p_ref,
                  description=description, reasons=tuple(reasons))
    return _checked(scene, model, description)


def _build_model_2d(scene):
    """The 2+1-D model: normal-only, K_zz of `halfplane_normal` / `layer_normal` at |q| of the
    rfft2 half-spectrum (`kernels.wavevector_magnitudes`); the scene has refused laws that need u_x."""
    s, m = scene.surface, scene.material
    nx, ny = s.nodes, s.nodes_y
    q = kernels.wavevector_magnitudes(nx, s.length, ny, s.length_y)
    e, nu, thick = m.youngs_modulus, m.poisson_ratio, m.thickness
    solved = law_from_scene(scene, tangential=False)
    reasons = [f"2+1-D surface {nx} × {ny} nodes on {s.length:g} × {s.length_y:g} m: normal-only (u_z), the "
               "plane-strain normal kernel along q at |q| (gfmd_contact.core.kernels.wavevector_magnitudes)",
               solved.tangential_reason(m)]
    if m.half_plane:
        reasons.append("thickness = inf: half-space kernel, mean displacement clamped (δ from the mean plane)")
        k_zz = kernels.halfplane_normal(q, e, nu)
    else:
        reasons.append(f"thickness = {thick:g} m: layer on a bonded rigid base, q = 0 stiffness M/D")
        k_zz = kernels.layer_normal(q, e, nu, thick)
    e_star = m.contact_modulus
    p_ref = solved.reference_traction(e_star)
    body = "half-space" if m.half_plane else f"layer D = {thick:g} m"
    description = f"{solved.name}, {body}, {nx} × {ny} nodes, unknowns u_z"
    model = Model(nodes=nx * ny, length=s.length, law=solved, tangential=False, half_plane=m.half_plane, q=q,
                  k_xx=None, k_xz=None, k_zz=np.asarray(k_zz), contact_modulus=e_star, reference_traction=p_ref,
                  description=description, reasons=tuple(reasons), shape=(nx, ny), length_y=s.length_y)
    return _checked(scene, model, description)


def _checked(scene, model, description):
    """The model with the findings of `scene_warnings` among its reasons, or ModelCheckError (checks = error)."""
    found = scene_warnings(scene, model)
    if found and scene.solver.checks == "error":
        raise ModelCheckError("scene refused (solver.checks = \"error\"): " + " | ".join(found))
    if found:
        tags = ", ".join(f.split(":")[0] for f in found)
        model = dataclasses.replace(model, description=f"{description} [{WARNING.strip()} {tags}]",
                                    reasons=model.reasons + tuple(WARNING + f for f in found),
                                    warnings=tuple(found))
    return model


def warnings_in(reasons):
    """The warnings (without the WARNING prefix) among a model's or a result's reasons."""
    return [r[len(WARNING):] for r in reasons if r.startswith(WARNING)]


def softest_normal_stiffness(model):
    """k_min (Pa/m): the smallest normal stiffness of any surface mode the solver moves.

    Normal-only: min K_zz(q); coupled: the normal Schur complement K_zz − |K_xz|²/K_xx
    (u_x free), which is softer. Half-plane: q = 0 is clamped, so k_min = k(q_1),
    = πE*/L for the frictionless kernel; layer: the uniform mode M/D is included.
    """
    k = np.asarray(model.k_zz, complex).real.copy()
    if model.tangential:
        k_xx = np.asarray(model.k_xx).real
        ok = k_xx > 0
        k[ok] -= np.abs(model.k_xz[ok]) ** 2 / k_xx[ok]
    if model.half_plane:
        k = k.ravel()[1:]  # q = 0 is the first entry of the rfft (1+1-D) and of the rfft2 (2+1-D) layout
    return float(np.min(k))


def scene_warnings(scene, model):
    """Resolution / stability findings of a scene (list of messages; empty when none).

    Each message starts with a short tag ("under-resolved δn", "unstable start")
    followed by a colon, names the values, and says how to fix it.
    """
    law, s = model.law, scene.surface
    if not law.adhesive:  # nothing attracts the surface, and no cohesive length to resolve
        return []
    found = []
    dn = law.length_normal
    spacing, key, length = s.spacing, "surface.nodes", s.length
    if s.two_d and s.spacings[1] > spacing:  # 2+1-D: δn must be resolved along both axes, the coarser one counts
        spacing, key, length = s.spacings[1], "surface.nodes_y", s.length_y
    ratio = dn / spacing
    if ratio < MIN_LENGTH_NORMAL_NODES:
        nodes = int(2 ** np.ceil(np.log2(MIN_LENGTH_NORMAL_NODES * length / dn)))
        found.append(
            f"under-resolved δn: cohesive length δn = {ratio:.3g} l is under-resolved (l = L/N = {spacing:.3g} m, "
            f"δn = {dn:.3g} m): refine to δn ≥ {MIN_LENGTH_NORMAL_NODES:g} l, e.g. {key} = "
            f"{nodes} (measured on a rough scene: pressure error ≈ 3 % at δn = l against 0.2 % at δn = 2 l, "
            "gfmd_contact.core.model docstring)")
    k_min = softest_normal_stiffness(model)
    gap = law.jump_in_separation(k_min)
    d0 = scene.loading.initial_separation
    if d0 < gap:
        mode = "half-plane: longest wave, k(2π/L)" if model.half_plane else "layer: min over q, uniform mode M/D included"
        found.append(
            f"unstable start: loading.initial_separation δ0 = {d0 / dn:.3g} δn lies inside the jump-in "
            f"range: the softest surface mode ({mode}, k = {k_min:.3g} Pa/m) is softer than the law's steepest "
            f"softening slope e^-2 φn/δn² = {law.steepest_softening:.3g} Pa/m: a flat surface "
            f"jumps into contact from δ_jump = {gap / dn:.3g} δn, so the first step may already jump "
            f"(the approach is then not recorded). Pick δ0 ≥ {gap / dn:.3g} δn = {gap:.3g} m "
            "(gfmd_contact.core.model.jump_in_separation)")
    found += coarse_unloading_warnings(scene, dn)
    found += stickiness.resolution_warnings(scene)
    return found


#: largest unloading step Δδ/δn of a displacement-controlled path measured to follow the attached branch
#: (verification/studies/cycle_convergence.py, sticky rough cycle φn* = 0.15, δn = 0.25 nm, N = 2048: an
#: unloading step of δn/5 follows it to snap-off at −2.3 nm; one of 2 δn leaves it at the first unloading
#: step, every step converged, W < 0: a wrong cycle no residual shows)
MAX_UNLOADING_STEP_LENGTHS = 0.2


def coarse_unloading_warnings(scene, dn):
    """["coarse unloading: …"] for a displacement path whose unloading steps exceed MAX_UNLOADING_STEP_LENGTHS δn."""
    ld = scene.loading
    if not ld.path or ld.control != "displacement":
        return []
    steps = [abs(b - a) / n for a, b, n in zip(ld.path[:-1], ld.path[1:], ld.segment_steps) if b < a]
    if not steps or max(steps) <= MAX_UNLOADING_STEP_LENGTHS * dn * (1 + 1e-9):  # the measured step itself,
        return []  # recomputed from other corners, passes whatever its last bits
    worst = max(steps)
    return [f"coarse unloading: an unloading step of loading.path is Δδ = {worst / dn:.3g} δn ({worst:.3g} m), above "
            f"{MAX_UNLOADING_STEP_LENGTHS:g} δn, the largest measured to follow the attached branch: a coarser step "
            "may leave it at once (every step converged, hysteresis W < 0; verification/studies/cycle_convergence.py); "
            f"raise loading.steps of the unloading segments to ≥ Δδ/({MAX_UNLOADING_STEP_LENGTHS:g} δn)"]
