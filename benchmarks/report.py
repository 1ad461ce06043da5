"""What a benchmark's markdown report starts and ends with: the command, the code version and the load (the
benchmarks of session 32 on; the older ones write their own)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def header(title, script, argv=None, note="2-core machine"):
    """The report's first lines: '# title', then the command as run, the git commit and the load average."""
    args = " ".join(argv if argv is not None else sys.argv[1:])
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True).stdout.strip()
    return [f"# {title}", "", f"`python benchmarks/{script} {args}`; git {head} (+ working tree); load average at "
            f"start {os.getloadavg()[0]:.2f} ({note})", ""]


def write(lines, out):
    """Add the load average at the end, write the report to `out` and print it."""
    text = "\n".join([*lines, "", f"Load average at end: {os.getloadavg()[0]:.2f}."]) + "\n"
    Path(out).write_text(text)
    print(text)


def ramp_differences(rows, reference):
    """(max |Δp̄| / max |p̄|, max |Δa_rel|, steps whose chain label differs) of a ramp's rows against the reference's
    (`benchmarks.bench_adhesion_scaling.ramp` rows, step by step)."""
    import numpy as np

    p, p_ref = (np.array([r["p"] for r in x]) for x in (rows, reference))
    dp = float(np.max(np.abs(p - p_ref)) / np.max(np.abs(p_ref)))
    da = max(abs(a["a_rel"] - b["a_rel"]) for a, b in zip(rows, reference))
    labels = sum(a["method"] != b["method"] for a, b in zip(rows, reference))
    return dp, da, labels


def ramp_row(size, variant, cpus, rows, reference, middle=()):
    """A comparison table's row for one variant's ramps: | 2^size | variant | CPU s of each repeat | median | *middle |
    FFT pairs | event steps | the `ramp_differences` against `reference` (rows, or None: not compared) |."""
    import numpy as np

    dp, da, labels = ramp_differences(rows, reference) if reference else (np.nan, np.nan, "–")
    cells = [f"2^{size}", variant, " / ".join(f"{c:.2f}" for c in cpus), f"{np.median(cpus):.2f}", *middle,
             f"{sum(r['pairs'] for r in rows):.0f}", str(sum(r["method"] != "newton" for r in rows)), f"{dp:.2g}",
             f"{da:.2g}", str(labels)]
    return "| " + " | ".join(cells) + " |"
