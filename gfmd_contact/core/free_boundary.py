"""A free (non-periodic) boundary: the scene's N nodes as a region of a padded periodic cell (Hockney).

Units: SI (see `gfmd_contact.core.conventions`). `padded_model` turns the periodic model of a scene with
`surface.boundary = "free"` into the model solved: the padded cell of 2N nodes per axis (twice the length),
the stiffness K_c = 1/Ĝ_c of the free body's circulant compliance (2×2 with tangential unknowns,
`gfmd_contact.core.free_kernels`), the q = 0 mode clamped as on the periodic half-plane, the law and unknowns
of the periodic model. The region is the padded cell's first N nodes per axis. The indenter exists only above the region: outside it the
method raises the indenter surface by `far_gap` (`padded_indenter`), a gap at which the law's
tractions, tangent and potential are exactly 0.0 (probed, so exact for every law in double precision;
the hard wall is never reached there; probed at Δt = 0, every law's tractions there carrying the vanishing
normal factor), and checks after each solve that no traction, normal or tangential, acted outside
(`outside_traction`). Results are the region's: `crop`. Design note: docs/design/free_boundary.md.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from . import free_kernels
from .errors import SceneError

#: the probe gaps of `far_gap`, in units of the law's length scale: 2^0 … 2^MAX_DOUBLINGS
MAX_DOUBLINGS = 1000
#: `far_gap`'s gap is exactly zero for the law there and at the next ZERO_RUN probes (2^10 = 1024× further)
ZERO_RUN = 10


def refusal(scene):
    """Why a free boundary cannot be solved for `scene` (a str naming the key), or None."""
    if not scene.material.half_plane:
        return (f"surface.boundary = \"free\" with material.thickness = {scene.material.thickness:g} m: the free "
                "boundary is the unbounded half-plane / half-space (Hockney padding of its Green's function); a "
                "finite layer has no free-surface kernel here: give material.thickness = \"inf\" or "
                "surface.boundary = \"periodic\"")
    return None


def _kernels(scene, model, spacings):
    """(k_xx, k_xz, k_zz) of the padded cell: normal-only (None, None, K_c) or the coupled 1+1-D kernel."""
    if not model.tangential:
        return None, None, free_kernels.padded_stiffness(model.grid, spacings, model.contact_modulus)
    nu = scene.material.poisson_ratio
    try:
        return free_kernels.padded_coupled_stiffness(model.nodes, spacings[0], model.contact_modulus,
                                                     (1 - 2 * nu) / (2 * (1 - nu)))
    except ValueError as exc:
        raise SceneError(f"surface.boundary = \"free\" with tangential unknowns and material.poisson_ratio = {nu:g}: "
                         f"{exc} (the odd normal–tangential coupling of an auxetic body, β > 1/2, breaks it on the "
                         "2N padding); use ν ≥ 0, interface.tangential_ratio = 0, or surface.boundary = "
                         "\"periodic\"") from exc


def region_slices(region):
    """The index of the region (its first N nodes per axis) in a padded field (…, 2N) / (…, 2Nx, 2Ny)."""
    return (Ellipsis,) + tuple(slice(0, n) for n in region)


def crop(field, region):
    """The region's values of a padded field (None stays None)."""
    return None if field is None else np.asarray(field)[region_slices(region)]


