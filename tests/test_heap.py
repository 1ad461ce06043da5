"""gfmd.heap: glibc's malloc told to keep a step's arrays on its heap when gfmd is imported, unless told not to.

* GFMD_KEEP_HEAP=0 leaves glibc's defaults, and glibc's own MALLOC_*_ variables stand where the user set them;
* on Linux with glibc every mallopt call is accepted (no setting "refused");
* what was done is in words in every run's backends line (meta.json), so a timing says which allocator ran.
"""

import sys

import pytest

from gfmd import heap


@pytest.fixture
def kept_state(monkeypatch):
    monkeypatch.setattr(heap, "STATE", heap.STATE)  # this process's words restored after the test


def test_opt_out_and_the_users_own_settings(kept_state):
    assert heap.keep_heap({"GFMD_KEEP_HEAP": "0"}) == "glibc defaults (GFMD_KEEP_HEAP=0)"
    assert heap.keep_heap({"GFMD_KEEP_HEAP": "off"}).startswith("glibc defaults")
    words = heap.keep_heap({"MALLOC_TOP_PAD_": "0", "MALLOC_MMAP_THRESHOLD_": "131072"})
    assert words == "the user's MALLOC_MMAP_THRESHOLD_, MALLOC_TOP_PAD_"


@pytest.mark.skipif(heap._mallopt() is None, reason="not Linux with glibc")
def test_glibc_accepts_every_setting(kept_state):
    words = heap.keep_heap({})
    assert words.startswith("glibc heap kept") and "refused" not in words
    for key, (_, value) in heap.SETTINGS.items():
        assert f"{key} {value >> 20} MB" in words


def test_other_platforms_say_so(kept_state, monkeypatch):
    monkeypatch.setattr(sys, "platform", "darwin")
    assert heap.keep_heap({}) == "the platform's allocator (not glibc)"


def test_the_run_records_the_allocator():
    from gfmd_contact.core.scene import default_scene
    from gfmd_contact.core import surfaces
    from gfmd.loading import prepare

    scene = default_scene().replace(**{"surface.nodes": 1024})
    cell = prepare(scene, surfaces.profile(scene.surface, 0))
    assert any(line.startswith(f"memory: {heap.STATE} (gfmd.heap") for line in cell.reasons)
    assert heap.STATE != "not set"  # set at import


def test_our_local_clusters_workers_keep_the_heap():
    """Dask's nannies start workers with MALLOC_TRIM_THRESHOLD_=65536 (and leave it in the parent's environment);
    our local cluster's config removes it, so its workers and this process keep `gfmd.heap`'s settings."""
    import dask
    import distributed  # noqa: F401 (its config)

    from gfmd_contact.app.study import LOCAL_CLUSTER_CONFIG

    assert dask.config.get("distributed.nanny.pre-spawn-environ").get("MALLOC_TRIM_THRESHOLD_") is not None
    with dask.config.set(LOCAL_CLUSTER_CONFIG):  # None: the nanny leaves the variable out (Dask's documented unset)
        assert dask.config.get("distributed.nanny.pre-spawn-environ")["MALLOC_TRIM_THRESHOLD_"] is None
