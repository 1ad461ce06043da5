"""A measured height file prepared for a scene, in the order of its [surface] keys, and turned to face the body.

Units: SI (see `gfmd_contact.core.conventions`). Node i of a file of N points over a size L sits at i·L/N
from the file's origin (the scene's periodic grid). The steps, each a key of `surface.kind = "file"`:

1. surface.region: keep the nodes with x0 ≤ x < x1 (and y0 ≤ y < y1): the cell is the crop, its size
   (count × spacing) the cell's; a file that states no size has no coordinates to crop by (refused).
2. surface.undefined: masked or non-finite heights are refused ("refuse"), or filled: "harmonic"
   (SurfaceTopography's harmonic imputation, a map) or "mean" (the mean of the defined heights).
3. surface.line: "x:K" takes the line along x at y-node K of a map, "y:K" the line along y at x-node K
   (after the crop), for a 1+1-D scene.
4. surface.height_scale multiplies the heights (the unit was applied on reading).
5. surface.line_levelling (a map): each scan line, the nodes along surface.scan_axis at one node of the
   other axis, loses its own mean ("height") or its own least-squares straight line ("slope"), as an AFM
   user aligns the rows of a scan first; "none" leaves them. The lines run along the instrument's fast-scan
   axis, which SurfaceTopography puts on x (axis 0) for a Bruker NanoScope .di file.
6. surface.levelling: SurfaceTopography's detrend, "height" (the mean), "slope" (the mean plane, least
   squares) or "curvature" (the best quadratic); "none" leaves mean and tilt.
7. surface.resample: "none" (the grid must be surface.nodes[ × nodes_y]), or onto that grid over the
   same size: "linear" or "cubic" (a periodic spline) interpolation between the nodes, the cell's last node
   joined to its first as the periodic cell joins them, or "fourier" (the spectrum truncated or padded,
   scipy.signal.resample; band-limited and periodic).

The prepared heights are the measured surface, z out of the measured material. surface.facing turns them
into the rigid indenter's lower surface h(x): "summits" (default) h = −z, so the measured summits touch
first (the indenter touches where h is smallest, `gfmd_contact.core.conventions`); "valleys" h = z.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.interpolate
import scipy.signal

from .errors import SceneError
from .scene_sections import Surface
from .topography_files import INSTALL_HINT, SIZE_RTOL, metre, read_measurement

#: surface.region values within this fraction of the spacing of a node count as on it (round-off of x = i·l)
ON_NODE = 1e-9


@dataclass(frozen=True)
class Prepared:
    """`heights` (m, the measured surface, prepared), `sizes` (m) of the cell, the `Measurement` read."""

    heights: np.ndarray
    sizes: tuple
    measurement: object


def indenter_heights(surface):
    """The rigid indenter's lower surface h (m) of a file scene: its prepared heights turned by surface.facing."""
    z = prepare(surface, surface_lengths(surface)).heights
    return -z if surface.facing == "summits" else z.copy()


def file_heights(path, shape, lengths):
    """The heights (m) of a file on the grid `shape` = (N,) or (Nx, Ny) over `lengths`, as read: unprepared,
    unturned."""
    probe = Surface(kind="file", path=str(path), nodes=shape[0], nodes_y=shape[1] if len(shape) == 2 else 0)
    return prepare(probe, tuple(lengths)).heights


def surface_lengths(surface):
    """(surface.length[, surface.length_y]) of a resolved scene: the cell's size."""
    return (surface.length, surface.length_y) if surface.two_d else (surface.length,)


def prepare(surface, lengths):
    """The `Prepared` file of `surface` (module docstring); `lengths` as the scene gives them (None: not given)."""
    fixed = surface.region == () and surface.line == "none" and surface.resample == "none"
    m = read_measurement(surface.path, channel=surface.channel, height_unit=surface.height_unit,
                         lengths=lengths, shape=surface.shape if fixed else None)
    h, sizes = m.heights, m.sizes
    _check_dimension(surface, h.ndim)
    if surface.region:
        if not m.size_stated:
            raise SceneError(f"surface.region = {list(surface.region)}: the file states no size, so it has no "
                             "coordinates to crop by; crop the file, or leave surface.region out")
        h, sizes = crop(h, sizes, surface.region)
    h = fill(h, sizes, surface.undefined, surface.path)
    if surface.line != "none":
        h, sizes = take_line(h, sizes, surface.line)
    h = level_lines(h * surface.height_scale, surface.scan_axis, surface.line_levelling)
    h = level(h, sizes, surface.levelling)
    h = resample(h, surface.shape, surface.resample, surface.path)
    if m.size_stated:
        _check_sizes(surface, sizes, lengths, m)
    return Prepared(h, sizes, m)


