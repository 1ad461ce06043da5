"""One BLAS thread while GFMD relaxes a load step, through threadpoolctl.

GFMD's dense linear algebra is small: GMRES's Gram–Schmidt over ≤ 60 basis vectors, coarse spaces of a few hundred
unknowns factored by LU. Threaded OpenBLAS (numpy's and scipy's start one thread per core) gains nothing there and
spin-waits: on a 2-core machine whose other core is busy, or in `gfmd run --workers 2`'s forked processes (each
with a thread per core), a step's `ndarray.dot` and `lu_factor` wait for threads that do not come (a profiled coupled
ramp at 2^15: 19.4 s in `dot` and 12.1 s in `lu_factor` with two threads, against a whole ramp of 18.7 s with one).
Measured with `gfmd run` at 2^15, 2 realizations (docs/design/performance.md, best wall s of two,
OpenBLAS's two threads / one): the coupled law (ν = 0.1) 100.9 / 16.6 s with --workers 2 and 59.3 / 30.4 s with
one process; the normal cohesive law 13.7 / 6.8 s and 10.4 / 10.2 s; the hard wall 5.6 / 3.9 s and 5.8 / 5.5 s.
Dask's nannies already start study workers with ``OPENBLAS_NUM_THREADS=1``, and so do our benchmarks: this makes
the default what they measured.

`one_thread()` (and `on_one_thread`, around `gfmd.chains.relax`) limits every BLAS library loaded in the process
to one thread for the duration of a `with` block and restores the counts after it, so a script's own numpy work
outside the solver keeps its threads. Nothing is changed where the user set a thread count in the environment
(`THREAD_VARIABLES`: theirs stands).
"""

from __future__ import annotations

import contextlib
import functools
import os

#: the environment variables by which a user sets BLAS threads (OpenBLAS, MKL, BLIS and OpenMP's): any one of them
#: set, `one_thread` leaves the libraries alone
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "OMP_NUM_THREADS")
_CONTROLLER = None  # threadpoolctl.ThreadpoolController, made at the first `one_thread` (after scipy's BLAS loaded)


def state(environ=None):
    """What `one_thread` does in this environment, in words (`gfmd.loading.GfmdCell.reasons`: meta.json)."""
    environ = os.environ if environ is None else environ
    own = [f"{name}={environ[name]}" for name in THREAD_VARIABLES if name in environ]
    if own:
        return f"as the environment sets them ({', '.join(own)}; Dask's nannies set 1 for their workers)"
    return "one thread while a step relaxes (gfmd.blas; OPENBLAS_NUM_THREADS in the environment overrides it)"


def one_thread(environ=None):
    """A context manager: every loaded BLAS library at one thread inside it, its own count restored after; a
    no-op where the environment sets a thread count (`THREAD_VARIABLES`)."""
    environ = os.environ if environ is None else environ
    if any(name in environ for name in THREAD_VARIABLES):
        return contextlib.nullcontext()
    global _CONTROLLER
    if _CONTROLLER is None:
        from threadpoolctl import ThreadpoolController
        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER.limit(limits=1, user_api="blas")


def on_one_thread(function):
    """`function` run inside `one_thread()` at every call (`gfmd.chains.relax`)."""
    @functools.wraps(function)
    def on_one(*args, **kwargs):
        with one_thread():
            return function(*args, **kwargs)
    return on_one
