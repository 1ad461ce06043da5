"""Rigid indenter profiles h(x) on the periodic grid (m).

Units: SI (see `gfmd_contact.core.conventions`). Grid x_j = (j − N/2) l, l = L/N.
Random profiles use the seed's spectral method (seed Eq. 4, reference-formulas §6):
deterministic amplitudes √((2π/L) C(q_n)), random phases from an explicit seed,
zero mean, and h_rms exact after a final rescaling.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import scipy.fft

from . import memo
from .errors import SceneError, first_line
from .surface_files import check_regular_file, read_npy, read_text
from .topography_files import TEXT_SUFFIXES  # read as text here; other suffixes: instrument files
from .topography_files import is_binary
from .psd import grid, psd_self_affine  # noqa: F401 (the grid and Eq. 4's shape, shared with gfmd_contact.core.surfaces_2d)


def self_affine(nodes, length, hurst, h_rms, rolloff_wavelength, rollon_wavelength, seed):
    """Random self-affine profile (m): seed Eq. 4 spectrum, random phases, exact h_rms.

    The Nyquist mode (even N) and q = 0 carry no amplitude. `seed` fixes the phases
    via numpy's default_rng, so equal arguments give identical profiles.
    """
    q = 2 * np.pi * np.fft.rfftfreq(nodes, d=length / nodes)
    amplitude = np.sqrt(psd_self_affine(q, hurst, rolloff_wavelength, rollon_wavelength, length))
    if nodes % 2 == 0:
        amplitude[-1] = 0.0
    rng = np.random.default_rng(seed)
    phase = rng.uniform(0.0, 2 * np.pi, size=q.size)
    h = scipy.fft.irfft(amplitude * np.exp(1j * phase), n=nodes)
    rms = np.sqrt(np.mean(h**2))
    if rms == 0.0:
        raise ValueError("self-affine spectrum has no modes on this grid: check the wavelengths against L and N")
    return h * (h_rms / rms)


def sinusoid(nodes, length, amplitude):
    """h(x) = −a cos(2πx/L) (m): one wavelength per cell, minimum (first contact) at x = 0.

    `amplitude` a in m (peak-to-valley 2a); reference-formulas §0 profile up to a constant.
    """
    return -amplitude * np.cos(2 * np.pi * grid(nodes, length) / length)


def cylinder(nodes, length, radius):
    """Parabolic cylinder h(x) = x²/(2R) (m) centred at x = 0, R in m."""
    x = grid(nodes, length)
    return x**2 / (2 * radius)


def flat(nodes, length):
    """Flat indenter h = 0 (m)."""
    return np.zeros(nodes)


def from_file(path, nodes, length=None):
    """Heights (m) read from a file of exactly `nodes` values: a 1-D .npy array, or a text file
    (suffix .txt, .dat, .csv, .tsv or none) with one column of heights (whitespace-separated numbers,
    '#' comments). Any other suffix, or binary content, is an instrument file, a line scan read through
    SurfaceTopography (the optional extra, `gfmd_contact.core.topography_files`), its heights converted to m and
    its physical size checked against `length` (surface.length, m). A scene reads its file with the preparation
    keys and turned to face the body (`gfmd_contact.core.topography_prep`); this is the plain reader.

    Anything else (a missing, unreadable, corrupt, empty, comma-separated or 2-D file, non-numeric
    or non-finite values, the wrong count) raises a `SceneError` naming surface.path,
    the file and what is expected.
    """
    path = Path(path)
    expected = (f"expected a 1-D .npy array or a text file with one column of surface.nodes = {nodes} "
                "heights in m")

    def fail(problem):
        raise SceneError(f"surface.path = {str(path)!r}: {problem}; {expected}")

    check_regular_file(path, fail)
    if path.suffix.lower() not in (".npy",) + TEXT_SUFFIXES or (path.suffix.lower() != ".npy" and _binary(path)):
        from .topography_prep import file_heights
        return file_heights(path, (nodes,), (length,))
    try:
        if path.suffix.lower() == ".npy":
            h, shape = read_npy(path, (nodes,), fail)  # the header first: the shape before any value
            if h is None and shape == (0,):
                fail("the file holds no numbers (empty)")
            if h is None and len(shape) != 1:
                fail(f"holds an array of shape {shape} ({len(shape)}-D), not one column of heights")
            if h is None:
                raise SceneError(f"surface.path = {str(path)!r} holds {shape[0]} heights, but surface.nodes = "
                                 f"{nodes}; {expected}")
        else:
            text = read_text(path, nodes, fail, "; a NumPy array must have the suffix .npy, an instrument file "
                                                 "its own suffix")
            body = [line.split("#", 1)[0] for line in text.splitlines()]
            if not any(line.strip() for line in body):
                fail("the file holds no numbers (empty)")
            if any("," in line for line in body):
                fail("comma-separated values are not read (write one height per line)")
            try:
                h = np.loadtxt(io.StringIO(text), dtype=float, ndmin=1)
            except ValueError as exc:  # non-numeric text, ragged rows
                fail(f"cannot be read as numbers ({first_line(exc)})")
    except OSError as exc:  # unreadable
        fail(f"cannot be read ({first_line(exc)})")
    if not isinstance(h, np.ndarray):  # e.g. an .npz archive named .npy
        getattr(h, "close", lambda: None)()
        fail(f"holds a {type(h).__name__}, not an array")
    if h.dtype.kind not in "iuf":
        fail(f"holds values of dtype {h.dtype}, not real numbers")
    if h.ndim != 1:
        fail(f"holds an array of shape {h.shape} ({h.ndim}-D), not one column of heights")
    if h.size == 0:
        fail("the file holds no numbers (empty)")
    h = np.asarray(h, dtype=float)
    if h.size != nodes:
        raise SceneError(f"surface.path = {str(path)!r} holds {h.size} heights, but surface.nodes = {nodes}; "
                         f"{expected}")
    if not np.all(np.isfinite(h)):
        fail(f"contains non-finite heights ({int(np.sum(~np.isfinite(h)))} of {h.size})")
    return h


def _binary(path):
    """Binary content under a text suffix (an instrument format, e.g. a binary .dat)? An unreadable file: no
    (the text reader names what is wrong)."""
    try:
        return is_binary(path)
    except OSError:
        return False


#: the profiles of the surface asked for last (a check, the run and its files share them; one surface's at a time)
_MADE = memo.LastOwner()


def profile(surface, realization=0):
    """Profile h(x) (m) for a `gfmd_contact.core.scene.Surface` spec; realization i uses seed + i.

    A 2+1-D surface (surface.nodes_y ≥ 2) gives h(x, y) of shape (Nx, Ny) (`gfmd_contact.core.surfaces_2d`).
    Made once per (surface object, realization; a file's size and modification time) and read-only after.
    """
    stamp = None
    if surface.kind == "file":
        try:
            stat = Path(surface.path).stat()
        except (OSError, TypeError, ValueError):  # make_profile says what is wrong with the path
            return make_profile(surface, realization)
        stamp = (stat.st_mtime_ns, stat.st_size)
    return _MADE.get(surface, (realization, stamp), lambda: _read_only(make_profile(surface, realization)))


def _read_only(h):
    h.flags.writeable = False
    return h


def make_profile(surface, realization=0):
    """`profile` made anew."""
    if getattr(surface, "nodes_y", 0):
        from .surfaces_2d import profile_2d
        return profile_2d(surface, realization)
    n, length = surface.nodes, surface.length
    if surface.kind == "self-affine":
        return self_affine(n, length, surface.hurst, surface.h_rms, surface.rolloff_wavelength,
                           surface.rollon_wavelength, surface.seed + realization)
    if surface.kind == "sinusoid":
        return sinusoid(n, length, surface.amplitude)
    if surface.kind == "cylinder":
        return cylinder(n, length, surface.radius)
    if surface.kind == "flat":
        return flat(n, length)
    if surface.kind == "file":  # read, prepared and turned to face the body (gfmd_contact.core.topography_prep)
        from .topography_prep import indenter_heights
        return indenter_heights(surface)
    raise ValueError(f"surface.kind = {surface.kind!r} is not a known profile kind")