def _check_dimension(surface, ndim):
    if surface.line_levelling != "none" and not surface.two_d:
        raise SceneError(f"surface.line_levelling = {surface.line_levelling!r}: levels each scan line of a map, but "
                         "the scene is a 1+1-D profile (surface.nodes_y = 0), one line with no lines beside it; "
                         "surface.levelling levels it, or surface.nodes_y ≥ 2 reads the map")
    if surface.line != "none" and surface.two_d:
        raise SceneError(f"surface.line = {surface.line!r}: takes a line scan for a 1+1-D profile, but surface.nodes_y "
                         f"= {surface.nodes_y} makes a 2+1-D surface; leave one of them out")
    want = 1 if surface.line == "none" and not surface.two_d else 2
    if ndim == want:
        return
    path = f"surface.path = {surface.path!r}"
    if surface.line != "none":
        raise SceneError(f"surface.line = {surface.line!r}: takes a line of a map, but {path} holds a line scan")
    if surface.two_d:
        raise SceneError(f"{path} holds a 1-D topography, but the scene needs a 2-D topography map "
                         "(a surface, surface.nodes_y ≥ 2)")
    raise SceneError(f"{path} holds a 2-D topography, but the scene needs a line scan (a profile, surface.nodes_y = "
                     "0): surface.line takes one line of the map, or surface.nodes_y ≥ 2 reads the map")


def _check_sizes(surface, sizes, lengths, m):
    for key, size, length in zip(("surface.length", "surface.length_y"), sizes, lengths):
        if length is not None and not abs(size - length) <= SIZE_RTOL * abs(length):
            raise SceneError(f"surface.path = {surface.path!r}: the prepared file's physical size is {size:.9g} m "
                             f"({size / metre(m.unit):.9g} {m.unit}), but {key} = {length:g} m "
                             f"(they must agree within {SIZE_RTOL:g} relative: the heights were measured on the "
                             f"file's size; leave {key} out to take it from the file)")


def crop(h, sizes, region):
    """(h, sizes) of the nodes inside `region` = [x0, x1(, y0, y1)] (m from the file's origin)."""
    if len(region) != 2 * h.ndim:
        raise SceneError(f"surface.region = {list(region)}: a {'map' if h.ndim == 2 else 'line scan'} is cropped by "
                         f"{2 * h.ndim} values, [x0, x1{', y0, y1' if h.ndim == 2 else ''}] (m)")
    index = []
    new_sizes = []
    for axis, (lo, hi) in enumerate(zip(region[::2], region[1::2])):
        n, size = h.shape[axis], sizes[axis]
        spacing = size / n
        if hi > size * (1 + ON_NODE):
            raise SceneError(f"surface.region = {list(region)}: reaches {hi:g} m along {'xy'[axis]}, beyond the "
                             f"file's size {size:g} m")
        i0, i1 = (int(np.ceil(v / spacing - ON_NODE)) for v in (lo, hi))
        i1 = min(i1, n)
        if i1 - i0 < 2:
            raise SceneError(f"surface.region = {list(region)}: holds {max(i1 - i0, 0)} node(s) along {'xy'[axis]} "
                             f"(spacing {spacing:g} m); a cell needs at least 2")
        index.append(slice(i0, i1))
        new_sizes.append((i1 - i0) * spacing)
    return h[tuple(index)], tuple(new_sizes)


