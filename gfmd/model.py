"""Model choice: only what a scene requires (unknowns, kernel, law), and why.

Units: SI (see `gfmd.conventions`). `build_model(scene)` returns a `Model`
holding the Fourier-space stiffness on the rfft half-spectrum and a
human-readable statement of the model solved, with the reasons.

Rules
-----
* Tangential unknowns u_x only if the law is cohesive with c = φt*/φn* > 0
  *and* the kernel couples normal and tangential motion (half-plane: ν < 1/2;
  bonded layer: always). Otherwise u_x ≡ 0 solves the tangential equations
  exactly (T_t(Δt = 0) = 0, and with c = 0 no tangential traction exists),
  and the normal problem uses the effective normal stiffness 1/G_zz.
* Half-plane (thickness "inf"): q = 0 clamped. Layer: bonded-base kernel with
  its q = 0 stiffness (reference-formulas §1.3, §1.5).
* Hard wall: a constraint Δn ≥ 0 (projection), no CZ parameters used.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import kernels
from .observables import rms_gradient


@dataclass(frozen=True)
class Model:
    nodes: int
    length: float
    law: str  # "hard-wall" | "cohesive"
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

    @property
    def components(self):
        """Number of displacement components solved (1: z; 2: x, z)."""
        return 2 if self.tangential else 1


def build_model(scene, h=None):
    """Choose and assemble the model for `scene`; `h` (m) sets the residual scale.

    reference_traction p_ref = E* ḡ (ḡ of the profile, seed Eq. 5–6), the scale of
    contact pressures in full contact; for a flat profile the law's peak traction
    φn/(e δn) (cohesive) or E* (hard wall).
    """
    s, m, i = scene.surface, scene.material, scene.interface
    n, length = s.nodes, s.length
    q = kernels.wavenumbers(n, length)
    e, nu, thick = m.youngs_modulus, m.poisson_ratio, m.thickness
    half_plane = m.half_plane
    reasons = []
    if i.law == "hard-wall":
        tangential = False
        reasons.append("hard wall: frictionless, no tangential traction, CZ parameters unused")
    elif i.tangential_ratio == 0:
        tangential = False
        reasons.append("c = φt*/φn* = 0: no tangential traction, u_x decouples (normal-only CZ, seed Eq. 3)")
    elif half_plane and nu == 0.5:
        tangential = False
        reasons.append("ν = 0.5 half-plane: kernel uncoupled, u_x ≡ 0 is exact (T_t(Δt=0) = 0)")
    else:
        tangential = True
        reasons.append(f"c = {i.tangential_ratio:g} > 0 and ν = {nu:g} couples u_x and u_z: coupled CZ (seed Eq. 2)")
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
    g = rms_gradient(h, s.spacing) if h is not None else 0.0
    if g > 0:
        p_ref = e_star * g
    elif i.law == "cohesive":
        p_ref = i.work_normal / (np.e * i.length_normal)
    else:
        p_ref = e_star
    law_text = {"hard-wall": "hard wall", "cohesive": "coupled CZ" if tangential else "normal-only CZ"}[i.law]
    body = "half-plane" if half_plane else f"layer D = {thick:g} m"
    unknowns = "u_x, u_z" if tangential else "u_z"
    description = f"{law_text}, {body}, {n} nodes, unknowns {unknowns}"
    return Model(nodes=n, length=length, law=i.law, tangential=tangential, half_plane=half_plane, q=q,
                 k_xx=k_xx, k_xz=k_xz, k_zz=np.asarray(k_zz), contact_modulus=e_star, reference_traction=p_ref,
                 description=description, reasons=tuple(reasons))
