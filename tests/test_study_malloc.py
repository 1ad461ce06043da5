"""Study tasks reuse freed arrays under Dask's worker environment (`gfmd_contact.app.study_task.reuse_freed_arrays`).

Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536; under glibc that made every
solver array of ≥ 2^14 doubles an mmap that is faulted in anew on each allocation. The check
is by counts, not times: a child process started with that variable allocates and frees a
1 MiB array 200 times and reports its minor page faults, with and without the call. Without
it every allocation faults its 256 pages in (≈ 51 200); with it the array is reused (the
first allocation's faults only). The bound is a quarter of the pages one round would fault,
so it holds for any page size ≤ 16 KiB and fails with a single round trip through mmap.
"""

import json
import os
import subprocess
import sys

import pytest

from gfmd_contact.app import study_task

CHILD = r"""
import json, resource, sys
import numpy as np
from gfmd_contact.app import study_task
fixed = study_task.reuse_freed_arrays() if sys.argv[1] == "fix" else None
x = np.ones(1 << 17); del x  # the first allocation's faults are not counted
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(200):
    x = np.ones(1 << 17)  # 1 MiB, touched
    del x
print(json.dumps({"fixed": fixed, "faults": resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before}))
"""

ROUNDS, PAGES = 200, (1 << 20) // 4096


def _child(mode):
    env = dict(os.environ, MALLOC_TRIM_THRESHOLD_="65536")  # what Dask's nanny sets
    out = subprocess.run([sys.executable, "-c", CHILD, mode], env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc malloc (Linux) only")
def test_tasks_reuse_freed_arrays_under_dask_environment():
    plain, fixed = _child("plain"), _child("fix")
    if not fixed["fixed"]:
        pytest.skip("no glibc mallopt in this C library")
    assert plain["faults"] > ROUNDS * PAGES / 2, plain  # the failure mode exists here
    assert fixed["faults"] < PAGES / 4, fixed


def test_run_task_applies_it(monkeypatch, tmp_path):
    calls = []
    monkeypatch.setattr(study_task, "reuse_freed_arrays", lambda: calls.append(1))
    from gfmd_contact.core.scene import default_scene

    scene = default_scene().replace(**{"surface.nodes": 64, "surface.rollon_wavelength": 1e-7, "loading.steps": 2,
                                       "surface.realizations": 1})
    study_task.run_task(scene, tmp_path / "task", progress=lambda step, steps: None)
    assert calls == [1]
