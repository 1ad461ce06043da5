"""Where, when and at what cost the numbers were made: `provenance()` and the `Meter`.

`provenance()`: code version (`gfmd_contact.app.io.code_version`), platform, python, numpy, scipy,
date, command line, working directory (cached per process).

`Meter`: wall time (`time.perf_counter`) and peak memory of a block. Memory is the delta of
the process's resident-set high-water mark (`ru_maxrss`): free, but only a lower bound (0 when
the block did not exceed the process's earlier peak). `Meter(memory="tracemalloc")` gives the
exact peak of Python/numpy allocations instead, but slows numpy-loop code ~5-10x: never time
with it.
"""

from __future__ import annotations

import datetime as _dt
import os
import platform
import resource
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np

MEMORY_RSS = "ru_maxrss delta (process RSS high-water mark; lower bound, 0 if below earlier peak)"
MEMORY_TRACEMALLOC = "tracemalloc peak (Python/numpy allocations)"

_PROVENANCE = None


def command_line():
    """The command as typed, as far as sys.argv tells ("python -m pytest …" for a -m run)."""
    if not sys.argv:
        return ""
    prog = Path(sys.argv[0])
    head = f"python -m {prog.parent.name}" if prog.name == "__main__.py" else prog.name
    return " ".join([head] + sys.argv[1:])


def provenance(refresh=False):
    """Where and how the numbers were made (cached per process)."""
    global _PROVENANCE
    if _PROVENANCE is None or refresh:
        import scipy

        from gfmd_contact.app.io import code_version
        _PROVENANCE = {
            "code_version": code_version(),
            "platform": platform.platform(),
            "machine": platform.machine(),
            "cpu_count": os.cpu_count(),
            "python": sys.version.split()[0],
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "command": command_line(),
            "cwd": os.getcwd(),
        }
    return dict(_PROVENANCE)


class Meter:
    """Context manager: `with Meter() as m: …` then m.wall_s (s), m.peak_memory_bytes, m.memory_method."""

    def __init__(self, memory="rss"):
        if memory not in ("rss", "tracemalloc", None):
            raise ValueError("memory must be 'rss', 'tracemalloc' or None")
        self.memory = memory
        self.wall_s = None
        self.peak_memory_bytes = None
        self.memory_method = {"rss": MEMORY_RSS, "tracemalloc": MEMORY_TRACEMALLOC, None: ""}[memory]

    def __enter__(self):
        self._rss0 = max_rss_bytes()
        self._started_tm = False
        if self.memory == "tracemalloc":
            if not tracemalloc.is_tracing():
                tracemalloc.start()
                self._started_tm = True
            tracemalloc.reset_peak()
        self._t0 = time.perf_counter()
        return self

    def __exit__(self, *exc):
        self.wall_s = time.perf_counter() - self._t0
        if self.memory == "rss":
            self.peak_memory_bytes = max(0, max_rss_bytes() - self._rss0)
        elif self.memory == "tracemalloc":
            self.peak_memory_bytes = int(tracemalloc.get_traced_memory()[1])
            if self._started_tm:
                tracemalloc.stop()
        return False


def max_rss_bytes():
    """Process resident-set high-water mark (bytes; ru_maxrss is KiB on Linux, bytes on macOS)."""
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(rss if sys.platform == "darwin" else rss * 1024)
