"""A height file as measured: its heights (m), its physical size (m) and what it says about itself.

One rule for every file of a `surface.kind = "file"` scene: a `.npy` array (1-D: a line scan, 2-D: a map,
axis 0 x) and a text file of one column of heights are read here, in m unless surface.height_unit says
otherwise; any other content goes to SurfaceTopography (the optional extra), whatever its suffix: a file
whose first bytes hold a NUL or are not UTF-8 is binary (an instrument format such as a binary `.dat`),
and text that is not one column (x–z columns, a profilometer's CSV, a matrix) is an instrument export too.

From an instrument file: the channel surface.channel names (a name or an index; default the file's
first height channel), its heights and physical size converted to m from the file's own unit. What a file
does not state, a key supplies, and a refusal names that key: no physical size → surface.length (and
surface.length_y for a map), no unit → surface.height_unit (the unit of the file's numbers, its size
included). SurfaceTopography's own words appear only inside such a sentence. Undefined (masked) and
non-finite heights come back masked; `gfmd_contact.core.topography_prep` refuses or fills them.
"""

from __future__ import annotations

import io
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import SceneError, first_line
from .surface_files import SNIFF_BYTES, check_regular_file, read_npy, read_text

# the file's physical size vs surface.length: agreement to round-off of a size written in another unit
# (µm → m is exact to ~1e-16); 1e-6 relative admits a size written with 7 significant digits
SIZE_RTOL = 1e-6

# suffixes `gfmd_contact.core.surfaces.from_file` reads as text itself (with .npy, the formats read without the extra)
TEXT_SUFFIXES = (".txt", ".dat", ".csv", ".tsv", "")

INSTALL_HINT = 'pip install "gfmd-contact[topography]"'

#: most values read from a .npy or text file whose grid the scene does not fix (region, line or resampling)
MAX_VALUES = 2**24

#: most bytes of any height file (2^24 heights as text, 32 bytes each): a bigger file is refused unread
MAX_FILE_BYTES = 32 * MAX_VALUES

#: length units (to m) of heights and sizes; both spellings of micro
UNITS = {"m": 1.0, "mm": 1e-3, "µm": 1e-6, "μm": 1e-6, "um": 1e-6, "nm": 1e-9, "Å": 1e-10, "A": 1e-10,
         "pm": 1e-12, "km": 1e3}


@dataclass(frozen=True)
class Measurement:
    """A file's heights as read: `heights` (m, masked where undefined; axis 0 x), `sizes` (m per axis),
    `size_stated` (False: the sizes came from surface.length[_y]), `unit` and `channel` (what was read)."""

    heights: np.ma.MaskedArray
    sizes: tuple
    size_stated: bool
    unit: str
    channel: str


def metre(unit, key="surface.height_unit"):
    """m per `unit`; a SceneError naming `key` for a unit that is no length."""
    factor = UNITS.get(unit)
    if factor is None:
        raise SceneError(f"{key} = {unit!r}: not a known length unit; one of {', '.join(UNITS)}")
    return factor


def is_binary(path):
    """Does the file's start hold a NUL byte or bytes that are not UTF-8 (an instrument's binary format)?"""
    with open(path, "rb") as f:
        data = f.read(SNIFF_BYTES)
    if b"\0" in data:
        return True
    try:
        data.decode("utf-8")
    except UnicodeDecodeError as exc:
        return exc.start < len(data) - 3  # a character cut at the end of the sniffed bytes is still text
    return False


def read_measurement(path, *, channel="", height_unit="", lengths=(None,), shape=None):
    """The `Measurement` of `path` (module docstring).

    lengths: (surface.length[, surface.length_y]) as given (None: not given), used where the file states no
    size; shape: the grid the scene fixes for a .npy file (checked from its header), or None (any grid up to
    MAX_VALUES values).
    """
    path = Path(path)
    if len(lengths) == 2 and lengths[1] is None:  # a size the file lacks: length_y defaults to length
        lengths = (lengths[0], lengths[0])

    def fail(problem):
        raise SceneError(f"surface.path = {str(path)!r}: {problem}")

    size = check_regular_file(path, fail)
    if size > MAX_FILE_BYTES:
        fail(f"is {size} bytes, more than the {MAX_FILE_BYTES} bytes a height file may take (2^24 heights as text); "
             "is it the right file?")
    try:
        binary = is_binary(path)
    except OSError as exc:
        fail(f"cannot be read ({exc.strerror or exc})")
    if path.suffix.lower() == ".npy":
        h = _npy(path, shape, fail)
    else:
        h = None if binary else _one_column(path, shape, fail)
    if h is None:
        content = "holds binary content" if binary else "holds text that is not one column of heights"
        return _instrument(path, channel, height_unit, lengths, fail, content)
    if h.ndim not in (1, 2):
        fail(f"holds an array of shape {h.shape}; a line scan is 1-D, a map 2-D (axis 0 x)")
    if channel != "":
        fail(f"surface.channel = {channel!r}: a .npy or one-column text file holds one channel; leave the key out")
    if any(length is None for length in lengths[: h.ndim]) or len(lengths) < h.ndim:
        keys = " and ".join(("surface.length", "surface.length_y")[: h.ndim])
        fail(f"a .npy or text file states no physical size; {keys} supply it (m)")
    unit = height_unit or "m"
    factor = metre(unit)
    heights = np.ma.masked_invalid(np.asarray(h, dtype=float) * factor)
    return Measurement(heights, tuple(float(s) for s in lengths[: h.ndim]), False, unit, "")


