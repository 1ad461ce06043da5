"""Measured topographies in instrument formats, read through SurfaceTopography (optional extra).

`gfmd_contact.core.surfaces.from_file` (1+1-D) and `gfmd_contact.core.surfaces_2d.from_file_2d` (2+1-D) read .npy and text
themselves; a file with any other suffix comes here: `SurfaceTopography.read_topography` detects the
format (netCDF .nc, .x3p, .sur, .opd, .di, .ibw, .datx, ...). The heights are converted to m from the file's
unit; the grid must be the scene's (a line scan for a profile, a map for a surface, nb_grid_pts =
(surface.nodes[, surface.nodes_y])); the file's physical size must be the cell's (surface.length
[, surface.length_y]) within `SIZE_RTOL`, as the file states the size its heights were measured on, and a
scene that silently rescaled them would change every slope (p_r* = p/(ḡ_r E*), seed Eq. 6). A file without a
physical size is refused too (no silent default). Undefined (masked) or non-finite heights are refused:
contact needs a height at every node. The file's heights are used as they are (mean, tilt and periodicity
untouched): the cell is periodic, so a measured map should be levelled and periodic enough for the study.
Without SurfaceTopography installed: a `SceneError` saying `pip install "gfmd-contact[topography]"`.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from .errors import SceneError, first_line

# the file's physical size vs surface.length: agreement to round-off of a size written in another unit
# (µm → m is exact to ~1e-16); 1e-6 relative admits a size written with 7 significant digits
SIZE_RTOL = 1e-6

# suffixes `gfmd_contact.core.surfaces.from_file` reads as text itself (with .npy, the formats read without the extra)
TEXT_SUFFIXES = (".txt", ".dat", ".csv", ".tsv", "")

INSTALL_HINT = 'pip install "gfmd-contact[topography]"'


def read_topography_file(path, nodes, lengths):
    """Heights (m) of an instrument file: shape (nodes[0],) for a line scan, (nodes[0], nodes[1]) for a map.

    `nodes` = (surface.nodes,) or (surface.nodes, surface.nodes_y); `lengths` the matching cell sizes (m).
    Every refusal is a `SceneError` naming surface.path and the key that disagrees (module docstring).
    """
    path = Path(path)
    dim = len(nodes)
    keys = ("surface.nodes", "surface.nodes_y")[:dim]
    length_keys = ("surface.length", "surface.length_y")[:dim]
    what = "a line scan" if dim == 1 else "a 2-D topography map"

    def fail(problem):
        raise SceneError(f"surface.path = {str(path)!r}: {problem}")

    if any(length is None for length in lengths):
        raise ValueError(f"reading an instrument file needs ({', '.join(length_keys)}) to check its physical size")

    try:
        import SurfaceTopography
        from SurfaceTopography.Support.UnitConversion import get_unit_conversion_factor
    except ImportError:
        fail(f"the suffix {path.suffix!r} is not one read without SurfaceTopography (.npy"
             + (", or text: " + ", ".join(s or "no suffix" for s in TEXT_SUFFIXES) if dim == 1 else "")
             + f"); instrument formats need the optional extra: {INSTALL_HINT}")
    try:
        with warnings.catch_warnings():  # scipy's netCDF reader warns about its memory map on close
            warnings.simplefilter("ignore", RuntimeWarning)
            topography = SurfaceTopography.read_topography(str(path))
            heights = np.ma.array(topography.heights(), dtype=float, copy=True)
    except Exception as exc:  # any reader's failure on this file is bad input (format, corrupt, ...)
        fail(f"SurfaceTopography cannot read it as a topography ({type(exc).__name__}: {first_line(exc)})")
    if topography.dim != dim:
        fail(f"holds a {topography.dim}-D topography, but the scene needs {what}"
             + (" (a profile, surface.nodes_y = 0)" if dim == 1 else " (a surface, surface.nodes_y ≥ 2)"))
    grid = tuple(int(n) for n in topography.nb_grid_pts)
    if grid != tuple(nodes):
        raise SceneError(f"surface.path = {str(path)!r} holds {what} of {' × '.join(map(str, grid))} points, but "
                         f"({', '.join(keys)}) = ({', '.join(map(str, nodes))})")
    unit = topography.unit
    try:
        to_metre = float(get_unit_conversion_factor(unit, "m"))
    except Exception as exc:
        fail(f"the file's unit {unit!r} is not a known length unit ({first_line(exc)}); "
             "expected m, mm, µm, nm, Å, ...")
    sizes = topography.physical_sizes
    if sizes is None:
        fail(f"the file states no physical size; it must equal ({', '.join(length_keys)})")
    sizes_m = tuple(float(s) * to_metre for s in sizes)
    for key, size_m, size, length in zip(length_keys, sizes_m, sizes, lengths):
        if not abs(size_m - length) <= SIZE_RTOL * abs(length):
            raise SceneError(f"surface.path = {str(path)!r}: the file's physical size is {size_m:.9g} m "
                             f"({float(size):.9g} {unit}), but {key} = "
                             f"{length:g} m (they must agree within {SIZE_RTOL:g} relative: the heights "
                             "were measured on the file's size)")
    undefined = int(np.ma.count_masked(heights))
    if undefined:
        fail(f"contains undefined (masked) heights ({undefined} of {heights.size}); contact needs a height "
             "at every node (fill or crop the measurement first)")
    h = np.asarray(heights.filled(np.nan)) * to_metre
    if not np.all(np.isfinite(h)):
        fail(f"contains non-finite heights ({int(np.sum(~np.isfinite(h)))} of {h.size})")
    return h
