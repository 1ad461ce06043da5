"""What a study task's per-step checkpoints cost: one every step against one every CHECKPOINT_SECONDS (issue 24).

Usage: python benchmarks/bench_checkpoints.py [--size 17] [--seconds 0 2] [--out FILE]

Two study tasks of the seed base scene at N = 2^size, surface seed 2: a weak-adhesion task (φn* = 0.001; `run_task`)
and a hard-wall solve shared by three contact rules (traction-tolerance, compressive, gap; `run_shared`, three task
directories, as the sensitivity study runs them). Each is run once per `gfmd_contact.app.checkpoints.CHECKPOINT_SECONDS`
value, one after the other in one process: CPU s, wall s, the state files written and the bytes the checkpoints wrote
(`partial/`), and whether every curve.csv (wall_s aside) and fields.npz equal the first value's. Writes
benchmarks/results/bench_checkpoints.md (or --out).
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from benchmarks.report import header, write  # noqa: E402
from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd_contact.app import checkpoints, safe_files, study_task  # noqa: E402
from gfmd_contact.app.study import task_scene  # noqa: E402

RULES = ("traction-tolerance", "compressive", "gap")
TASKS = {"weak adhesion (φn* = 0.001), one task": ({"interface.law": "cohesive", "interface.phi_n_star": 0.001,
                                                    "interface.tangential_ratio": 0.0}, RULES[:1]),
         "hard wall, one solve for three contact rules": ({"interface.law": "hard-wall"}, RULES)}


def _counted():
    """Count the bytes and state files the checkpoints write (wrapping `safe_files`' writers)."""
    written = {"bytes": 0, "states": 0}
    atomic, append = safe_files.atomic_write, safe_files.append_line

    def atomic_write(path, data, binary=False):
        if checkpoints.PARTIAL in Path(path).parts:
            written["bytes"] += len(data)
            written["states"] += str(path).endswith(".state.npz")
        atomic(path, data, binary=binary)

    def append_line(path, line, header=None):
        if checkpoints.PARTIAL in Path(path).parts:
            written["bytes"] += len(line) + 1
        append(path, line, header=header)

    safe_files.atomic_write, safe_files.append_line = atomic_write, append_line
    return written


def _files(dirs):
    out = []
    for d in dirs:
        with open(Path(d) / "curve.csv") as fh:
            out.append([{k: v for k, v in row.items() if k != "wall_s"} for row in csv.DictReader(fh)])
        with np.load(Path(d) / "fields.npz") as z:
            out.append({k: z[k] for k in z.files})
    return out


def _same(a, b):
    for x, y in zip(a, b):
        if isinstance(x, dict):
            if x.keys() != y.keys() or any(not np.array_equal(x[k], y[k]) for k in x):
                return False
        elif x != y:
            return False
    return True


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--seconds", type=float, nargs="+", default=[0.0, checkpoints.CHECKPOINT_SECONDS])
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_checkpoints.md"))
    args = ap.parse_args(argv)
    study_task.reuse_freed_arrays()
    written = _counted()
    base = load_scene(ROOT / "studies" / "seed" / "seed_base.toml")
    lines = header(f"Per-step checkpoints against one every CHECKPOINT_SECONDS, N = 2^{args.size}", "bench_checkpoints.py",
                   argv)
    lines += ["| task | CHECKPOINT_SECONDS | steps | CPU s | wall s | state files written | MB written | "
              "the same files |", "|---|---|---|---|---|---|---|---|"]
    for name, (keys, rules) in TASKS.items():
        first = None
        for seconds in args.seconds:
            checkpoints.CHECKPOINT_SECONDS = seconds
            with tempfile.TemporaryDirectory() as tmp:
                members = [(task_scene(base.replace(**{"surface.nodes": 2**args.size, **keys,
                                                        "interface.contact_rule": rule}), 1), Path(tmp) / rule)
                           for rule in rules]
                written.update(bytes=0, states=0)
                t0, w0 = time.process_time(), time.perf_counter()
                study_task.run_shared(members, progress=None)
                cpu, wall = time.process_time() - t0, time.perf_counter() - w0
                files = _files([d for _, d in members])
                steps = len(files[0])
            first = first or files
            lines.append(f"| {name} | {seconds:g} | {steps} × {len(rules)} | {cpu:.2f} | {wall:.2f} | "
                         f"{written['states']} | {written['bytes'] / 1e6:.0f} | {'yes' if _same(files, first) else 'NO'} |")
    write(lines, args.out)


if __name__ == "__main__":
    main()
