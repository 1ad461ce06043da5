"""What a study task's saved fields cost to write: numpy's savez_compressed (every member deflated, the writer before
session 34) against `gfmd_contact.app.checkpoints._npz_bytes` (a member deflated only where zlib shrinks it).

Usage: python benchmarks/bench_npz.py [--size 17] [--law weak] [--repeats 3] [--out FILE]

One study task of the seed's base scene (`gfmd_contact.app.study.run_task`, realization 2, N = 2^size; --law: weak φn* =
0.001, strong φn* = 0.15, hard-wall) is run once; its fields.npz members and one saved step's checkpoint file
(the step's fields with the ramp's warm start, `checkpoints._save_fields`) are then written by both writers, alternating,
`--repeats` times: CPU s (time.process_time, median) and MB per file. A task writes one such checkpoint file per saved
step and fields.npz once; the per-task saving is measured whole in the closing note (two tasks at once).
"""

from __future__ import annotations

import argparse
import io
import os
import sys
import tempfile
import time
from pathlib import Path

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):  # before numpy: one thread
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import report  # noqa: E402

from gfmd_contact.core.scene import load_scene  # noqa: E402
from gfmd_contact.app import checkpoints, study_task  # noqa: E402
from gfmd_contact.app.study import run_task, task_scene  # noqa: E402

LAWS = {"hard-wall": {"interface.law": "hard-wall"},
        "weak": {"interface.law": "cohesive", "interface.phi_n_star": 0.001, "interface.tangential_ratio": 0.0},
        "strong": {"interface.law": "cohesive", "interface.phi_n_star": 0.15, "interface.tangential_ratio": 0.0}}


def savez_compressed_bytes(arrays):
    """The writer before: numpy's savez_compressed into memory."""
    buf = io.BytesIO()
    np.savez_compressed(buf, **arrays)
    return buf.getvalue()


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=17)
    ap.add_argument("--law", choices=sorted(LAWS), default="weak")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results" / "bench_npz.md"))
    args = ap.parse_args(argv)
    study_task.reuse_freed_arrays()
    base = load_scene(ROOT / "studies" / "seed" / "seed_base.toml")
    scene = task_scene(base.replace(**{"surface.nodes": 2**args.size, **LAWS[args.law]}), 1)
    with tempfile.TemporaryDirectory() as tmp:
        run_task(scene, tmp, progress=lambda step, steps: None)
        with np.load(Path(tmp) / "fields.npz") as z:
            fields = {name: z[name] for name in z.files}
    one_step = sorted({name.split("_")[1] for name in fields if name.startswith("r0_s")})[0]
    step = {name.split("_", 2)[2]: a for name, a in fields.items() if name.startswith(f"r0_{one_step}_")}
    spectrum = np.zeros((1, 2**args.size // 2 + 1), complex)
    spectrum[0] = np.fft.rfft(step["u_z"])
    step.update(ramp_current=spectrum, ramp_previous=spectrum.copy(), ramp_slip_warned=np.bool_(False),
                ramp_counts=np.array([0, 0, 0]))
    files = {"fields.npz (once per task)": fields, f"one saved step's checkpoint ({one_step})": step}
    writers = {"np.savez_compressed": savez_compressed_bytes, "_npz_bytes": checkpoints._npz_bytes}
    lines = report.header(f"Writing a study task's saved fields (N = 2^{args.size}, {args.law})", "bench_npz.py", argv)
    lines += ["| file | members | MB in memory | writer | CPU s (median) | MB written |", "|---|---|---|---|---|---|"]
    for label, arrays in files.items():
        times = {w: [] for w in writers}
        sizes = {}
        for _ in range(args.repeats):
            for w, write in writers.items():
                t0 = time.process_time()
                data = write(arrays)
                times[w].append(time.process_time() - t0)
                sizes[w] = len(data)
        raw = sum(np.asarray(a).nbytes for a in arrays.values()) / 1e6
        for w in writers:
            lines.append(f"| {label} | {len(arrays)} | {raw:.1f} | {w} | {np.median(times[w]):.3f} | "
                         f"{sizes[w] / 1e6:.2f} |")
    report.write(lines, args.out)


if __name__ == "__main__":
    main()
