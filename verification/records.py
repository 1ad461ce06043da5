"""Measurement records and their JSON file (`reports/results.json`).

A `Measurement` is one number a verification test measured (an error, a difference, an order)
with its tolerance, where the tolerance comes from, the methods and resolution it compares, its
cost and plots (`verification.plots`). The pytest fixture `verification_record`
(`verification/conftest.py`) makes them; `verification.report` renders them.
Values are usually dimensionless relative errors; SI otherwise (`gfmd_contact.core.conventions`).
"""

from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .plots import validate_plot
from .provenance import provenance

SCHEMA_VERSION = 1


@dataclass
class Measurement:
    """One measured quantity of a verification case."""

    case: str
    metric: str
    value: Any
    tolerance: float | None = None
    tolerance_source: str = ""
    methods: tuple = ()
    resolution: dict = field(default_factory=dict)
    wall_s: float | None = None
    peak_memory_bytes: int | None = None
    memory_method: str = ""
    passed: bool | None = None
    plots: list = field(default_factory=list)
    notes: str = ""
    test: str = ""  # pytest node id, filled by the fixture
    test_outcome: str = ""  # passed/failed/skipped/error, filled at session end
    provenance: dict = field(default_factory=dict)
    scene: str = ""  # the scene measured, as TOML (`gfmd_contact.core.scene.scene_to_toml`); "" if not given
    #: the stored measured number the tolerance rests on (at this record's resolution), None if the
    #: tolerance is a rule (round-off, one node per edge) or the test did not say
    measured: float | None = None
    #: where the numbers behind the tolerance were measured: "study → data file [entry].value", one per
    #: line; filled from the `verification.measured` look-ups the test made if it does not say
    measured_source: str = ""
    #: the tolerance is a lower bound (value ≥ tolerance: an observed order, a refinement ratio, an effect
    #: that must show), not an upper one
    lower_bound: bool = False

    def __post_init__(self):
        self.methods = tuple(self.methods or ())
        self.resolution = dict(self.resolution or {})
        self.plots = list(self.plots or [])
        for plot in self.plots:
            validate_plot(plot)
        self.passed = (verdict(self.value, self.tolerance, self.lower_bound) if self.passed is None
                       else bool(self.passed))
        if self.measured is not None:
            self.measured = float(self.measured)
        if not isinstance(self.scene, str):  # a gfmd_contact.core.scene.Scene
            from gfmd_contact.core.scene import scene_to_toml
            self.scene = scene_to_toml(self.scene)

    def to_dict(self):
        return to_jsonable(dataclasses.asdict(self))

    @classmethod
    def from_dict(cls, d):
        names = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in d.items() if k in names})


def verdict(value, tolerance, lower_bound=False):
    """Default pass/fail: finite scalar value with |value| ≤ tolerance (value ≥ tolerance for a lower bound);
    None if either is missing.

    NaN/inf values fail. Non-scalar values have no default verdict (None).
    """
    if tolerance is None or value is None:
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    if lower_bound:
        return bool(math.isfinite(v) and v >= float(tolerance))
    return bool(math.isfinite(v) and abs(v) <= float(tolerance))


def scene_resolution(scene):
    """Resolution dict of a scene: nodes, spacing, steps, solver tolerance."""
    s = scene.surface
    return {"N": s.nodes, "spacing_m": s.spacing, "L_m": s.length, "steps": scene.loading.steps,
            "solver_tolerance": scene.solver.tolerance}


# --------------------------------------------------------------------------- JSON
def to_jsonable(obj):
    """Recursively convert numpy arrays/scalars, tuples, Paths, dataclasses to JSON types.

    Non-finite floats become None (strict JSON has no NaN/inf); dict keys become str.
    """
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return to_jsonable(dataclasses.asdict(obj))
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, set, frozenset)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, complex):
        return [to_jsonable(obj.real), to_jsonable(obj.imag)]
    if obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, Path):
        return str(obj)
    return repr(obj)


def results_document(records, session=None):
    """The results.json document: schema, provenance, session summary, records."""
    return to_jsonable({"schema": SCHEMA_VERSION, "provenance": provenance(), "session": session or {},
                        "records": [r.to_dict() if isinstance(r, Measurement) else r for r in records]})


def write_results(path, records, session=None):
    """Write results.json (strict JSON); returns the document written."""
    doc = results_document(records, session)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    from gfmd_contact.app.safe_files import atomic_write  # a kill or a full disk never leaves half a results.json

    atomic_write(path, json.dumps(doc, indent=1, allow_nan=False))
    return doc


def load_results(path):
    """Read results.json back: (document dict, [Measurement])."""
    doc = json.loads(Path(path).read_text(encoding="utf-8"))
    return doc, [Measurement.from_dict(d) for d in doc.get("records", [])]


def failure_records(failures, records):
    """A failing Measurement for every test in `failures` ({nodeid: (outcome, text)}) that
    recorded nothing: a test that fails before its first measurement still shows in the summary."""
    recorded = {r.test for r in records}
    out = []
    for nodeid, (outcome, text) in failures.items():
        if nodeid in recorded:
            continue
        case = nodeid.split("::")[0].removeprefix("verification/").removesuffix(".py")
        out.append(Measurement(case=case, metric=f"test {outcome} before it recorded a measurement", value=None,
                               passed=False, notes=text, test=nodeid, test_outcome=outcome))
    return out


# --------------------------------------------------------------------------- the list of tolerances
LOOSE_RATIO = 10.0  # a tolerance more than this many times the number it rests on is flagged "loose"


def _scalar(x):
    try:
        v = float(x)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def tolerance_rows(records):
    """One row per record with a tolerance: the generated list of every verification tolerance.

    {"case", "metric", "test", "tolerance", "basis" ("stored": the study's measured number the test
    derived the bound from; "this run": no stored number given, the value measured now), "measured",
    "ratio" (tolerance / measured; for a lower bound measured / tolerance: how far the bound sits from the
    number it rests on; inf for a measured 0), "value", "source" (tolerance_source), "measured_source"
    (study → data file), "lower" (a lower bound), "loose" (ratio > LOOSE_RATIO)}.
    """
    rows = []
    for r in records:
        tol = _scalar(r.tolerance)
        if tol is None:
            continue
        stored = _scalar(r.measured)
        value = _scalar(r.value)
        basis = "stored" if stored is not None else "this run"
        base = stored if stored is not None else value
        if base is None:
            ratio = None
        elif r.lower_bound:
            ratio = abs(base) / abs(tol) if tol != 0 else math.inf
        else:
            ratio = abs(tol) / abs(base) if base != 0 else math.inf
        rows.append({"case": r.case, "metric": r.metric, "test": r.test, "tolerance": tol, "basis": basis,
                     "measured": base, "ratio": ratio, "value": value, "source": r.tolerance_source,
                     "measured_source": r.measured_source, "lower": r.lower_bound,
                     "loose": ratio is not None and ratio > LOOSE_RATIO})
    return rows
