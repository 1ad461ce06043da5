"""The real FFT the GFMD algorithms use, counting pairs, and the nodal dot products.

Backend: FFTW (pyfftw, a default dependency), else ducc0, else scipy.fft; ``GFMD_FFT=scipy|ducc0|fftw|auto``
(default auto: the fastest installed) chooses (`fft_backend`). Measured per rfft/irfft pair at 2^17
(docs/design/performance.md). FFTW runs plans made once per process, shape and thread (`_fftw_plans`; measured plans
kept as wisdom, `FFTW_MEASURE_FROM`): the input is copied into the plan's aligned buffer, the output written straight
into the aligned array returned (`_execute_into`). The hard-wall
CGs, the cohesive NCG, FIRE on a law with a traction function, Newton–Krylov and the final fields of every step
(`gfmd.stopping.finish`) go through `Fft`; the projected dynamics of the hard wall and of the cohesive wall call
scipy.fft directly (through `rfft_nodes` / `irfft_nodes`, which are exactly those calls in 1+1-D).

2+1-D surfaces (a `gfmd_contact.core.model.Model` with shape (Nx, Ny)): the algorithms see nodal fields as flat
vectors of the N = Nx·Ny nodes (row-major, x first) and spectra as flat vectors of the Nx·(Ny//2 + 1)
modes of the rfft2 half-spectrum (`gfmd.problem.flat_problem`); `Fft` and the helpers here reshape
to the grid, transform over its axes (rfftn / irfftn over (-2, -1)) and flatten again (views, no
copies). One rfft2/irfft2 pair counts as one pair, as in 1+1-D.
"""

from __future__ import annotations

import atexit
import contextlib
import functools
import hashlib
import os
import platform
import sys
import threading
from pathlib import Path

import numpy as np
import scipy.fft

from . import kernels

try:  # a default dependency: a faster real FFT than scipy's (measured 1.4–2× per rfft/irfft pair here)
    import ducc0.fft as _ducc_fft
except ImportError:  # pragma: no cover - depends on the environment
    _ducc_fft = None
try:  # POSIX: the FFTW wisdom file's lock
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None
try:  # a default dependency: FFTW's plans, faster again than ducc0 (docs/design/performance.md)
    import pyfftw as _pyfftw
except ImportError:  # pragma: no cover - depends on the environment
    _pyfftw = None

#: FFTW transforms of at least this many points are planned with FFTW_MEASURE (candidates timed; whole 2^17 ramps
#: took 0.84× ducc0's CPU time with the NCG, 0.79× with the hard wall, 0.88× coupled, docs/design/performance.md), their
#: plans kept as FFTW wisdom in `wisdom_path` under a file lock, so every later process on this machine makes the same
#: plan (the same results bit for bit) at once; smaller ones (and all where no wisdom file can be made) FFTW_ESTIMATE:
#: a plan by heuristics, the same in every process. FFTW_PATIENT instead was measured and dropped:
#: whole ramps only ≈ 5 % faster for ≈ 50 s of planning per shape on each machine's first run (docs/design/solvers.md)
FFTW_MEASURE_FROM = 1 << 14
_FFTW_LOCAL = threading.local()  # {(real shape, axes): _FftwPair}, per thread: a plan's buffers are its own


def fft_backend(name=None):
    """The FFT backend in use: "fftw", "ducc0" or "scipy" (from `name`, else $GFMD_FFT, default "auto": FFTW,
    else ducc0, else scipy, as installed)."""
    return kernels.choose_backend("GFMD_FFT", name, {"fftw": ("pyfftw", _pyfftw is not None),
                                                     "ducc0": ("ducc0", _ducc_fft is not None)}, "scipy")


def backend_words(name=None):
    """`fft_backend` in words for a model description, naming its variable (and how FFTW's plans are made)."""
    backend = fft_backend(name)
    if backend != "fftw":
        return f"{backend} (GFMD_FFT)"
    if wisdom_path() is None:
        return "fftw (GFMD_FFT; every plan FFTW_ESTIMATE, GFMD_FFTW_WISDOM off)"
    return f"fftw (GFMD_FFT; FFTW_MEASURE plans from {FFTW_MEASURE_FROM} points, kept as wisdom: GFMD_FFTW_WISDOM)"


