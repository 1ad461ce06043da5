"""The cycle part of a run directory whose loading has a path: extra columns and meta.json.

Units: SI (see `gfmd_contact.core.conventions`). For a scene with `loading.path` (`gfmd_contact.core.loading`):
  curve.csv       + branch ("loading"/"unloading"), cycle (0, 1, ...) and event ("jump-in"/"jump-out"/""):
                  what `gfmd_contact.core.cycle.jump_events` finds at that step (force control: the run's own
                  instability events, `gfmd_contact.core.force`), and under force control `load` (Pa): the
                  prescribed p̄ of the step (`p` is the p̄ reached; they differ where the body detached)
  mean_curve.csv  + branch and cycle per step (realizations share the steps, so the per-step means
                  are per (branch, step) and never mix the branches)
  meta.json       "cycles": per realization, per cycle, `gfmd_contact.core.cycle.cycle_observables` (pull-off,
                  snap-off δ, hysteresis W, events), with "cycle_units" and "cycle_definitions"
A ramp (no path) writes none of these: its files are those of the seed's ramp.
"""

from __future__ import annotations

from gfmd_contact.core import cycle as cyc
from gfmd_contact.core.loading import path_values, step_branches


def has_path(scene):
    return bool(scene.loading.path)


def realization_cycles(scene, curve, instabilities=None):
    """(per-cycle observables, per-step (branch, cycle, event[, load]) columns) of one realization's curve
    (a dict of arrays with delta, p, a_rel); instabilities: a force-controlled run's own events
    (Result.diagnostics["instabilities"], `gfmd_contact.core.force`), used instead of the jumps found in p̄(δ)."""
    branch, cycle = step_branches(scene.loading)
    n = len(curve["delta"])
    given = None
    if scene.loading.control == "force":
        given = [{**e, "branch": str(branch[e["step"]]), "cycle": int(cycle[e["step"]])}
                 for e in (instabilities or []) if e["step"] < n]
    rows = cyc.cycle_observables(curve["delta"], curve["p"], curve["a_rel"], branch[:n], cycle[:n], events=given)
    events = [e for r in rows for e in r["events"]]
    columns = {"branch": list(branch[:n]), "cycle": [int(c) for c in cycle[:n]], "event": cyc.step_events(n, events)}
    if scene.loading.control == "force":  # the prescribed load of each step (p is the p̄ reached)
        columns["load"] = [repr(float(v)) for v in path_values(scene.loading)[:n]]
    return rows, columns


def meta_cycles(results, cycles):
    """meta.json entries of a path run: {"cycles": [{realization, seed, cycles}], units, definitions}; cycles:
    {realization: its per-cycle observables}, the first item of `realization_cycles`."""
    entries = [{"realization": r.realization, "seed": r.seed, "cycles": cycles[r.realization]} for r in results]
    return {"cycles": entries, "cycle_units": cyc.UNITS,
            "cycle_definitions": " ".join(cyc.__doc__.split("\n\n")[2:]).replace("\n", " ")}


def step_loads(scene):
    """The prescribed p̄ (Pa) of every step under force control (the realizations share these, not δ), else None."""
    return path_values(scene.loading) if scene.loading.control == "force" else None


def mean_columns(scene, steps):
    """{"branch", "cycle"} for the mean_curve.csv steps (array of step indices)."""
    branch, cycle = step_branches(scene.loading)
    return {"branch": [branch[k] for k in steps], "cycle": [int(cycle[k]) for k in steps]}


#: columns of a study's cycles.csv after set, the axis columns, realization, seed, task
STUDY_COLUMNS = ("cycle", "pull_off_pressure", "pull_off_delta", "snap_off_delta", "hysteresis", "closed",
                 "jump_in", "jump_out", "snap_off_rule")


def write_study_cycles(study, out, tasks, axis_text, atomic_write):
    """DIR/cycles.csv of a study whose tasks have load paths: one row per (task, cycle) with pull-off
    (Pa, min p̄ on unloading), its δ and the snap-off δ (m), hysteresis W (J/m²), whether the cycle is
    closed, its number of jump-in / jump-out events and the snap-off rule (`gfmd_contact.core.cycle`), from each finished task's meta.json "cycles".
    Nothing is written when no task has a path."""
    import csv
    import io as _io
    import json
    from pathlib import Path

    rows = []
    for t in sorted(tasks, key=lambda t: (t.set, t.realization)):
        meta = Path(out) / "tasks" / t.key / "meta.json"
        if not meta.is_file():
            continue
        entries = json.loads(meta.read_text()).get("cycles") or []
        params = [axis_text(study.sets[t.set][k]) for k in study.keys]
        for e in entries:
            for c in e["cycles"]:
                kinds = [ev["kind"] for ev in c["events"]]
                rows.append([str(t.set)] + params + [str(t.realization), str(t.seed), t.key, str(c["cycle"])]
                            + ["" if c[k] is None else repr(c[k]) if isinstance(c[k], float) else str(c[k])
                               for k in ("pull_off_pressure", "pull_off_delta", "snap_off_delta", "hysteresis",
                                         "closed")]
                            + [str(kinds.count("jump-in")), str(kinds.count("jump-out")),
                               c.get("snap_off_rule") or ""])  # "": no snap-off (or a run before the rule)
    if not rows:
        return None
    buf = _io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(["set"] + list(study.keys) + ["realization", "seed", "task"] + list(STUDY_COLUMNS))
    w.writerows(rows)
    atomic_write(Path(out) / "cycles.csv", buf.getvalue())
    return Path(out) / "cycles.csv"
