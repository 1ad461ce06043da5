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


def simultaneous(commands):
    """Run the worker commands (argv lists) as simultaneous processes, the i-th with ``--dump FILE --cpu i`` added
    (it pins itself to core i and writes its rows there as JSON): their rows, in order. SystemExit if one fails."""
    import json
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        dumps = [Path(tmp) / f"{i}.json" for i in range(len(commands))]
        procs = [subprocess.Popen([*cmd, "--dump", str(d), "--cpu", str(i)])
                 for i, (cmd, d) in enumerate(zip(commands, dumps))]
        if any(p.wait() != 0 for p in procs):
            raise SystemExit("a worker failed")
        return [json.loads(d.read_text()) for d in dumps]


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


def event_sweep_row(steps, reference, **label):
    """One row of a coupled sweep (`benchmarks.bench_adhesion_scaling.ramp` rows `steps`): the swept value (`label`),
    the ramp's and its event steps' cost (the steps the continuation Newton gave up, where FIRE ran) and its states
    against `reference` (`ramp_differences`)."""
    events = [s for s in steps if s["method"] != "newton"]
    dp, da, labels = ramp_differences(steps, reference)
    return {**label, "steps": len(steps), "cpu_s": sum(s["cpu"] for s in steps),
            "fft_pairs": sum(s["pairs"] for s in steps), "iterations": sum(s["it"] for s in steps),
            "event_steps": len(events), "event_cpu_s": sum(s["cpu"] for s in events),
            "event_fft_pairs": sum(s["pairs"] for s in events), "converged": sum(s["converged"] for s in steps),
            "dp_rel": dp, "da_rel": da, "labels_differ": labels}


def event_sweep_table(rows, name, value_of):
    """A coupled sweep's table (`event_sweep_row` rows; the first the reference) and its line on the fewest event FFT
    pairs; `name` heads the value column, `value_of(row)` writes a row's value."""
    lines = [f"| {name} | ramp CPU s | FFT pairs | iterations | event steps | event CPU s | event FFT pairs "
             "| converged | max Δp̄ / max p̄ | max Δa_rel | labels differ |", "|" + "---|" * 11]
    for r in rows:
        lines.append(f"| {value_of(r)} | {r['cpu_s']:.1f} | {r['fft_pairs']:.0f} | {r['iterations']} | "
                     f"{r['event_steps']} | {r['event_cpu_s']:.1f} | {r['event_fft_pairs']:.0f} | "
                     f"{r['converged']}/{r['steps']} | {r['dp_rel']:.1e} | {r['da_rel']:.1e} | {r['labels_differ']} |")
    best = min(rows, key=lambda r: r["event_fft_pairs"])
    return lines + ["", f"Fewest FFT pairs on the event steps at {name} = {value_of(best)}: "
                        f"{best['event_fft_pairs']:.0f} against {rows[0]['event_fft_pairs']:.0f} at {value_of(rows[0])} "
                        f"({best['event_fft_pairs'] / rows[0]['event_fft_pairs'] - 1:+.0%}); the whole ramp "
                        f"{best['cpu_s']:.1f} against {rows[0]['cpu_s']:.1f} CPU s."]


def write_event_sweep(rows, data_path, key, out, title, script, argv, name, value_of, same=None):
    """Store a coupled sweep's rows in the JSON file `data_path` under `key` (where `same(row)` is given, added to the
    rows a sweep of the same key stored before, a row of the same value replaced), and write its report to `out`."""
    import json

    data = json.loads(Path(data_path).read_text()) if Path(data_path).exists() else {}
    if same is not None:
        kept = {same(r): r for r in data.get(key, [])}
        kept.update({same(r): r for r in rows})
        rows_stored = list(kept.values())
    else:
        rows_stored = rows
    data[key] = rows_stored
    Path(data_path).write_text(json.dumps(data, indent=1) + "\n")
    write(header(title, script, argv) + event_sweep_table(rows, name, value_of), out)


def event_sweep_arguments(doc, name, values, value_type=str, argv=None):
    """The options the coupled sweeps share (--size, --realization, --nu, --values, --out, --data) parsed, --out
    defaulting to benchmarks/results/<name>_e<size>_nu<ν>_r<realization>.md and --data to <name>.json there."""
    import argparse

    results = ROOT / "benchmarks" / "results"
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--size", type=int, default=15)
    ap.add_argument("--realization", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.1)
    ap.add_argument("--values", type=value_type, nargs="+", default=values)
    ap.add_argument("--out")
    ap.add_argument("--data", default=str(results / f"{name}.json"))
    args = ap.parse_args(argv)
    args.out = args.out or results / f"{name}_e{args.size}_nu{args.nu:g}_r{args.realization}.md"
    return args
