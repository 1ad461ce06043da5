"""What Dask's own diagnostics cost a study task on our local cluster (issue 24): Dask's defaults against
`gfmd_contact.app.study.LOCAL_CLUSTER_CONFIG`, on the same whole study task.

Usage: python benchmarks/bench_dask_overhead.py [--size 17] [--phi 0.05] [--rounds 2] [--out FILE]

Per round, one after the other, a one-worker LocalCluster with Dask's defaults ("defaults") and one made by
`gfmd_contact.app.study._client` ("ours") each run the study task (`gfmd_contact.app.study_task.run_task`, the seed base scene at
N = 2^size, φn* = --phi, realization 2) as a Dask task. Per run: the task's wall time, the CPU time of the thread that
ran it, of the whole worker process over the task (the difference: the worker's other threads, e.g. Dask's
statistical profiler sampling the task's stack every 10 ms) and of the main process (scheduler, nanny, client) over
the same span. Writes benchmarks/results/bench_dask_overhead.md (or --out).
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "benchmarks")]
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def task(size, phi):
    """Run the study task in this (worker) process: (wall s, task thread CPU s, process CPU s)."""
    import resource
    import tempfile

    sys.path[:0] = [str(ROOT), str(ROOT / "benchmarks")]
    from bench_adhesion_scaling import ramp, task_of

    from gfmd_contact.app.study_task import reuse_freed_arrays, run_task
    reuse_freed_arrays()
    keys = {"interface.phi_n_star": phi, "material.poisson_ratio": 0.45}
    ramp(2**12, "cohesive", max_steps=3, scene_keys=keys)  # compiled kernels and plans warm
    scene, _ = task_of(2**size, "cohesive", 2, keys)
    with tempfile.TemporaryDirectory() as tmp:
        before = resource.getrusage(resource.RUSAGE_SELF)
        wall, thread = time.perf_counter(), time.thread_time()
        run_task(scene, Path(tmp) / "task", progress=lambda *a: None)
        after = resource.getrusage(resource.RUSAGE_SELF)
        return (time.perf_counter() - wall, time.thread_time() - thread,
                after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)


def run(variant, size, phi):
    """(wall, task thread CPU, worker process CPU, main process CPU) of one task on a fresh one-worker cluster."""
    import resource

    from distributed import Client, LocalCluster

    from gfmd_contact.app.study import _client
    if variant == "ours":
        client, cluster = _client(1, None)
    else:
        cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR)
        client = Client(cluster)
    try:
        before = resource.getrusage(resource.RUSAGE_SELF)  # this (main) process, all its threads
        wall, thread, process = client.submit(task, size, phi, pure=False).result()
        after = resource.getrusage(resource.RUSAGE_SELF)
        return wall, thread, process, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    finally:
        client.close()
        cluster.close()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, default=17)
    parser.add_argument("--phi", type=float, default=0.05)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_dask_overhead.md"))
    args = parser.parse_args(argv)
    rows = []
    for r in range(args.rounds):
        for variant in ("defaults", "ours"):
            rows.append((variant, r + 1, *run(variant, args.size, args.phi)))
    lines = [f"# Dask's diagnostics on a study task: defaults against `LOCAL_CLUSTER_CONFIG` (N = 2^{args.size}, "
             f"φn* = {args.phi})", "",
             f"`python benchmarks/bench_dask_overhead.py --size {args.size} --phi {args.phi} --rounds {args.rounds}`; "
             "one-worker local clusters, one task each, one after the other; CPU s.", "",
             "| cluster | round | task wall s | task thread CPU | worker's other threads CPU | main process CPU |",
             "|---|---|---|---|---|---|"]
    for variant, r, wall, thread, process, main_cpu in rows:
        lines.append(f"| {variant} | {r} | {wall:.2f} | {thread:.2f} | {process - thread:.2f} | {main_cpu:.2f} |")
    for variant in ("defaults", "ours"):
        mine = [x for x in rows if x[0] == variant]
        other = sum(x[4] - x[3] for x in mine) / sum(x[3] for x in mine)
        main_share = sum(x[5] for x in mine) / sum(x[2] for x in mine)
        lines.append(f"\n- {variant}: the worker's other threads {100 * other:.1f} % of the task thread's CPU, the main "
                     f"process {100 * main_share:.1f} % of a core over the task's wall time")
    text = "\n".join(lines) + "\n"
    Path(args.out).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
