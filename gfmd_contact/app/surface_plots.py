"""Maps of a saved step of a 2+1-D run: the contact map and the pressure map.

Units: SI in, plotted in µm (positions) and units of E* (pressure). They stand in for the 1+1-D
interface snapshot (`gfmd_contact.app.plots`): a surface has no single cut to draw. The contact set is the
run's own rule (`gfmd_contact.core.observables.contact_mask` with the scene's law, as the curve's a_rel), the
pressure −t_n (compressive > 0, tension < 0 on an adhesive law).
"""

from __future__ import annotations

import numpy as np
from matplotlib.colors import ListedColormap, TwoSlopeNorm
from matplotlib.figure import Figure

from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.observables import contact_mask, patch_statistics

#: the figures a 2+1-D run draws instead of the interface snapshot
SURFACE_FIGURES = ("contact_map", "pressure_map")


def _extent(fields):
    """imshow extent (µm) with x horizontal, y vertical (arrays are (Nx, Ny): drawn transposed)."""
    x, y = fields["x"] * 1e6, fields["y"] * 1e6
    dx = (x[1] - x[0]) if x.size > 1 else 1.0
    dy = (y[1] - y[0]) if y.size > 1 else 1.0
    return (x[0] - dx / 2, x[-1] + dx / 2, y[0] - dy / 2, y[-1] + dy / 2)


def surface_maps(scene, fields, realization, step, delta, title_note=""):
    """{"contact_map": Figure, "pressure_map": Figure} of saved step `step` (δ = delta, m) of `realization`."""
    r, k = realization, step
    gap, t_n = fields[f"r{r}_s{k}_gap"], fields[f"r{r}_s{k}_t_n"]
    contact = np.asarray(contact_mask(law_from_scene(scene), gap, t_n), bool)
    s = scene.surface
    stats = patch_statistics(contact, s.length * s.length_y / (s.nodes * s.nodes_y),
                             periodic=s.boundary == "periodic")  # a free region's edges join nothing
    where = f"δ = {delta * 1e9:.2f} nm, realization {r}{title_note}"
    extent = _extent(fields)
    figs = {}
    fig = Figure(figsize=(5.6, 5.0), layout="constrained")
    ax = fig.subplots()
    ax.imshow(contact.T, origin="lower", extent=extent, cmap=ListedColormap(["white", "black"]), vmin=0, vmax=1,
              interpolation="nearest", gid="contact")
    area = stats["mean_patch_area"] * 1e12
    ax.set(xlabel=r"$x$ (µm)", ylabel=r"$y$ (µm)",
           title=f"Contact map at {where}\na_rel = {contact.mean():.4g}, {stats['patches']} patches"
                 + (f", mean area {area:.3g} µm²" if stats["patches"] else ""))
    figs["contact_map"] = fig
    fig = Figure(figsize=(6.2, 5.0), layout="constrained")
    ax = fig.subplots()
    p = -np.asarray(t_n, float) / scene.material.contact_modulus
    lo, hi = float(np.nanmin(p)), float(np.nanmax(p))
    norm = TwoSlopeNorm(0.0, min(lo, -1e-30), max(hi, 1e-30))  # white at p = 0, tension blue, pressure red
    im = ax.imshow(p.T, origin="lower", extent=extent, cmap="RdBu_r", norm=norm, interpolation="nearest",
                   gid="pressure")
    fig.colorbar(im, ax=ax, label=r"local pressure $-t_n/E^*$")
    ax.set(xlabel=r"$x$ (µm)", ylabel=r"$y$ (µm)", title=f"Pressure map at {where}")
    figs["pressure_map"] = fig
    return figs
