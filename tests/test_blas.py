"""gfmd.blas: one BLAS thread while a GFMD step relaxes, unless the user set a thread count.

* inside `one_thread` every loaded BLAS library runs one thread, and after it each has its own count again (a
  script's numpy work outside the solver keeps its threads);
* any of the standard thread variables in the environment leaves the libraries alone, and says so;
* `gfmd.chains.relax` runs its algorithms inside it, and every run's meta.json says which held.
"""

import numpy  # noqa: F401 (its BLAS loaded: threadpoolctl controls loaded libraries)
import pytest
import scipy.linalg  # noqa: F401 (and scipy's)
from threadpoolctl import threadpool_info, threadpool_limits

from gfmd import blas


def blas_threads():
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_one_thread_inside_and_the_counts_restored_after():
    if not blas_threads():
        pytest.skip("no BLAS library that threadpoolctl can control is loaded")
    with threadpool_limits(limits=3, user_api="blas"):  # a count other than 1 to come back to
        before = blas_threads()
        with blas.one_thread({}):
            assert blas_threads() == [1] * len(before)
        assert blas_threads() == before


def test_the_users_thread_count_stands():
    environ = {"OPENBLAS_NUM_THREADS": "4"}
    with threadpool_limits(limits=3, user_api="blas"):
        before = blas_threads()
        with blas.one_thread(environ):
            assert blas_threads() == before
    assert blas.state(environ).startswith("as the environment sets them (OPENBLAS_NUM_THREADS=4;")
    assert blas.state({"OMP_NUM_THREADS": "2", "MKL_NUM_THREADS": "1"}) == \
        "as the environment sets them (MKL_NUM_THREADS=1, OMP_NUM_THREADS=2; Dask's nannies set 1 for their workers)"
    assert blas.state({}).startswith("one thread")


def test_relax_runs_its_algorithms_on_one_blas_thread(monkeypatch):
    from gfmd_contact.core import surfaces
    from gfmd_contact.core.loading import indenter_surface
    from gfmd_contact.core.scene import default_scene
    from gfmd import chains
    from gfmd.loading import prepare

    if not blas_threads():
        pytest.skip("no BLAS library that threadpoolctl can control is loaded")
    for name in blas.THREAD_VARIABLES:
        monkeypatch.delenv(name, raising=False)
    seen = []
    for key, solve in list(chains.ALGORITHMS.items()):
        def watched(problem, start, settings, _solve=solve):
            seen.append(blas_threads())
            return _solve(problem, start, settings)
        monkeypatch.setitem(chains.ALGORITHMS, key, watched)
    scene = default_scene().replace(**{"surface.nodes": 1024})
    h = surfaces.profile(scene.surface, 0)
    cell = prepare(scene, h)
    z_ind = indenter_surface(h, 0.0, 1e-9)  # 1 nm into the highest asperity
    with threadpool_limits(limits=3, user_api="blas"):
        before = blas_threads()
        chains.relax(cell.physics, cell.law, z_ind, cell.initial_state(), cell.settings)
        assert blas_threads() == before
    assert seen and all(threads == [1] * len(before) for threads in seen)
    assert any(line.startswith(f"BLAS threads: {blas.state()}") for line in cell.reasons)