def fill(h, sizes, how, path):
    """Heights without undefined points: refused (how = "refuse") or filled ("harmonic", "mean")."""
    count = int(np.ma.count_masked(h))
    if count == 0:
        return np.ma.getdata(h).astype(float)
    if count == h.size:
        raise SceneError(f"surface.path = {path!r}: every height is undefined (masked or non-finite)")
    if how == "refuse":
        raise SceneError(f"surface.path = {path!r}: contains undefined (masked or non-finite) heights ({count} of "
                         f"{h.size}); contact needs a height at every node: surface.undefined = \"harmonic\" or "
                         "\"mean\" fills them, surface.region crops them away")
    if how == "mean":
        return h.filled(float(h.mean()))
    st = _surface_topography("surface.undefined")
    if h.ndim != 2:
        raise SceneError(f"surface.undefined = {how!r}: SurfaceTopography's harmonic fill works on a map; a line "
                         "scan takes \"mean\"")
    topography = st.Topography(h, sizes, periodic=False)
    return np.asarray(topography.interpolate_undefined_data(how).heights(), dtype=float)


def take_line(h, sizes, line):
    """One line of a map (module docstring, step 3): ("x:K", h) → h[:, K], ("y:K", h) → h[K, :]."""
    axis_name, index = line.split(":")
    along = "xy".index(axis_name)
    across = 1 - along
    k = int(index)
    if not 0 <= k < h.shape[across]:
        raise SceneError(f"surface.line = {line!r}: node {k} is outside the map's {h.shape[across]} nodes along "
                         f"{'xy'[across]} (0 to {h.shape[across] - 1}, after surface.region)")
    return np.take(h, k, axis=across), (sizes[along],)


def level_lines(h, scan_axis, mode):
    """Map `h` with each line along `scan_axis` ("x": h[:, j]) less its mean ("height") or its least-squares
    straight line ("slope"); "none": `h`. The node spacing does not enter: the fit is over node indices."""
    if mode == "none":
        return h
    axis = "xy".index(scan_axis)
    h = h - h.mean(axis=axis, keepdims=True)
    if mode == "slope":
        shape = [1, 1]
        shape[axis] = h.shape[axis]
        x = (np.arange(h.shape[axis]) - (h.shape[axis] - 1) / 2).reshape(shape)
        h = h - x * (np.sum(x * h, axis=axis, keepdims=True) / np.sum(x**2))
    return h


def level(h, sizes, mode):
    """`h` less its mean ("height"), mean plane ("slope") or best quadratic ("curvature"); "none": `h`."""
    if mode == "none":
        return h
    st = _surface_topography("surface.levelling")
    topography = (st.UniformLineScan(h, sizes[0], periodic=False) if h.ndim == 1
                  else st.Topography(h, sizes, periodic=False))
    return np.asarray(topography.detrend(detrend_mode=mode).heights(), dtype=float)


def resample(h, shape, method, path=""):
    """`h` on the scene's grid `shape` over the same size (module docstring, step 7)."""
    if method == "none":
        if h.shape != tuple(shape):
            keys = "(surface.nodes, surface.nodes_y)" if len(shape) == 2 else "(surface.nodes)"
            raise SceneError(f"surface.path = {str(path)!r}: the prepared file holds "
                             f"{' × '.join(map(str, h.shape))} points, but {keys} = "
                             f"({', '.join(map(str, shape))}); surface.resample = \"linear\", \"cubic\" or "
                             "\"fourier\" puts it on that grid")
        return h
    for axis, n in enumerate(shape):
        h = _resample_axis(h, n, axis, method)
    return h


def _resample_axis(h, n_new, axis, method):
    n = h.shape[axis]
    if n == n_new:
        return h
    if method == "fourier":
        return scipy.signal.resample(h, n_new, axis=axis)
    x = np.arange(n + 1) / n  # the nodes in units of the cell, and the first again at the cell's end
    joined = np.concatenate([h, np.take(h, [0], axis=axis)], axis=axis)
    if method == "linear":
        spline = scipy.interpolate.make_interp_spline(x, joined, k=1, axis=axis)
    else:
        spline = scipy.interpolate.CubicSpline(x, joined, axis=axis, bc_type="periodic")
    return spline(np.arange(n_new) / n_new)


def _surface_topography(key):
    try:
        import SurfaceTopography
    except ImportError:
        raise SceneError(f"{key}: needs SurfaceTopography, the optional extra: {INSTALL_HINT}") from None
    return SurfaceTopography