class _FftwPair:
    """FFTW's r2c and c2r plans over `shape` (..., n) along `axes`, sharing one spectrum buffer:
    real_in → spectrum (forward), spectrum → real_out (backward, unnormalised; it overwrites the spectrum)."""

    def __init__(self, shape, axes):
        self.axes = axes
        spectrum_shape = shape[:-1] + (shape[-1] // 2 + 1,)
        self.real_in = _pyfftw.empty_aligned(shape, dtype=float)
        self.spectrum = _pyfftw.empty_aligned(spectrum_shape, dtype=complex)
        self.real_out = _pyfftw.empty_aligned(shape, dtype=float)
        points = int(np.prod([shape[a] for a in axes]))
        self.scale = 1.0 / points
        self.planner = _in_planner_thread(self._make_plans, points)

    def _make_plans(self, points):
        """Both plans (FFTW_MEASURE from FFTW_MEASURE_FROM points where wisdom can be kept); the planner's name."""
        with _PLANNING:  # FFTW's planner is not thread-safe
            if points >= FFTW_MEASURE_FROM and _with_wisdom(self._plan):
                return "FFTW_MEASURE"
            _pyfftw.forget_wisdom()  # FFTW's heuristics alone, as in a process that never read wisdom
            self._plan("FFTW_ESTIMATE")
            return "FFTW_ESTIMATE"

    def _plan(self, planner):
        flags = (planner, "FFTW_DESTROY_INPUT")
        self.forward = _pyfftw.FFTW(self.real_in, self.spectrum, axes=self.axes, direction="FFTW_FORWARD",
                                    flags=flags, threads=1)
        self.backward = _pyfftw.FFTW(self.spectrum, self.real_out, axes=self.axes, direction="FFTW_BACKWARD",
                                     flags=flags, threads=1)


_PLANNING = threading.Lock()
_INTERRUPTED_PLANS = []  # the end events of plans whose caller was interrupted (`_in_planner_thread`)


@atexit.register
def _exit_before_fftw_cleanup():
    """At exit, a plan an interrupt left running would meet pyfftw's fftw_cleanup (SIGSEGV, seen at 2^22 points):
    the process ends here instead, as interrupted (exit 130), its output flushed."""
    if not all(finished.is_set() for finished in _INTERRUPTED_PLANS):
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        os._exit(130)


def _in_planner_thread(work, *args):
    """work(*args) in a helper thread, this thread waiting for it: pyfftw releases the GIL while FFTW plans, so a
    signal reaches this thread at once (Ctrl-C within a second of a FFTW_MEASURE plan that takes minutes at 2^22
    points, docs/design/preflight.md) with the same plan, the same bits. An interrupted plan goes on in the background
    and keeps `_PLANNING` until it ends (the next plan waits); work's exception is raised here."""
    done, finished = {}, threading.Event()

    def target():
        try:
            done["value"] = work(*args)
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting thread
            done["error"] = exc
        finally:
            finished.set()

    threading.Thread(target=target, name="gfmd-fftw-planner", daemon=True).start()
    try:  # not Thread.join: interrupted, it marks a running thread stopped (its tstate lock looks taken)
        finished.wait()  # interruptible: a signal's handler runs here while FFTW plans
    except BaseException:
        _INTERRUPTED_PLANS.append(finished)
        raise
    if "error" in done:
        raise done["error"]
    return done["value"]


@functools.cache
def _machine_tag():
    """This machine's CPU and FFTW in 12 hex digits: wisdom is valid for one CPU model and FFTW build only."""
    cpu = ""
    try:
        with open("/proc/cpuinfo") as f:
            cpu = "".join(sorted({line for line in f if line.startswith(("model name", "flags"))}))
    except OSError:
        pass
    text = "|".join((platform.machine(), platform.processor(), cpu, getattr(_pyfftw, "__version__", "")))
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def wisdom_path():
    """Where FFTW wisdom is kept: $GFMD_FFTW_WISDOM (a directory; "off": none, every plan FFTW_ESTIMATE), else
    $XDG_CACHE_HOME/gfmd-contact, else ~/.cache/gfmd-contact; one file per machine (`_machine_tag`)."""
    where = os.environ.get("GFMD_FFTW_WISDOM")
    if where is not None and where.strip().lower() in ("", "off", "0", "no", "false"):
        return None
    base = Path(where) if where else Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "gfmd-contact"
    return base / f"fftw-wisdom-{_machine_tag()}.txt"


def _with_wisdom(plan):
    """plan("FFTW_MEASURE") under the wisdom file's lock: the file's wisdom read first (a plan FFTW has timed
    before is made again at once, the same plan), written back after (atomically), then forgotten in this process.
    False where no wisdom file can be kept (an unmakeable directory, no file locks, $GFMD_FFTW_WISDOM = "off"): the
    caller plans FFTW_ESTIMATE instead. Where the file cannot be written (a full disk) the plan holds in this process
    alone."""
    path = wisdom_path()
    if path is None:
        return False
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        lock = open(path.with_suffix(".lock"), "a")
    except OSError:
        return False
    with lock:
        if fcntl is not None:
            try:
                fcntl.flock(lock, fcntl.LOCK_EX)
            except OSError:  # a file system without locks (some network mounts): no shared plans
                return False
        try:
            known = path.read_bytes()
        except OSError:
            known = b""
        if known:
            current = _pyfftw.export_wisdom()
            _pyfftw.import_wisdom((known, current[1], current[2]))  # a corrupt file is ignored (False)
        plan("FFTW_MEASURE")
        wisdom = _pyfftw.export_wisdom()[0]
        _pyfftw.forget_wisdom()  # in memory only while planning: a later FFTW_ESTIMATE plan never sees it
        if wisdom != known:
            tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
            try:
                tmp.write_bytes(wisdom)
                os.replace(tmp, path)
            except OSError:  # a full or read-only disk: this plan holds in this process alone
                with contextlib.suppress(OSError):
                    tmp.unlink()
    return True


def _fftw_plans(shape, axes):
    """This thread's `_FftwPair` for real arrays of `shape` transformed along `axes` (made on first use)."""
    plans = getattr(_FFTW_LOCAL, "plans", None)
    if plans is None:
        plans = _FFTW_LOCAL.plans = {}
    key = (tuple(shape), tuple(axes))
    pair = plans.get(key)
    if pair is None:
        pair = plans[key] = _FftwPair(key[0], key[1])
    return pair


def _execute_into(plan, source, out, home):
    """Run `plan` from `source` into `out` (aligned as its own output, `home`), then point it back at `home`: the
    caller's array is FFTW's output, no copy of it. Whole 201-step ramps at 2^17 against copying out
    (docs/design/performance.md, the same states bit for bit): φn* = 0.15 CPU × 0.92 ± 0.14,
    the hard wall × 0.99 ± 0.12 (± this machine's noise between the two core placements)."""
    plan.update_arrays(source, out)
    try:
        plan.execute()
    finally:
        plan.update_arrays(source, home)
    return out


def _fftw_r2c(x, axes):
    pair = _fftw_plans(x.shape, axes)
    pair.real_in[...] = x
    return _execute_into(pair.forward, pair.real_in, _pyfftw.empty_aligned(pair.spectrum.shape, dtype=complex),
                         pair.spectrum)


def _fftw_r2c_scratch(x):
    """`_fftw_r2c` of a 1-D x that the transform may overwrite, straight from x where x is aligned as the plan's input
    (no copy in; the plan pointed back at its own input after)."""
    if x.dtype != np.float64 or not x.flags.c_contiguous or x.ctypes.data % _pyfftw.simd_alignment:
        return _fftw_r2c(x, (-1,))
    pair = _fftw_plans(x.shape, (-1,))
    plan, out = pair.forward, _pyfftw.empty_aligned(pair.spectrum.shape, dtype=complex)
    plan.update_arrays(x, out)
    try:
        plan.execute()
    finally:
        plan.update_arrays(pair.real_in, pair.spectrum)
    return out


def _fftw_c2r(x_hat, shape, axes):
    """The unnormalised c2r of x_hat · 1/points (the scale taken in the copy in; without round-off where points is a
    power of two, as were the nodal values scaled after)."""
    pair = _fftw_plans(shape, axes)
    np.multiply(x_hat, pair.scale, out=pair.spectrum)
    return _execute_into(pair.backward, pair.spectrum, _pyfftw.empty_aligned(pair.real_out.shape, dtype=float),
                         pair.real_out)


def _grid(grid):
    """(N,) for a node count or a 1-tuple, (Nx, Ny) for a 2-D grid."""
    return (int(grid),) if np.ndim(grid) == 0 else tuple(int(g) for g in grid)


def _half_spectrum(grid):
    return grid[:-1] + (grid[-1] // 2 + 1,)


def rfft_nodes(x, grid):
    """The rfft of nodal fields x (..., N) by scipy.fft: scipy.fft.rfft(x) on a profile; on a grid (Nx, Ny)
    rfftn over the grid's axes, flattened to (..., Nx·(Ny//2 + 1))."""
    grid = _grid(grid)
    if len(grid) == 1:
        return scipy.fft.rfft(x, axis=-1)
    x = np.asarray(x)
    lead = x.shape[:-1]
    return scipy.fft.rfftn(x.reshape(lead + grid), axes=(-2, -1)).reshape(lead + (-1,))


def irfft_nodes(x_hat, grid):
    """The inverse of `rfft_nodes` (flat nodal fields (..., N)) by scipy.fft."""
    grid = _grid(grid)
    if len(grid) == 1:
        return scipy.fft.irfft(x_hat, n=grid[0], axis=-1)
    x_hat = np.asarray(x_hat)
    lead = x_hat.shape[:-1]
    return scipy.fft.irfftn(x_hat.reshape(lead + _half_spectrum(grid)), s=grid, axes=(-2, -1)).reshape(lead + (-1,))


class Fft:
    """rfft / irfft along the last axis (length n) through the chosen backend, counting pairs.

    grid = (Nx, Ny): a 2+1-D surface; nodal fields (..., n = Nx·Ny) and spectra (..., Nx·(Ny//2 + 1))
    are flat and transformed over the grid's two axes (module docstring). grid None or (n,): 1+1-D.
    """

    def __init__(self, n, backend=None, grid=None):
        self.n, self.backend, self.calls = n, fft_backend(backend), 0
        self._spectrum = None  # `apply_to`'s preallocated spectrum (ducc0)
        self.grid = _grid(grid) if grid is not None and len(_grid(grid)) > 1 else None
        if self.grid is not None:
            if int(np.prod(self.grid)) != n:
                raise ValueError(f"Fft: grid {self.grid} does not hold n = {n} nodes")
            self.axes = (-2, -1)
            self.spectrum_grid = _half_spectrum(self.grid)

    def rfft(self, x):
        self.calls += 1
        if self.grid is not None:
            return self._rfft2(x)
        if self.backend == "fftw":
            return _fftw_r2c(x, (-1,))
        if self.backend == "ducc0":
            return _ducc_fft.r2c(np.ascontiguousarray(x), axes=(-1,), forward=True)
        return scipy.fft.rfft(x, axis=-1)

    def rfft_scratch(self, x):
        """`rfft` of x (N,), which it may overwrite: with FFTW straight from x where x is aligned as its plans' input
        (`empty_nodes`), no copy."""
        if self.backend == "fftw" and self.grid is None and x.ndim == 1:
            self.calls += 1
            return _fftw_r2c_scratch(x)
        return self.rfft(x)

    def empty_nodes(self):
        """An empty nodal field (N,), aligned as FFTW's plans want their input (`rfft_scratch`)."""
        if self.backend == "fftw":
            return _pyfftw.empty_aligned(self.n, dtype=float)
        return np.empty(self.n)

    def irfft(self, x_hat):
        self.calls += 1
        if self.grid is not None:
            return self._irfft2(x_hat)
        if self.backend == "fftw":
            return _fftw_c2r(x_hat, x_hat.shape[:-1] + (self.n,), (-1,))
        if self.backend == "ducc0":
            return _ducc_fft.c2r(np.ascontiguousarray(x_hat), axes=(-1,), forward=False, lastsize=self.n, inorm=2)
        return scipy.fft.irfft(x_hat, n=self.n, axis=-1)

    def _rfft2(self, x):
        x = np.ascontiguousarray(x)
        lead = x.shape[:-1]
        x = x.reshape(lead + self.grid)
        if self.backend == "fftw":
            return _fftw_r2c(x, self.axes).reshape(lead + (-1,))
        if self.backend == "ducc0":
            out = _ducc_fft.r2c(x, axes=self.axes, forward=True)
        else:
            out = scipy.fft.rfftn(x, axes=self.axes)
        return out.reshape(lead + (-1,))

    def _irfft2(self, x_hat):
        x_hat = np.ascontiguousarray(x_hat)
        lead = x_hat.shape[:-1]
        x_hat = x_hat.reshape(lead + self.spectrum_grid)
        if self.backend == "fftw":
            return _fftw_c2r(x_hat, lead + self.grid, self.axes).reshape(lead + (-1,))
        if self.backend == "ducc0":
            out = _ducc_fft.c2r(x_hat, axes=self.axes, forward=False, lastsize=self.grid[-1], inorm=2)
        else:
            out = scipy.fft.irfftn(x_hat, s=self.grid, axes=self.axes)
        return out.reshape(lead + (-1,))

    def apply(self, kernel, x):
        """irfft(kernel · rfft(x)): one pair."""
        x_hat = self.rfft(x)
        x_hat *= kernel
        return self.irfft(x_hat)

    def apply_to(self, kernel, x, out):
        """out ← irfft(kernel · rfft(x)) for 1-D x: one pair; with ducc0 single-threaded and without
        allocating (preallocated spectrum, c2r into `out`, overwriting the spectrum)."""
        self.calls += 2
        if self.grid is not None:
            return self._apply_to2(kernel, x, out)
        if self.backend == "fftw":
            return _fftw_apply_to(kernel, x, out, x.shape, (-1,))
        if self.backend == "ducc0":
            if self._spectrum is None:
                self._spectrum = np.empty(self.n // 2 + 1, complex)
            spectrum = _ducc_fft.r2c(x, axes=(-1,), forward=True, out=self._spectrum, nthreads=1)
            spectrum *= kernel
            return _ducc_fft.c2r(spectrum, axes=(-1,), forward=False, lastsize=self.n, inorm=2, out=out,
                                 nthreads=1, allow_overwriting_input=True)
        out[...] = scipy.fft.irfft(kernel * scipy.fft.rfft(x), n=self.n)
        return out

    def _apply_to2(self, kernel, x, out):
        """`apply_to` on a 2-D grid (flat x, out of n nodes; kernel flat over the half-spectrum)."""
        if self.backend == "fftw":
            _fftw_apply_to(np.reshape(kernel, self.spectrum_grid), np.reshape(x, self.grid), out.reshape(self.grid),
                           self.grid, self.axes)
            return out
        if self.backend == "ducc0":
            if self._spectrum is None:
                self._spectrum = np.empty(self.spectrum_grid, complex)
            spectrum = _ducc_fft.r2c(np.ascontiguousarray(x).reshape(self.grid), axes=self.axes, forward=True,
                                     out=self._spectrum, nthreads=1)
            spectrum.reshape(-1)[...] *= kernel
            _ducc_fft.c2r(spectrum, axes=self.axes, forward=False, lastsize=self.grid[-1], inorm=2,
                          out=out.reshape(self.grid), nthreads=1, allow_overwriting_input=True)
            return out
        spectrum = scipy.fft.rfftn(np.reshape(x, self.grid), axes=self.axes)
        spectrum *= np.reshape(kernel, self.spectrum_grid)
        out[...] = scipy.fft.irfftn(spectrum, s=self.grid, axes=self.axes).reshape(-1)
        return out

    @property
    def pairs(self):
        return self.calls / 2


def _fftw_apply_to(kernel, x, out, shape, axes):
    """out ← irfft(kernel · rfft(x)) on one `_FftwPair`: the spectrum never leaves its buffer."""
    pair = _fftw_plans(shape, axes)
    pair.real_in[...] = x
    pair.forward.execute()
    pair.spectrum *= kernel
    pair.backward.execute()
    np.multiply(pair.real_out, pair.scale, out=out)
    return out


def dot(a, b):
    """Σ a_j b_j without BLAS: multi-threaded BLAS dot products of 1-D arrays stalled
    the solver 4× on a loaded 2-core machine (measured: 15.2 s vs 3.6 s per step at N = 2^17)."""
    if a.ndim != 1:  # 2+1-D fields on their grid: the same sum over the flattened nodes
        return float(np.einsum("i,i->", a.ravel(), b.ravel()))
    return float(np.einsum("i,i->", a, b))


def spectral_weights(nodes):
    """w_n with Σ_j a_j b_j = (1/N) Σ_n w_n Re(conj(â_n) b̂_n) for rfft spectra.

    `nodes`: N (or (N,)) for a profile; a grid (Nx, Ny) for the rfft2 half-spectrum of a surface, flat
    (Nx·(Ny//2 + 1),): every mode with 0 < q_y-index < Ny/2 stands for itself and its conjugate (w = 2),
    the q_y = 0 column and, for even Ny, the Nyquist column hold their own conjugates (w = 1).
    """
    grid = _grid(nodes)
    if len(grid) > 1:
        w = np.full(_half_spectrum(grid), 2.0)
        w[..., 0] = 1.0
        if grid[-1] % 2 == 0:
            w[..., -1] = 1.0
        return w.reshape(-1)
    nodes = grid[0]
    w = np.full(nodes // 2 + 1, 2.0)
    w[0] = 1.0
    if nodes % 2 == 0:
        w[-1] = 1.0
    return w
