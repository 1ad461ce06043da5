"""Run the dense surface solves with single-threaded BLAS (threadpoolctl); shared by both FE references
(reference.fem, reference.fem3d): thread plumbing, not physics either checks.

On small, shared machines threaded OpenBLAS spin-waits: a 128×128 Cholesky took
0.25 s with threads vs 0.1 ms single-threaded (measured here). The FE surface
matrices are small (≤ 4096), so one thread is also the fast choice.
"""

from __future__ import annotations

from threadpoolctl import threadpool_limits


def single_thread():
    """A context manager: every loaded BLAS library at one thread inside the block, its own count restored after."""
    return threadpool_limits(limits=1, user_api="blas")