def padded_model(scene, model):
    """The free-boundary model of `scene` from its periodic `model` (law, unknowns, E*): the padded cell's grid
    and kernel, `region` the scene's grid, without the periodic model's check findings (`gfmd_contact.core.model`
    checks the padded model anew). SceneError (`refusal`) if not solvable."""
    why = refusal(scene)
    if why:
        raise SceneError(why)
    s = scene.surface
    region = model.grid
    grid = free_kernels.padded_grid(region)
    spacings = s.spacings if s.two_d else (s.spacing,)
    k_xx, k_xz, k_zz = _kernels(scene, model, spacings)
    n_text = " × ".join(str(n) for n in region)
    p_text = " × ".join(str(n) for n in grid)
    reason = (f"surface.boundary = free: free boundary (Hockney padding to 2N): the {n_text} nodes are the region of "
              f"a {p_text} padded cell whose kernel K_c = 1/Ĝ_c is the free body's exact nodal compliance "
              "(gfmd_contact.core.free_kernels); the indenter acts on the region only "
              "(gfmd_contact.core.free_boundary); "
              "δ is measured from the padded cell's mean plane, the far-field shift s is in the diagnostics")
    description = model.description.split(" [")[0] + ", free boundary (Hockney padding to 2N)"
    q = free_kernels.padded_wavenumbers(grid, spacings)
    padded = dataclasses.replace(
        model, nodes=int(np.prod(grid)), length=2 * model.length, length_y=2 * model.length_y,
        shape=grid if model.shape else (), q=q, k_xx=k_xx, k_xz=k_xz, k_zz=k_zz, region=region,
        description=description,
        reasons=tuple(r for r in model.reasons if not any(r.endswith(w) for w in model.warnings)) + (reason,),
        warnings=())
    return padded


def far_gap(law, scale):
    """The gap (m) beyond which `law`'s tractions, tangent and potential are exactly 0.0, plus `scale` (m): the
    indenter's height above its region's highest point outside the region. The hard wall: `scale` alone (a
    wall is never reached that far above). ValueError for a law that never vanishes exactly within
    2^MAX_DOUBLINGS length scales."""
    if law.constraint and not law.adhesive:
        return scale
    gaps = float(law.length_scale) * 2.0 ** np.arange(MAX_DOUBLINGS + 1, dtype=float)
    gaps = gaps[np.isfinite(gaps)]
    with np.errstate(all="ignore"):
        t_n, t_t = law.tractions(gaps, np.zeros_like(gaps))
        values = [t_n, t_t, *law.tangent(gaps, np.zeros_like(gaps))]
        if law.has_potential:
            values.append(law.potential(gaps))
    zero = np.ones(gaps.shape, bool)
    for v in values:
        zero &= np.broadcast_to(np.asarray(v, float), gaps.shape) == 0.0
    # zero here and over the next ZERO_RUN doublings (the tail beyond the far reach falls monotonically; far
    # beyond, a law's formula may overflow, which no gap of a solve reaches)
    run = np.convolve(zero, np.ones(ZERO_RUN + 1, int), mode="valid") == ZERO_RUN + 1
    if not run.any():
        raise ValueError(f"surface.boundary = \"free\": the law {law.name!r} does not vanish exactly at any gap up to "
                         f"{gaps[-1]:.3g} m, so the indenter cannot be removed outside the region")
    return float(gaps[int(np.argmax(run))]) + scale


def padded_indenter(z_region, region, far):
    """The padded indenter surface: z_region on the region, max(z_region) + far (m) everywhere else."""
    z = np.full(free_kernels.padded_grid(region), float(np.max(z_region)) + far)
    z[region_slices(region)] = z_region
    return z


def outside_traction(t_padded, region):
    """max |t| (Pa) outside the region of a padded traction field (0.0 when the indenter acted on the region only)."""
    outside = np.ones(np.shape(t_padded)[-len(region):], bool)
    outside[region_slices(region)] = False
    t = np.asarray(t_padded)[..., outside]
    return float(np.max(np.abs(t))) if t.size else 0.0


def far_field_shift(model, t_padded):
    """s (m): u_free = u + s on the region, from the mean traction over the padded cell
    (`gfmd_contact.core.free_kernels.far_field_shift`)."""
    spacings = (model.length / model.shape[0], model.length_y / model.shape[1]) if model.shape else \
        (model.length / model.nodes,)
    return free_kernels.far_field_shift(model.region, spacings, model.contact_modulus, float(np.mean(t_padded)))
