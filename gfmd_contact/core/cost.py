"""What a run will cost before it starts: an estimate of its peak memory, the memory this process may use, and an
estimate of its wall time (`estimate_seconds`: FFT pairs per step × one pair timed here now, docs/design/preflight.md).

Units: bytes. The estimate is what `gfmd_contact.core.loading.preflight` compares, before any profile or
solver array is allocated, with the least of: the memory the machine has available (MemAvailable), the
cgroup's limit less its usage, and the address-space limit (`ulimit -v`, RLIMIT_AS) less what this process
has mapped. Above it the scene is refused (`check_memory`), naming both numbers and the keys that reduce it.

Model: peak = IMPORTS + workers × (nodes × per-node bytes of the law) + realizations × saved fields, where
nodes = Nx (× Ny), the per-node bytes are the solver's arrays (peak RSS measured in a fresh process over 2^16 …
2^20 nodes and 512² … 1024² surfaces, rounded up so that the estimate stays above each: docs/design/preflight.md)
and a saved field step keeps FIELD_ARRAYS arrays of 8 bytes per node until the run's files are written.
"""

from __future__ import annotations

import functools
import math
import os
import resource
import time

from .errors import SceneError

#: resident memory of the imported solver stack (numpy, scipy, the method: 237 MiB measured) and of what a first
#: step compiles and plans (up to 90 MiB more at 2^16 nodes, docs/design/preflight.md)
IMPORTS = 320 * 2**20
#: solver bytes per node of a profile: hard wall (dual CG), normal laws, a coupled law (u_x and u_z), the FE
#: reference (per surface node of its mesh: measured 463 kB at 512 and 582 kB at 1,024 nodes, layer L/4; it grows
#: faster than N, so it is an estimate at those sizes only)
PER_NODE = {"hard-wall": 1100, "normal": 800, "coupled": 1600, "fe": 600_000}
#: the same per node of a 2+1-D surface (the rfft2 half-spectrum)
PER_NODE_2D = {"hard-wall": 450, "normal": 450, "coupled": 900, "fe": 600_000}
#: arrays kept per saved field step (u_z, u_x, gap, t_n, t_t and the profile), 8 bytes per node each
FIELD_ARRAYS = 6
#: the keys that reduce the estimate, named in a refusal
REDUCING_KEYS = ("surface.nodes", "surface.nodes_y", "output.workers", "output.field_steps")


def _law_kind(scene):
    if scene.method.name == "fe":
        return "fe"
    if scene.interface.law == "hard-wall":
        return "hard-wall"
    return "coupled" if scene.interface.tangential_ratio > 0 else "normal"


def processes(scene, workers=None):
    """How many realizations run at once: `workers` (None: output.workers; 0: the CPU cores), at most the realizations."""
    w = scene.output.workers if workers is None else workers
    w = w or os.cpu_count() or 1
    return max(1, min(int(w), scene.surface.realizations))


def solved_grid(surface):
    """The grid the solver's FFTs run on: the surface's, or on a free boundary its padded cell (2N per axis,
    `gfmd_contact.core.free_boundary`)."""
    return tuple(2 * n for n in surface.shape) if surface.boundary == "free" else tuple(surface.shape)


def estimate_peak_memory(scene, workers=None):
    """Estimated peak memory (bytes) of a run of `scene` with `workers` processes (module docstring)."""
    s = scene.surface
    nodes = s.nodes * max(s.nodes_y, 1)
    solved = math.prod(solved_grid(s))  # a free boundary solves the padded cell
    solver = solved * (PER_NODE_2D if s.two_d else PER_NODE)[_law_kind(scene)]
    fields = s.realizations * min(scene.output.field_steps, scene.loading.steps + 1) * FIELD_ARRAYS * 8 * nodes
    return IMPORTS + processes(scene, workers) * solver + fields


def _meminfo_available():
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024, "available memory (MemAvailable)"
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"), "available memory"
    except (OSError, ValueError, AttributeError):
        return None


def _read_int(path):
    try:
        with open(path, encoding="ascii") as f:
            text = f.read().strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


def _cgroup_free():
    """The cgroup's memory limit less its usage (v2, else v1), or None without a limit."""
    for limit_file, usage_file in (("/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory.current"),
                                   ("/sys/fs/cgroup/memory/memory.limit_in_bytes",
                                    "/sys/fs/cgroup/memory/memory.usage_in_bytes")):
        limit = _read_int(limit_file)
        if limit is not None and limit < 2**60:
            usage = _read_int(usage_file) or 0
            return max(limit - usage, 0), f"the cgroup's memory limit {limit / 2**30:.3g} GiB less its usage"
    return None