def _npy(path, shape, fail):
    """The array of a .npy file: of `shape` when the scene fixes it (header first), else of ≤ MAX_VALUES values."""
    h, file_shape = read_npy(path, shape or (), fail)
    if h is not None:
        return h
    if shape is not None and len(shape) == len(file_shape) == 1:
        fail(f"holds {file_shape[0]} heights, but surface.nodes = {shape[0]} (or surface.resample puts them on "
             "that grid)")
    if shape is not None:
        names = "(surface.nodes, surface.nodes_y)" if len(shape) == 2 else "(surface.nodes,)"
        fail(f"holds an array of shape {file_shape}, but {names} = {tuple(shape)} (or surface.resample puts it "
             "on that grid, surface.line takes a line of a map)")
    if len(file_shape) not in (1, 2) or 0 in file_shape:
        fail(f"holds an array of shape {file_shape}; a line scan is 1-D, a map 2-D (axis 0 x)")
    if int(np.prod(file_shape, dtype=np.int64)) > MAX_VALUES:
        fail(f"holds an array of shape {file_shape}, more than {MAX_VALUES} values")
    return read_npy(path, file_shape, fail)[0]


def _one_column(path, shape, fail):
    """Heights of a text file of one column (one number per line, '#' comments), or None for other text."""
    count = shape[0] if shape is not None and len(shape) == 1 else MAX_VALUES
    text = read_text(path, count, fail)
    rows = [line.split("#", 1)[0].split() for line in text.splitlines()]
    rows = [row for row in rows if row]
    if not rows:
        fail("the file holds no numbers (empty)")
    if any(len(row) != 1 or "," in row[0] for row in rows):
        return None
    try:
        h = np.loadtxt(io.StringIO("\n".join(row[0] for row in rows)), dtype=float, ndmin=1)
    except ValueError:
        return None  # words in one column: an instrument export's header, perhaps
    if shape is not None and len(shape) == 1 and h.size != shape[0]:
        fail(f"holds {h.size} heights, but surface.nodes = {shape[0]} (or surface.resample puts them on that grid)")
    return h


def _instrument(path, channel, height_unit, lengths, refuse, content):
    """The `Measurement` of a file SurfaceTopography reads (module docstring)."""
    def fail(problem):
        refuse(f"{content}, read as an instrument file: {problem}")

    what = ("a .npy array, one column of heights, or a file SurfaceTopography reads (surface.channel, "
            "surface.length, surface.height_unit supply what it lacks)")
    try:
        import SurfaceTopography
    except ImportError:
        fail(f"that needs the optional extra: {INSTALL_HINT}")
    try:
        with warnings.catch_warnings():  # readers warn about metadata they skip
            warnings.simplefilter("ignore")
            reader = SurfaceTopography.open_topography(str(path))
            channels = list(reader.channels)
    except Exception as exc:  # any reader's failure on this file is bad input (format, corrupt, ...)
        fail(f"SurfaceTopography cannot read it ({type(exc).__name__}: {first_line(exc)}); expected {what}")
    info = _channel(channels, channel, reader.default_channel, fail)
    unit = info.unit
    if unit is not None and not isinstance(unit, str):
        fail(f"channel {info.index} ({info.name!r}) holds no heights (units {unit}); surface.channel picks another: "
             + _listing(channels))
    kwargs = {}
    if unit is None or unit not in UNITS:
        if not height_unit:
            stated = "states no unit" if unit is None else f"states the unit {unit!r}, not a known length unit,"
            fail(f"the file {stated} for its numbers (heights and size); surface.height_unit supplies it "
                 f"(one of {', '.join(UNITS)})")
        if unit is None:
            kwargs["unit"] = height_unit
        unit = height_unit
    elif height_unit and metre(height_unit) != metre(unit):
        fail(f"the file states its unit, {unit!r}, but surface.height_unit = {height_unit!r}; leave the key out "
             "(surface.height_scale corrects heights written in a wrong unit)")
    factor = metre(unit)
    sizes = info.physical_sizes
    stated = sizes is not None and all(s is not None and float(s) > 0 for s in sizes)
    if not stated:
        keys = ("surface.length", "surface.length_y")[: info.dim]
        given = tuple(lengths[: info.dim]) if len(lengths) >= info.dim else ()
        if len(given) < info.dim or any(s is None for s in given):
            fail(f"the file states no physical size; {' and '.join(keys)} supply it (m)")
        kwargs["physical_sizes"] = tuple(s / factor for s in given)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t = reader.topography(channel_index=info.index, **kwargs)
            heights = np.ma.masked_invalid(np.ma.array(t.heights(), dtype=float, copy=True))
            sizes_m = tuple(float(s) * factor for s in t.physical_sizes)
    except Exception as exc:
        fail(f"SurfaceTopography cannot read channel {info.index} ({type(exc).__name__}: {first_line(exc)}); "
             f"expected {what}")
    return Measurement(heights * factor, sizes_m, stated, unit, str(info.name))


def _listing(channels):
    return "; ".join(f"{c.index}: {c.name!r}" for c in channels)


def _channel(channels, channel, default, fail):
    """The channel info surface.channel names (an index or a unique name); default the reader's default."""
    if channel == "":
        return default
    if isinstance(channel, int):
        if not 0 <= channel < len(channels):
            fail(f"surface.channel = {channel}: the file has channels 0 to {len(channels) - 1} ({_listing(channels)})")
        return channels[channel]
    matches = [c for c in channels if c.name == channel]
    if len(matches) != 1:
        problem = "names no channel" if not matches else f"names {len(matches)} channels (give the index)"
        fail(f"surface.channel = {channel!r} {problem}; the file's channels: {_listing(channels)}")
    return matches[0]
