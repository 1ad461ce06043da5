"""Measured numbers that tolerances are derived from: `verification/data/<study>.json`.

The study that measures them writes the file (`python -m verification.studies.<study> --write`);
the test reads it to set its bound (`value(study, key, name)`), so a bound follows the
measurement it was derived from and the rule that derives it stays in the test. Layout:

    {"study": "verification.studies.<study>", "regenerate": "<command>", "description": "…",
     "entries": {key: {"code_version", "date", "scene", "values": {…}, …}}}

Each entry carries its own code version, date (UTC) and scene (`gfmd_contact.core.scene.scene_to_dict`, or
the catalogue factory that builds it); writing replaces the entries measured and keeps the others.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
from pathlib import Path

DATA_DIR = Path(__file__).resolve().parent / "data"
SIGNIFICANT_DIGITS = 4  # of the measured numbers stored (floats; ints are stored as they are)
LINE_WIDTH = 160  # of the data files


#: every look-up since the last `reset_accesses()`: ("study", key or None, name or None, value or None);
#: the verification fixture turns them into a record's `measured_source` (the list of tolerances)
ACCESSES: list = []


def reset_accesses():
    """Start a fresh access log; returns its start index."""
    return len(ACCESSES)


def accessed_sources(start=0):
    """The look-ups since `start` as lines "verification.studies.<study> → verification/data/<study>.json
    [key].name", in order, without repeats."""
    out = []
    for study, key, name, _ in ACCESSES[start:]:
        where = f"verification.studies.{study} → verification/data/{study}.json"
        if key is not None:
            where += f" [{key}]" + (f".{name}" if name is not None else "")
        if where not in out:
            out.append(where)
    # drop a bare "[key]" line when the same entry's ".name" is listed too
    return [w for w in out if not any(o != w and o.startswith(w) for o in out)]


class MissingMeasurement(LookupError):
    """A test asked for a measured number that its data file does not hold."""


def path(study):
    return DATA_DIR / f"{study}.json"


def regenerate_command(study, *args):
    return " ".join(["python -m", f"verification.studies.{study}", "--write", *args])


def load(study):
    """The whole document of `verification/data/<study>.json`."""
    p = path(study)
    if not p.exists():
        raise MissingMeasurement(f"{p} does not exist: run `{regenerate_command(study)}`")
    ACCESSES.append((study, None, None, None))
    return json.loads(p.read_text(encoding="utf-8"))


def entry(study, key):
    """The entry `key` (a dict with its provenance and "values")."""
    entries = load(study)["entries"]
    ACCESSES.append((study, key, None, None))
    if key not in entries:
        raise MissingMeasurement(f"no measured entry {key!r} in {path(study)}: run `{regenerate_command(study)}` "
                                 f"(with --full for the slow cells); entries: {sorted(entries)}")
    return entries[key]


def value(study, key, name):
    """One measured number: entries[key]["values"][name]."""
    values = entry(study, key)["values"]
    if name not in values:
        raise MissingMeasurement(f"{path(study)}: entry {key!r} has no value {name!r} ({sorted(values)})")
    ACCESSES.append((study, key, name, values[name]))
    return values[name]


def node_count(a_rel_difference, nodes):
    """|Δa_rel| on N = `nodes` as the whole number of nodes it is (a_rel counts nodes: quantised by 1/N).

    Stored as an int, so that a bound "stored + k nodes" keeps its margin: the float |Δa_rel| rounded
    to SIGNIFICANT_DIGITS (1/256 → 0.003906) is below the count, and stored + 1/N then falls 2.4e-7
    short of the next count (a difference of exactly one more node would fail). Round-off below
    1e-6 node is not a node; a difference that is not a whole count rounds up (a larger bound)."""
    return int(math.ceil(a_rel_difference * nodes - 1e-6))


def make_entry(values, scene=None, **extra):
    """An entry measured now: code version, date, scene (a Scene is stored as its dict), values."""
    from gfmd_contact.app.io import code_version

    from .records import to_jsonable
    if scene is not None and not isinstance(scene, (str, dict)):
        from gfmd_contact.core.scene import scene_to_dict
        scene = scene_to_dict(scene)
    return _rounded(to_jsonable({"code_version": code_version(),
                                 "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                                 "scene": scene, **extra, "values": values}))


def _rounded(obj, digits=SIGNIFICANT_DIGITS):
    """Floats to `digits` significant digits (measured numbers, not identities), recursively."""
    if isinstance(obj, float):
        return float(f"{obj:.{digits}g}")
    if isinstance(obj, dict):
        return {k: _rounded(v, digits) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_rounded(v, digits) for v in obj]
    return obj


def _dumps(obj, indent=0, width=LINE_WIDTH):
    """JSON with one key (or list item) a line; whatever fits in `width` characters on one line."""
    flat = json.dumps(obj, ensure_ascii=False, allow_nan=False)
    if not isinstance(obj, (dict, list)) or not obj or indent + len(flat) <= width:
        return flat
    pad = " " * (indent + 1)
    if isinstance(obj, dict):
        items = [f"{pad}{json.dumps(k, ensure_ascii=False)}: {_dumps(v, indent + 1, width)}" for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + " " * indent + "}"
    return "[\n" + ",\n".join(pad + _dumps(v, indent + 1, width) for v in obj) + "\n" + " " * indent + "]"


def write(study, entries, description=""):
    """Merge `entries` {key: make_entry(…)} into `verification/data/<study>.json`; returns its path."""
    p = path(study)
    doc = json.loads(p.read_text(encoding="utf-8")) if p.exists() else {}
    merged = dict(doc.get("entries", {}))
    merged.update(entries)
    doc = {"study": f"verification.studies.{study}", "regenerate": regenerate_command(study),
           "description": description or doc.get("description", ""), "entries": dict(sorted(merged.items()))}
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(_dumps(doc) + "\n", encoding="utf-8")
    return p


