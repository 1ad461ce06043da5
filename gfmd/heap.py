"""glibc's malloc told to keep a load step's arrays on its heap, set once when `gfmd` is imported.

A step allocates and frees arrays of one field's size many times (a coupled Newton at N = 2^17: 2 MB per (u_x, u_z)
field, a few per GMRES product). glibc serves an allocation above its mmap threshold (128 kB at start, raised
to the size of the last such block freed) by a fresh mmap, and gives the top of its heap back to the system
above the trim threshold (twice that): the pages of such a block are faulted in again, zeroed by the kernel, on
every use; and where MALLOC_TRIM_THRESHOLD_ is set in the environment (Dask's nannies set 65536 for their workers)
the threshold stays at 128 kB for good. Measured on whole 201-step ramps at 2^17, ν = 0.45, realization 2
(docs/design/performance.md; CPU s user + system, page faults): coupled law 47.0 s and 2.7 M
with glibc's defaults, 105.8 s and 33 M under Dask's setting, 35.4 s and 0.07 M with the heap kept (MMAP_THRESHOLD
32 MB, TRIM_THRESHOLD 256 MB, TOP_PAD 64 MB); the normal law 19.0, 36.5 and 17.0 s. The cost: a process keeps up to
TRIM_THRESHOLD of freed memory for reuse instead of returning it.

Set through `mallopt` (ctypes) on Linux with glibc only; nothing where the user set any of glibc's own
MALLOC_MMAP_THRESHOLD_, MALLOC_TRIM_THRESHOLD_, MALLOC_TOP_PAD_ (theirs stand) or ``GFMD_KEEP_HEAP=0``.
"""

from __future__ import annotations

import ctypes
import os
import sys

#: glibc's mallopt parameters (malloc.h) and the values set: arrays up to 32 MB (glibc's largest threshold on 64-bit,
#: a 2^20-node two-component field is 16 MB) from the heap, 256 MB of freed heap kept, the heap grown 64 MB at a time
M_TRIM_THRESHOLD, M_TOP_PAD, M_MMAP_THRESHOLD = -1, -2, -3
SETTINGS = {"MMAP_THRESHOLD": (M_MMAP_THRESHOLD, 32 << 20), "TRIM_THRESHOLD": (M_TRIM_THRESHOLD, 256 << 20),
            "TOP_PAD": (M_TOP_PAD, 64 << 20)}
#: what `keep_heap` did in this process, in words (`gfmd.loading.GfmdCell.reasons`: meta.json's model_reasons)
STATE = "not set"


def keep_heap(environ=None):
    """Set `SETTINGS` by mallopt where glibc is the allocator, unless the environment says otherwise; returns (and
    keeps in STATE) what was done, in words."""
    global STATE
    environ = os.environ if environ is None else environ
    if environ.get("GFMD_KEEP_HEAP", "1").strip().lower() in ("0", "false", "no", "off"):
        STATE = "glibc defaults (GFMD_KEEP_HEAP=0)"
        return STATE
    own = sorted(f"MALLOC_{key}_" for key in SETTINGS if f"MALLOC_{key}_" in environ)
    if own:
        STATE = f"the user's {', '.join(own)}"
        return STATE
    mallopt = _mallopt()
    if mallopt is None:
        STATE = "the platform's allocator (not glibc)"
        return STATE
    failed = [key for key, (param, value) in SETTINGS.items() if mallopt(param, value) != 1]
    STATE = "glibc heap kept (" + ", ".join(f"{key} {value >> 20} MB" for key, (_, value) in SETTINGS.items()) + \
        (f"; refused: {', '.join(failed)})" if failed else ")")
    return STATE


def _mallopt():
    """glibc's mallopt(int, int) -> int, or None on another platform or C library."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(None)  # the C library this process runs on (find_library would start ldconfig)
        if not hasattr(libc, "gnu_get_libc_version"):  # musl and others: no mallopt semantics to rely on
            return None
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return None
    mallopt.argtypes, mallopt.restype = (ctypes.c_int, ctypes.c_int), ctypes.c_int
    return mallopt