def _mapped_bytes():
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("VmSize:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return 0


def _address_space_free():
    """RLIMIT_AS (`ulimit -v`) less what this process has mapped, or None without a limit."""
    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft == resource.RLIM_INFINITY:
        return None
    return (max(soft - _mapped_bytes(), 0),
            f"the address-space limit (ulimit -v) {soft / 2**30:.3g} GiB less the {_mapped_bytes() / 2**30:.3g} GiB "
            "this process has mapped")


def memory_allowed():
    """(bytes, what limits them): the least of the available memory, the cgroup's and `ulimit -v`'s room;
    (None, "") where none can be read."""
    found = [x for x in (_meminfo_available(), _cgroup_free(), _address_space_free()) if x is not None]
    if not found:
        return None, ""
    return min(found, key=lambda x: x[0])


def _size(n):
    return f"{n / 2**30:.3g} GiB" if n >= 2**30 else f"{n / 2**20:.3g} MiB"


def check_memory(scene, workers=None):
    """The estimated peak memory (bytes); refuses (SceneError naming surface.nodes and the keys that reduce it)
    a scene whose estimate exceeds `memory_allowed`, before anything is allocated."""
    need = estimate_peak_memory(scene, workers)
    allowed, what = memory_allowed()
    if allowed is not None and need - IMPORTS > allowed:  # the imports are in memory already
        s = scene.surface
        grid = f"surface.nodes = {s.nodes}" + (f", surface.nodes_y = {s.nodes_y}" if s.two_d else "")
        raise SceneError(
            f"{grid}: the run needs an estimated {_size(need)} of memory at its peak "
            f"({processes(scene, workers)} process(es) × {_law_kind(scene)} solver, {scene.output.field_steps} saved "
            f"field step(s) × {s.realizations} realization(s); gfmd_contact.core.cost), {_size(need - IMPORTS)} more "
            f"than this process holds now, but it may use {_size(allowed)} more ({what}); reduce {', '.join(REDUCING_KEYS)}, or run where more memory is free")
    return need


def describe(need, seconds=None):
    """The estimates in words for the progress line (memory; time where `seconds` is given)."""
    words = f"estimated peak memory {_size(need)}"
    return words if seconds is None else f"{words}, {describe_time(seconds)}"


# --- time -----------------------------------------------------------------------------------------------------
#: FFT pairs per load step of each law's production chain (docs/design/performance.md: the two-level dual CG, the
#: cohesive NCG, the coupled law's Newton chain; 2+1-D: the dual CG and the NCG on 256²–2048²)
PAIRS_PER_STEP = {"hard-wall": 14, "normal": 35, "coupled": 80}
PAIRS_PER_STEP_2D = {"hard-wall": 25, "normal": 28, "coupled": 80}
#: a pair of the solver (FFTW, with the nodal work beside it) in units of the scipy.fft pair `pair_seconds` times,
#: fitted on whole runs (docs/design/preflight.md); the coupled 2+1-D law was not measured (the normal law's)
OVERHEAD = {"hard-wall": 1.3, "normal": 0.54, "coupled": 1.0}
OVERHEAD_2D = {"hard-wall": 0.6, "normal": 2.6, "coupled": 2.6}
#: seconds of Python per FFT pair (the iteration's bookkeeping: what dominates below 2^15 nodes; fitted as above)
PYTHON_PER_PAIR_S = 1.5e-4
#: seconds a process spends on a realization beside its steps: the surface, the model, the first step's compiling
SETUP_S = 0.4
#: the estimate's stated uncertainty: a run takes between 1/TIME_FACTOR and TIME_FACTOR times it (measured)
TIME_FACTOR = 3
#: the largest transform `pair_seconds` times (larger ones are scaled by N log N from it: both out of cache; from
#: 2^18 the scaling fell 2–2.5× short at 2^20, the cache's edge lying between)
TIMED_POINTS_MAX = 1 << 20


@functools.cache
def pair_seconds(grid):
    """Seconds of one rfft/irfft pair (scipy.fft, one thread) over `grid` ((N,) or (Nx, Ny)) on this machine now: the
    least of up to seven timed pairs after one untimed (0.05–0.25 s), above TIMED_POINTS_MAX points timed at that size and
    scaled by N log N. Kept per process, so the progress line and meta.json say the same estimate."""
    import numpy as np
    import scipy.fft

    points = math.prod(grid)
    timed = grid
    if points > TIMED_POINTS_MAX:
        timed = (TIMED_POINTS_MAX,) if len(grid) == 1 else (1024, TIMED_POINTS_MAX // 1024)
    x = np.random.default_rng(0).standard_normal(timed)
    axes = tuple(range(-len(timed), 0))
    best, spent = math.inf, 0.0
    for i in range(8):  # the least of up to 7 timed pairs, within about 0.05 s: the machine's other load varies
        start = time.perf_counter()
        scipy.fft.irfftn(scipy.fft.rfftn(x, axes=axes, workers=1), s=timed, axes=axes, workers=1)
        took = time.perf_counter() - start
        best, spent = (best, 0.0) if i == 0 else (min(best, took), spent + took)
        if spent > 0.05:
            break
    n = math.prod(timed)
    return best * points * math.log2(points) / (n * math.log2(n)) if points > n else best


def estimate_seconds(scene, workers=None):
    """Estimated wall time (s) of a run of `scene` with `workers` processes, None for the FE reference:
    realizations / processes (rounded up) × (SETUP_S + (load steps + 1) × FFT pairs per step × (OVERHEAD ×
    `pair_seconds` + PYTHON_PER_PAIR_S)). An estimate within a factor TIME_FACTOR either way (docs/design/preflight.md);
    a machine's first run at a size adds FFTW's planning (its plans kept as wisdom after, `gfmd.fft`)."""
    kind = _law_kind(scene)
    if kind == "fe":
        return None
    s = scene.surface
    pairs, overhead = (PAIRS_PER_STEP_2D, OVERHEAD_2D) if s.two_d else (PAIRS_PER_STEP, OVERHEAD)
    per_step = pairs[kind] * (overhead[kind] * pair_seconds(solved_grid(s)) + PYTHON_PER_PAIR_S)
    rounds = math.ceil(s.realizations / processes(scene, workers))
    return rounds * (SETUP_S + (scene.loading.steps + 1) * per_step)


def describe_time(seconds):
    """The time estimate in words, with its uncertainty."""
    if seconds is None:
        return "time not estimated (FE)"
    if seconds < 120:
        words = f"{seconds:.2g} s"
    elif seconds < 7200:
        words = f"{seconds / 60:.2g} min"
    else:
        words = f"{seconds / 3600:.3g} h"
    return f"estimated time {words} (within ×{TIME_FACTOR} either way)"
