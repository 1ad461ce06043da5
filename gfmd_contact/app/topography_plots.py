"""The figure `gfmd scene --check` writes for a file scene: the prepared measured topography and its PSD.

Units: SI in, plotted in µm (positions), nm (heights) and 1/m (wavevectors). The heights are the measured
surface z after the [surface] preparation keys (before surface.facing turns it: summits up). The PSD is the
periodogram of the prepared cell, C(q) = l^d/N |FFT(z − ⟨z⟩)|² (m³ for a line scan, m⁴ for a map), a map's
averaged over rings of |q|; its shape, not a calibrated spectrum of a non-periodic scan.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure


def periodogram(z, sizes):
    """(q (1/m), C(q)) of the prepared heights `z` over `sizes` (module docstring); q > 0 only."""
    z = np.asarray(z, dtype=float) - np.mean(z)
    spacings = [size / n for size, n in zip(sizes, z.shape)]
    power = np.abs(np.fft.fftn(z)) ** 2 * np.prod(spacings) / z.size
    axes = [2 * np.pi * np.fft.fftfreq(n, d=l) for n, l in zip(z.shape, spacings)]
    q = np.sqrt(sum(g**2 for g in np.meshgrid(*axes, indexing="ij")))
    if z.ndim == 1:
        keep = axes[0] > 0
        return axes[0][keep], power[keep]
    step = 2 * np.pi / max(sizes)
    ring = np.rint(q / step).astype(int).ravel()
    total = np.bincount(ring, power.ravel())
    count = np.bincount(ring)
    keep = (count > 0) & (np.arange(count.size) > 0)
    return np.arange(count.size)[keep] * step, total[keep] / count[keep]


def topography_figure(scene, prepared):
    """The prepared topography (a line or a map; `gfmd_contact.core.topography_stats.prepared_file`) and its PSD."""
    s = scene.surface
    z, sizes = prepared.heights, prepared.sizes
    fig = Figure(figsize=(10.5, 4.2), layout="constrained")
    left, right = fig.subplots(1, 2)
    if z.ndim == 1:
        left.plot(np.arange(z.size) * sizes[0] / z.size * 1e6, z * 1e9, lw=0.8)
        left.set(xlabel=r"$x$ (µm)", ylabel=r"$z$ (nm)")
    else:
        im = left.imshow(z.T * 1e9, origin="lower", extent=(0, sizes[0] * 1e6, 0, sizes[1] * 1e6), cmap="viridis")
        fig.colorbar(im, ax=left, label=r"$z$ (nm)")
        left.set(xlabel=r"$x$ (µm)", ylabel=r"$y$ (µm)")
    left.set_title(f"{Path(s.path).name}, prepared (levelling {s.levelling}, resample {s.resample})", fontsize=9)
    q, c = periodogram(z, sizes)
    shortest = 2 * max(size / n for size, n in zip(sizes, z.shape))
    right.loglog(q, c, ".", ms=3)
    right.set(xlabel=r"$q$ (1/m)", ylabel=r"$C(q)$ (periodogram)",
              title=f"PSD: wavelengths {shortest * 1e6:.3g} µm to {max(sizes) * 1e6:.3g} µm")
    return fig


def write_check_figure(scene, prepared, scene_file):
    """Write the figure next to the scene file as <stem>_topography.png; its path."""
    path = Path(scene_file).with_name(Path(scene_file).stem + "_topography.png")
    topography_figure(scene, prepared).savefig(path, dpi=110)
    return path
