"""Statistics of a prepared measured topography, as `gfmd scene --check` prints them for a file scene.

Units: SI (see `gfmd_contact.core.conventions`). On the prepared measured heights z (the file after every
[surface] preparation key, before surface.facing turns it), node spacing l per axis:

* h_rms: the root mean square of z about its mean;
* rms slope: (⟨(∂z/∂x)²⟩ + ⟨(∂z/∂y)²⟩)^½ from forward differences between neighbouring nodes of the scan
  (not across the periodic seam, where a measured scan's edges need not meet); a map's also per axis, the
  slope along x and along y (scan lines show as a larger slope across them);
* rms curvature: the rms of z'' (a line scan) or of ½∇²z (a map, the mean curvature) from central second
  differences on the interior nodes;
* the wavelengths the grid holds, from 2l (Nyquist) to the cell's size L per axis;
* the grid spacing against the process zone l_pz = E* w/σ_max² of an adhesive law
  (`gfmd_contact.core.stickiness`), which the grid must resolve.
"""

from __future__ import annotations

import numpy as np

from .laws import law_from_scene
from .stickiness import measured_process_zone_limit, process_zone_size
from .topography_prep import prepare, surface_lengths


def statistics(z, sizes):
    """{"h_rms", "rms_slope", "rms_slopes" (per axis), "rms_curvature" (1/m), "spacings" (m), "wavelengths"
    ((shortest, longest) m)}."""
    z = np.asarray(z, dtype=float)
    spacings = tuple(size / n for size, n in zip(sizes, z.shape))
    slopes2 = [np.mean((np.diff(z, axis=a) / l) ** 2) for a, l in enumerate(spacings)]
    second = [(np.diff(z, n=2, axis=a) / l**2) for a, l in enumerate(spacings)]
    if z.ndim == 1:
        curvature = second[0]
    else:
        curvature = 0.5 * (second[0][:, 1:-1] + second[1][1:-1, :])
    return {"h_rms": float(np.std(z)), "rms_slope": float(np.sqrt(sum(slopes2))),
            "rms_slopes": tuple(float(np.sqrt(v)) for v in slopes2),
            "rms_curvature": float(np.sqrt(np.mean(curvature**2))), "spacings": spacings,
            "wavelengths": (2 * max(spacings), max(sizes))}


def prepared_file(scene):
    """The `gfmd_contact.core.topography_prep.Prepared` file of a file scene (one read for the check's lines and
    figure)."""
    return prepare(scene.surface, surface_lengths(scene.surface))


def check_lines(scene, prepared):
    """Lines of `gfmd scene --check` on a file scene: what was read, the prepared statistics, l against l_pz."""
    s = scene.surface
    m = prepared.measurement
    st = statistics(prepared.heights, prepared.sizes)
    grid = " × ".join(map(str, m.heights.shape))
    out = [f"read {s.path}: {grid} points over {' × '.join(f'{v:.6g}' for v in m.sizes)} m"
           + (" (surface.length)" if not m.size_stated else "") + f", heights in {m.unit}"
           + (f", channel {m.channel!r}" if m.channel else ""),
           f"prepared: region {list(s.region) or 'whole file'}, undefined {s.undefined}, line {s.line}, "
           f"height_scale {s.height_scale:g}, {_line_levelling(s)}levelling {s.levelling}, resample {s.resample}, "
           f"facing {s.facing} "
           f"→ {' × '.join(map(str, s.shape))} nodes",
           f"h_rms = {st['h_rms']:.4g} m, rms slope = {st['rms_slope']:.4g}{_per_axis(st)}, rms curvature = "
           f"{st['rms_curvature']:.4g} 1/m",
           f"PSD wavelengths from {st['wavelengths'][0]:.6g} m (2l) to {st['wavelengths'][1]:.6g} m (L)"]
    return out + [_process_zone_line(scene, max(st["spacings"]))]


def _per_axis(st):
    """A map's rms slope along x and along y, in words; "" for a line scan."""
    if len(st["rms_slopes"]) == 1:
        return ""
    return " (along x {:.4g}, along y {:.4g})".format(*st["rms_slopes"])


def _line_levelling(s):
    """The prepared line's words for surface.line_levelling (a map's only: a profile refuses the key)."""
    if not s.two_d:
        return ""
    along = f" (scan lines along {s.scan_axis})" if s.line_levelling != "none" else ""
    return f"line_levelling {s.line_levelling}{along}, "


def _process_zone_line(scene, spacing):
    law = law_from_scene(scene)
    if not law.adhesive:
        return f"grid spacing l = {spacing:.4g} m; interface.law = {scene.interface.law!r} has no process zone"
    lpz = process_zone_size(scene.material.contact_modulus, law.work_of_adhesion, law.peak_traction)
    limit, _ = measured_process_zone_limit()
    verdict = "resolved" if lpz / spacing >= limit else f"UNDER-RESOLVED (needs l_pz/l ≥ {limit:.3g})"
    return (f"grid spacing l = {spacing:.4g} m against the process zone l_pz = E* w/σ_max² = {lpz:.4g} m: "
            f"l_pz/l = {lpz / spacing:.3g}, {verdict}")
