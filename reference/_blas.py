"""Run the dense surface solves with single-threaded OpenBLAS (no threadpoolctl dependency); shared by
both FE references (reference.fem, reference.fem3d): thread plumbing, not physics either checks.

On small, shared machines threaded OpenBLAS spin-waits: a 128×128 Cholesky took
0.25 s with threads vs 0.1 ms single-threaded (measured here). The FE surface
matrices are small (≤ 4096), so one thread is also the fast choice. Any failure
to find OpenBLAS makes this a no-op.
"""

from __future__ import annotations

import ctypes
import contextlib


def _openblas_handles():
    handles = []
    try:
        with open("/proc/self/maps") as f:
            paths = {line.split()[-1] for line in f if "openblas" in line.lower() and line.rstrip().endswith(".so")
                     or ("openblas" in line.lower() and ".so" in line.split()[-1])}
    except OSError:
        return handles
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for prefix in ("scipy_openblas", "openblas", ""):
            for suffix in ("64_", ""):
                get = getattr(lib, f"{prefix}_get_num_threads{suffix}" if prefix else "openblas_get_num_threads",
                              None)
                set_ = getattr(lib, f"{prefix}_set_num_threads{suffix}" if prefix else "openblas_set_num_threads",
                               None)
                if get is not None and set_ is not None:
                    handles.append((get, set_))
                    break
            else:
                continue
            break
    return handles


@contextlib.contextmanager
def single_thread():
    saved = []
    try:
        for get, set_ in _openblas_handles():
            saved.append((set_, int(get())))
            set_(1)
    except Exception:  # never let thread control break a solve
        pass
    try:
        yield
    finally:
        for set_, n in saved:
            try:
                set_(n)
            except Exception:
                pass
