"""The [surface] keys of a measured height file (surface.kind = "file"), validated; the file read once for its size.

Every bad value is a `SceneError` naming the key. The keys (their steps: `gfmd_contact.core.topography_prep`):
path, facing ("summits" | "valleys"), channel (a name or an index; "" the file's first height channel),
region ([x0, x1] or [x0, x1, y0, y1], m), undefined ("refuse" | "harmonic" | "mean"), line ("none" |
"x:K" | "y:K"), height_unit ("" the file's; m, mm, µm, nm, ...), height_scale (> 0), line_levelling ("none" |
"height" | "slope", a map's scan lines each levelled), scan_axis ("x" | "y", the lines' axis), levelling ("none" |
"height" | "slope" | "curvature") and resample ("none" | "linear" | "cubic" | "fourier"). The cell's size
is the prepared file's: surface.length (and length_y) may be left out, and where given must agree.
"""

from __future__ import annotations

import math
import os
import re

from .errors import SceneError
from .scene_sections import Surface
from .topography_files import UNITS

#: the keys of a "file" surface besides the common ones, in the order of preparation
FILE_KEYS = ("path", "facing", "channel", "region", "undefined", "line", "height_unit", "height_scale",
             "line_levelling", "scan_axis", "levelling", "resample")
FACINGS = ("summits", "valleys")
UNDEFINED = ("refuse", "harmonic", "mean")
LEVELLINGS = ("none", "height", "slope", "curvature")
LINE_LEVELLINGS = ("none", "height", "slope")
SCAN_AXES = ("x", "y")
RESAMPLINGS = ("none", "linear", "cubic", "fourier")
_LINE = re.compile(r"^[xy]:\d+$")


def _choice(d, key, allowed, why):
    value = d.get(key, getattr(Surface, key))
    if not isinstance(value, str) or value not in allowed:
        raise SceneError(f"surface.{key} = {value!r}: must be one of {list(allowed)} ({why})")
    return value


def file_keys(d):
    """The validated preparation keys of a [surface] table (no file read), as `Surface` fields."""
    path = d.get("path", "")
    if not isinstance(path, str) or not path:
        raise SceneError(f"surface.path = {path!r}: must name a height file: a .npy array or one column of "
                         "heights (m), or an instrument file (the optional extra SurfaceTopography)")
    channel = d.get("channel", "")
    if isinstance(channel, bool) or not isinstance(channel, (str, int)) or (isinstance(channel, int) and channel < 0):
        raise SceneError(f"surface.channel = {channel!r}: must be a channel's name or its index (an integer ≥ 0)")
    unit = d.get("height_unit", "")
    if not isinstance(unit, str) or (unit and unit not in UNITS):
        raise SceneError(f"surface.height_unit = {unit!r}: must be a length unit, one of {', '.join(UNITS)} "
                         "(or \"\": the file's own)")
    scale = d.get("height_scale", 1.0)
    if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not 0 < scale < math.inf:
        raise SceneError(f"surface.height_scale = {scale!r}: must be a finite number > 0 (the heights' factor)")
    line = d.get("line", "none")
    if not isinstance(line, str) or not (line == "none" or _LINE.match(line)):
        raise SceneError(f"surface.line = {line!r}: must be \"none\", \"x:K\" (the line along x at y-node K of a "
                         "map) or \"y:K\" (along y at x-node K)")
    return dict(path=path, channel=channel, region=_region(d.get("region", [])), line=line, height_unit=unit,
                height_scale=float(scale),
                facing=_choice(d, "facing", FACINGS, "summits: the measured surface's highest points touch first"),
                undefined=_choice(d, "undefined", UNDEFINED, "refuse undefined points, or fill them"),
                line_levelling=_choice(d, "line_levelling", LINE_LEVELLINGS,
                                       "each scan line's own mean, or mean and tilt, removed"),
                scan_axis=_choice(d, "scan_axis", SCAN_AXES, "the axis the scan lines run along, the fast-scan axis"),
                levelling=_choice(d, "levelling", LEVELLINGS, "what SurfaceTopography's detrend removes"),
                resample=_choice(d, "resample", RESAMPLINGS, "none: the file's grid must be the scene's"))


def _region(value):
    bad = (f"surface.region = {value!r}: must be [x0, x1] (a line scan) or [x0, x1, y0, y1] (a map), in m from "
           "the file's origin, 0 ≤ x0 < x1")
    if not isinstance(value, (list, tuple)) or len(value) not in (0, 2, 4):
        raise SceneError(bad)
    if any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in value):
        raise SceneError(bad)
    if any(not 0 <= lo < hi for lo, hi in zip(value[::2], value[1::2])):
        raise SceneError(bad)
    return tuple(float(v) for v in value)


def resolve(d, nodes, nodes_y, lengths):
    """(the `Surface` fields of the file keys, the cell's sizes (m)): `file_keys` and the file prepared once.

    lengths: (surface.length, surface.length_y) as given, None where not given.
    """
    kw = file_keys(d)
    from .topography_prep import prepare

    probe = Surface(kind="file", nodes=nodes, nodes_y=nodes_y, **kw)
    try:
        sizes = prepare(probe, lengths[:2] if nodes_y else lengths[:1]).sizes
    except ValueError as exc:  # a library's refusal of these values (SceneError is one too)
        raise SceneError(str(exc)) from None
    # the file read just now, wherever the scene is written and read back (a run's DIR/scene.toml resolves a
    # relative path against DIR): a relative path is the working directory's
    kw["path"] = os.path.abspath(kw["path"])
    return kw, sizes
