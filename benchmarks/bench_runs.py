"""Whole runs: the FE reference against GFMD on one verification scene, and a study task in process, on a Dask worker
and with a checkpoint at every step.

FE vs GFMD: the cohesive sinusoid of the verification suite (`verification.scenes.cohesive_sinusoid`: a = 50 nm,
L = 1 µm, layer D = L, φn* = 0.01, δn = 1 nm) on N surface nodes, its first STEPS load steps, each method as the
scene's [method] section names it (`gfmd_contact.app.methods.run_realization`, FE: P2, linear "auto"); the row gives
the whole run's time per step (setup included) and, for FE, the largest difference of the mean pressure from GFMD's.

Study task: `gfmd_contact.app.study_task.run_task` of the seed base scene (Fig. 3's strong adhesion) at N = 2^e with
a short ramp, into a fresh task directory each round: in this process (checkpoints as the study writes them, one
every CHECKPOINT_SECONDS), on the one worker of the study's local cluster (`gfmd_contact.app.study`, started before
the timing), and in this process with a checkpoint at every step (GFMD_CHECKPOINT_SECONDS = 0).
"""

from __future__ import annotations

import tempfile
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from gfmd_contact.app.methods import run_realization
from gfmd_contact.app.study_task import run_task
from gfmd_contact.core.scene import load_scene

SEED_BASE = Path(__file__).resolve().parents[1] / "studies" / "seed" / "seed_base.toml"
STEPS = 5  # FE vs GFMD: load steps of the verification scene's 3.1 nm increment
INCREMENT = 62e-9 / 20


def fe_scene(nodes, method):
    from verification.scenes import cohesive_sinusoid

    sc = cohesive_sinusoid(nodes)
    return sc.replace(**{"loading.steps": STEPS, "output.field_steps": 0, "method.name": method,
                         "loading.final_penetration": STEPS * INCREMENT - sc.loading.initial_separation})


@cache
def mean_pressures(nodes, method):
    return np.asarray(run_realization(fe_scene(nodes, method)).curve["p"], float)


@pytest.mark.parametrize("method", ["gfmd", "fe"])
def test_fe_vs_gfmd(benchmark, sizes, table, method):
    nodes = sizes["fe_nodes"]
    result = benchmark.pedantic(run_realization, args=(fe_scene(nodes, method),), rounds=max(2, sizes["rounds"] // 2),
                                iterations=1, warmup_rounds=1)
    assert result.all_converged
    p = np.asarray(result.curve["p"], float)
    note = f"{np.median(result.curve['iterations']):.0f} it per step"
    if method == "fe":
        ref = mean_pressures(nodes, "gfmd")
        note += f", max |Δp̄| / max |p̄| vs GFMD {np.max(np.abs(p - ref)) / np.max(np.abs(ref)):.1e}"
    table.add(benchmark, f"{method.upper()} cohesive sinusoid", f"N = {nodes}", per=len(p), note=note)


def task_scene(exponent, steps):
    base = load_scene(SEED_BASE)
    nodes = 2**exponent
    return base.replace(**{"surface.nodes": nodes, "loading.steps": steps, "output.field_steps": 0,
                           "surface.rollon_wavelength": max(base.surface.rollon_wavelength,
                                                            4 * base.surface.length / nodes)})


@pytest.fixture(scope="module")
def dask_client():
    from gfmd_contact.app.study import _client  # the study's local cluster and its settings

    client, cluster = _client(1, None)
    yield client
    client.close()
    cluster.close()


@pytest.mark.parametrize("where", ["in process", "Dask worker", "checkpoint every step"])
def test_study_task(benchmark, sizes, table, request, monkeypatch, where):
    exponent, steps = sizes["task"]
    scene = task_scene(exponent, steps)
    if where == "checkpoint every step":
        monkeypatch.setenv("GFMD_CHECKPOINT_SECONDS", "0")
    run = run_task
    if where == "Dask worker":
        client = request.getfixturevalue("dask_client")

        def run(scene, out, progress):
            return client.submit(run_task, scene, out, progress=progress, pure=False).result()

    with tempfile.TemporaryDirectory() as tmp:
        dirs = (Path(tmp) / f"task{i}" for i in range(1000))
        benchmark.pedantic(run, setup=lambda: ((scene, next(dirs), None), {}), rounds=sizes["rounds"],
                           iterations=1, warmup_rounds=1)
    base = table.extra.get("study task")
    seconds = benchmark.stats.stats.min if benchmark.stats else None
    if where == "in process":
        table.extra["study task"] = seconds
    note = f"{steps}-step task" + (f", × {seconds / base:.3f} in process" if base and seconds else "")
    table.add(benchmark, f"study task, {where}", f"2^{exponent}", per=steps, note=note)


def test_time_estimate(benchmark, sizes, table):
    """The preflight's time estimate (`gfmd_contact.core.cost.estimate_seconds`, stated within ×TIME_FACTOR) beside the
    measured time of the same run: the study task's scene, one realization, in this process."""
    from gfmd_contact.core import cost

    exponent, steps = sizes["task"]
    scene = task_scene(exponent, steps).replace(**{"surface.realizations": 1})
    estimate = cost.estimate_seconds(scene, workers=1)
    with tempfile.TemporaryDirectory() as tmp:
        dirs = (Path(tmp) / f"task{i}" for i in range(1000))
        benchmark.pedantic(run_task, setup=lambda: ((scene, next(dirs), None), {}), rounds=sizes["rounds"],
                           iterations=1, warmup_rounds=1)
    seconds = benchmark.stats.stats.min if benchmark.stats else None
    note = (f"estimate {estimate:.2f} s, measured / estimate {seconds / estimate:.2f} "
            f"(stated within ×{cost.TIME_FACTOR})" if seconds else f"estimate {estimate:.2f} s")
    table.add(benchmark, "time estimate vs run", f"2^{exponent}", per=steps, note=note)
