"""Driver of tests/test_crash_consistency.py: SIGKILL a `gfmd run` / `gfmd study run` at seeded random
write events, resume each time, until one attempt completes; prints a JSON report on stdout.

    python tests/crash_driver.py run|study REF_DIR DIR SEED MEAN_GAP [gfmd args ...]

REF_DIR gets the uninterrupted run (in this process for a run, which also warms it up).

Every attempt is a fork of this process (the imports are paid once) that runs `gfmd_contact.cli.main`
with the write functions of `gfmd_contact.app.safe_files` instrumented: each call is three events,
(a) before it, (b) half of the data written (a temporary file cut short, or half a CSV row
appended), (c) after it. An attempt draws k from 1 + Poisson-like geometric(MEAN_GAP) and kills itself
(SIGKILL, no cleanup, no atexit) at its k-th event; at (b) the half-written data is left on disk. A
kill between two events is the same on disk as a kill anywhere during the computation between them
(a load step's solve), so the events enumerate every distinct state a kill can leave. For the study
the Dask cluster is in-process (threads), so the kill takes the whole study, tasks included; the
run uses --workers 1 (a pool worker killed alone is the worker tests' business).
"""

import json
import os
import random
import signal
import sys
import threading
from pathlib import Path


def instrument(target, log_path):
    """Patch safe_files so that this process SIGKILLs itself at its `target`-th write event."""
    from gfmd_contact.app import safe_files

    lock = threading.Lock()
    count = [0]
    real_atomic, real_append = safe_files.atomic_write, safe_files.append_line

    def event(stage, path, partial=None):
        with lock:
            count[0] += 1
            hit = count[0] == target
        if hit:
            if partial is not None:
                partial()
            with open(log_path, "w") as fh:
                json.dump({"event": count[0], "stage": stage, "path": str(path)}, fh)
            os.kill(os.getpid(), signal.SIGKILL)

    def atomic_write(path, data, binary=False):
        path = Path(path)

        def half():
            with open(path.parent / f".{path.name}.killed.tmp", "wb" if binary else "w") as fh:
                fh.write(data[: len(data) // 2])

        event("before", path)
        event("mid", path, half)
        real_atomic(path, data, binary)
        event("after", path)

    def append_line(path, line, header=None):
        def half():
            with open(path, "a") as fh:
                fh.write(line[: len(line) // 2])

        event("before", path)
        event("mid", path, half)
        real_append(path, line, header)
        event("after", path)

    safe_files.atomic_write = atomic_write
    safe_files.append_line = append_line
    return count


def threaded_cluster(workers, scheduler):
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None)
    return Client(cluster), cluster


def attempt(argv, target, log_path):
    """Fork: run main(argv) killing at event `target` (None: never); (outcome, events, kill record)."""
    if os.path.exists(log_path):
        os.unlink(log_path)
    pid = os.fork()
    if pid == 0:
        code = 70
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, 1)
            os.dup2(devnull, 2)
            count = instrument(target, log_path)
            import gfmd_contact.app.study

            gfmd_contact.app.study._client = threaded_cluster
            from gfmd_contact.cli import main

            code = main(argv)
            with open(log_path + ".count", "w") as fh:
                fh.write(str(count[0]))
        finally:
            os._exit(code if isinstance(code, int) else 70)
    _, status = os.waitpid(pid, 0)
    if os.WIFSIGNALED(status):
        assert os.WTERMSIG(status) == signal.SIGKILL, status
        with open(log_path) as fh:
            return "killed", None, json.load(fh)
    with open(log_path + ".count") as fh:
        events = int(fh.read())
    return os.WEXITSTATUS(status), events, None


def progress(kind, out):
    """What was on disk after a kill: saved load steps, and whether the final files were there."""
    out = Path(out)
    dirs = [out] if kind == "run" else sorted((out / "tasks").glob("*")) if (out / "tasks").is_dir() else []
    steps = 0
    for d in dirs:
        meta = d / "meta.json"
        if meta.is_file() and json.loads(meta.read_text()).get("complete"):  # partial/ may be half removed
            steps += sum(1 for _ in open(d / "curve.csv")) - 1
            continue
        for state in (d / "partial").glob("*.state.npz") if (d / "partial").is_dir() else []:
            import numpy as np

            try:
                steps += int(np.load(state)["step"]) + 1
            except Exception:  # noqa: BLE001 - a state being replaced
                pass
    return steps


def warm_up(kind, ref, args):
    """Pay the one-off costs (imports, numba compilation, git describe) in this process, before forking:
    the run's reference runs here; for a study, its first task's scene runs here as a plain run."""
    from gfmd_contact.cli import main as gfmd
    from gfmd_contact.app.io import code_version

    code_version()
    if kind == "run":
        assert gfmd(["run", *args, "--out", ref, "--quiet", "--workers", "1"]) == 0
        return
    import gfmd_contact.app.plots  # noqa: F401
    from gfmd_contact.app.study import load_study

    scratch = Path(ref).parent / ".warm"
    task = load_study(args[0]).tasks[0]
    from gfmd_contact.app.io import prepare_run_dir
    from gfmd_contact.app.ensemble import run_to_directory

    run_to_directory(task.scene, prepare_run_dir(scratch, task.scene), progress=False)


def main():
    kind, ref, out, seed, gap, *args = sys.argv[1:]
    rng = random.Random(int(seed))
    gap = float(gap)
    if kind == "run":
        argv = ["run", *args, "--out", out, "--quiet", "--workers", "1"]
        resume = argv + ["--resume"]
    else:
        argv = ["study", "run", *args, "--out", out, "--quiet", "--workers", "2"]
        resume = argv
    warm_up(kind, ref, args)
    log = str(Path(out).parent / f".{Path(out).name}.kill.json")
    if kind == "study":
        assert attempt(["study", "run", *args, "--out", ref, "--quiet", "--workers", "2"], None, log)[0] == 0
    kills, outcome, events = [], None, None
    current = argv
    for _ in range(500):
        target = 1 + int(rng.expovariate(1 / gap)) if gap > 0 else None
        outcome, events, record = attempt(current, target, log)
        if outcome != "killed":
            break
        record["steps_on_disk"] = progress(kind, out)
        record["path"] = os.path.relpath(record["path"], out)
        kills.append(record)
        current = resume
    print(json.dumps({"exit": outcome, "events_of_last_attempt": events, "kills": kills}))


if __name__ == "__main__":
    main()
