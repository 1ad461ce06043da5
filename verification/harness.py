"""Verification harness: measurement records, declared cases, provenance, JSON.

Plain functions and dataclasses, no pytest dependency (the pytest glue is
`verification/conftest.py`, the HTML is `verification/report.py`).

* `Measurement`: one number a verification test measured (an error, a
  difference) with its tolerance, where the tolerance comes from, the methods
  and resolution it compares, the cost (wall time, peak memory) and plots.
* `Case`: a scene + methods + metrics + tolerance "declared as data";
  `run_case(case)` runs every method on it through the method registry
  `METHODS` (name -> callable(scene) -> `contact.result.Result`), so adding a case
  is a few lines and adding a method is one `register_method` call.
* `Meter`: wall time (`time.perf_counter`) and peak memory of a block.
  Memory is measured as the delta of the process's resident-set high-water
  mark (`resource.getrusage(RUSAGE_SELF).ru_maxrss`): free, but only a lower
  bound (0 when the block did not exceed the process's earlier peak).
  `Meter(memory="tracemalloc")` gives the exact peak of Python/numpy
  allocations instead, but slows numpy-loop code ~5-10x: never time with it.
* `provenance()`: code version (`git describe --always --dirty`, else the
  package version), platform, python, numpy, date, command line.
* JSON: `to_jsonable` (numpy -> lists, non-finite floats -> null),
  `write_results` / `load_results`.

Units: whatever the record says (values are usually dimensionless relative
errors; SI otherwise, see `contact.conventions`).
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import json
import math
import os
import platform
import resource
import subprocess
import sys
import time
import tracemalloc
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

REPO_ROOT = Path(__file__).resolve().parent.parent
SCHEMA_VERSION = 1
PLOT_KINDS = ("profile", "curve", "convergence", "table", "pareto", "grid")
MEMORY_RSS = "ru_maxrss delta (process RSS high-water mark; lower bound, 0 if below earlier peak)"
MEMORY_TRACEMALLOC = "tracemalloc peak (Python/numpy allocations)"


# --------------------------------------------------------------------------- records
@dataclass
class Measurement:
    """One measured quantity of a verification case (see module docstring)."""

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
    scene: str = ""  # the scene measured, as TOML (`contact.scene.scene_to_toml`); "" if not given

    def __post_init__(self):
        self.methods = tuple(self.methods or ())
        self.resolution = dict(self.resolution or {})
        self.plots = list(self.plots or [])
        for plot in self.plots:
            validate_plot(plot)
        self.passed = verdict(self.value, self.tolerance) if self.passed is None else bool(self.passed)
        if not isinstance(self.scene, str):  # a contact.scene.Scene
            from contact.scene import scene_to_toml
            self.scene = scene_to_toml(self.scene)

    def to_dict(self):
        return to_jsonable(dataclasses.asdict(self))

    @classmethod
    def from_dict(cls, d):
        names = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in d.items() if k in names})


def verdict(value, tolerance):
    """Default pass/fail: finite scalar value with |value| ≤ tolerance; None if either is missing.

    NaN/inf values fail. Non-scalar values have no default verdict (None).
    """
    if tolerance is None or value is None:
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return bool(math.isfinite(v) and abs(v) <= float(tolerance))


# --------------------------------------------------------------------------- plots
def validate_plot(plot):
    """Raise ValueError if a plot dict lacks its kind or required keys (see report docstring)."""
    if not isinstance(plot, dict) or plot.get("kind") not in PLOT_KINDS:
        raise ValueError(f"plot must be a dict with kind in {PLOT_KINDS}, got {plot!r:.200}")
    required = {"profile": ("x", "series"), "curve": ("x", "series"), "convergence": ("h", "error"),
                "table": ("columns", "rows"), "pareto": ("points",), "grid": ("columns", "rows")}[plot["kind"]]
    missing = [k for k in required if k not in plot]
    if missing:
        raise ValueError(f"{plot['kind']} plot misses keys {missing}")
    return plot


def profile_plot(x, series, *, xlabel="x", ylabel="", title="", difference=True):
    """Overlay of fields on the same nodes, one line per method; a difference panel when exactly two."""
    return {"kind": "profile", "x": x, "series": dict(series), "xlabel": xlabel, "ylabel": ylabel,
            "title": title, "difference": difference}


def curve_plot(x, series, *, xlabel="", ylabel="", title="", difference=False):
    """Load curves (p–δ, a_rel–δ …): x shared by all series; a difference panel if asked and two series."""
    return {"kind": "curve", "x": x, "series": dict(series), "xlabel": xlabel, "ylabel": ylabel,
            "title": title, "difference": difference}


def convergence_plot(h, error, *, order=None, xlabel="h", ylabel="error", title=""):
    """Log-log error vs resolution; `order` defaults to the least-squares slope of log e vs log h."""
    if order is None:
        order = fitted_order(h, error)
    return {"kind": "convergence", "h": h, "error": error, "order": order, "xlabel": xlabel,
            "ylabel": ylabel, "title": title}


def table_plot(columns, rows, *, title=""):
    return {"kind": "table", "columns": list(columns), "rows": [list(r) for r in rows], "title": title}


def pareto_plot(points, *, xlabel="wall time (s)", ylabel="error", title=""):
    """points: [{"label", "method", "time", "error"}]; log-log scatter, one marker per method."""
    return {"kind": "pareto", "points": list(points), "xlabel": xlabel, "ylabel": ylabel, "title": title}


def grid_plot(columns, rows, *, title=""):
    """Extremes table: rows = [[row label, cell, cell, …]], cell = {"status": "ok"|"fail"|…, "message": str}."""
    return {"kind": "grid", "columns": list(columns), "rows": [list(r) for r in rows], "title": title}


def fitted_order(h, error):
    """Least-squares slope of log(error) vs log(h) over the finite positive points; NaN if < 2."""
    h, e = np.asarray(h, float), np.asarray(error, float)
    ok = np.isfinite(h) & np.isfinite(e) & (h > 0) & (e > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(h[ok]), np.log(e[ok]), 1)[0])


# --------------------------------------------------------------------------- metrics
def relative_l2(a, b, reference=None):
    """‖a − b‖₂ / ‖reference‖₂ (reference defaults to a); 0 if both are zero, inf if only the reference is."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ref = a if reference is None else np.asarray(reference, float)
    num, den = float(np.linalg.norm(a - b)), float(np.linalg.norm(ref))
    if den == 0:
        return 0.0 if num == 0 else float("inf")
    return num / den


def field_difference(result, reference, name):
    """Max over `result`'s recorded field steps of ‖result − reference‖₂/‖reference‖₂ of field `name`."""
    return max(relative_l2(result.fields[k][name], reference.fields[k][name], reference.fields[k][name])
               for k in result.fields)


def curve_difference(result, reference, column):
    """max_k |result − reference| / max_k |reference| of a load-curve column (dimensionless)."""
    ref = np.asarray(reference.curve[column], float)
    return float(np.max(np.abs(np.asarray(result.curve[column], float) - ref)) / np.max(np.abs(ref)))


def run_fe_and_gfmd(scene, order=2):
    """(fe, gfmd, fe_s, gfmd_s): `reference.fem` P<order> and GFMD (scene.solver) on one scene, wall times (s)."""
    from gfmd.loading import run_realization
    from reference import fem
    t0 = time.perf_counter()
    fe = fem.run_realization(scene, order=order)
    t1 = time.perf_counter()
    gfmd = run_realization(scene)
    return fe, gfmd, t1 - t0, time.perf_counter() - t1


# --------------------------------------------------------------------------- cost
class Meter:
    """Context manager: `with Meter() as m: …` then m.wall_s (s), m.peak_memory_bytes, m.memory_method."""

    def __init__(self, memory="rss"):
        if memory not in ("rss", "tracemalloc", None):
            raise ValueError("memory must be 'rss', 'tracemalloc' or None")
        self.memory = memory
        self.wall_s = None
        self.peak_memory_bytes = None
        self.memory_method = {"rss": MEMORY_RSS, "tracemalloc": MEMORY_TRACEMALLOC, None: ""}[memory]

    def __enter__(self):
        self._rss0 = max_rss_bytes()
        self._started_tm = False
        if self.memory == "tracemalloc":
            if not tracemalloc.is_tracing():
                tracemalloc.start()
                self._started_tm = True
            tracemalloc.reset_peak()
        self._t0 = time.perf_counter()
        return self

    def __exit__(self, *exc):
        self.wall_s = time.perf_counter() - self._t0
        if self.memory == "rss":
            self.peak_memory_bytes = max(0, max_rss_bytes() - self._rss0)
        elif self.memory == "tracemalloc":
            self.peak_memory_bytes = int(tracemalloc.get_traced_memory()[1])
            if self._started_tm:
                tracemalloc.stop()
        return False


def max_rss_bytes():
    """Process resident-set high-water mark (bytes; ru_maxrss is KiB on Linux, bytes on macOS)."""
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return int(rss if sys.platform == "darwin" else rss * 1024)


# --------------------------------------------------------------------------- provenance
_PROVENANCE = None


def code_version():
    """`git describe --always --dirty` of the repository, else the installed package version."""
    try:
        out = subprocess.run(["git", "describe", "--always", "--dirty"], cwd=REPO_ROOT, capture_output=True,
                             text=True, timeout=10)
        if out.returncode == 0 and out.stdout.strip():
            return "git " + out.stdout.strip()
    except (OSError, subprocess.SubprocessError):
        pass
    try:
        from importlib.metadata import version
        return "package gfmd-contact " + version("gfmd-contact")
    except Exception:  # noqa: BLE001 - any failure means "unknown"
        return "unknown"


def command_line():
    """The command as typed, as far as sys.argv tells ("python -m pytest …" for a -m run)."""
    if not sys.argv:
        return ""
    prog = Path(sys.argv[0])
    head = f"python -m {prog.parent.name}" if prog.name == "__main__.py" else prog.name
    return " ".join([head] + sys.argv[1:])


def provenance(refresh=False):
    """Where and how the numbers were made (cached per process)."""
    global _PROVENANCE
    if _PROVENANCE is None or refresh:
        import scipy
        _PROVENANCE = {
            "code_version": code_version(),
            "platform": platform.platform(),
            "machine": platform.machine(),
            "cpu_count": os.cpu_count(),
            "python": sys.version.split()[0],
            "numpy": np.__version__,
            "scipy": scipy.__version__,
            "date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "command": command_line(),
            "cwd": os.getcwd(),
        }
    return dict(_PROVENANCE)


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
    path.write_text(json.dumps(doc, indent=1, allow_nan=False), encoding="utf-8")
    return doc


def load_results(path):
    """Read results.json back: (document dict, [Measurement])."""
    doc = json.loads(Path(path).read_text(encoding="utf-8"))
    return doc, [Measurement.from_dict(d) for d in doc.get("records", [])]


# --------------------------------------------------------------------------- methods and cases
def _gfmd(method):
    def run(scene, realization=0):
        from gfmd.loading import run_realization
        from gfmd.solver import Settings
        settings = Settings(method=method, tolerance=scene.solver.tolerance,
                            max_iterations=scene.solver.max_iterations)
        return run_realization(scene, realization, settings=settings, method_name=f"gfmd-{method}")
    return run


#: method name -> callable(scene, realization=0) -> contact.result.Result
METHODS: dict[str, Callable] = {"gfmd-fire": _gfmd("fire"), "gfmd-verlet": _gfmd("verlet")}


def register_method(name, run):
    """Make `name` usable in `Case.methods`: run(scene, realization=0) -> Result (e.g. "fe-p2")."""
    METHODS[name] = run
    return run


@dataclass(frozen=True)
class Case:
    """A verification case declared as data.

    scene: a `contact.scene.Scene` or a zero-argument callable returning one (so
    building it costs nothing at import); methods: names in `METHODS`;
    metrics: names of the numbers the test records; tolerance: one float for
    all metrics or {metric: float}; tolerance_source: which convergence study
    or argument justifies the tolerance.
    """

    name: str
    scene: Any
    methods: tuple
    metrics: tuple = ()
    tolerance: Any = None
    tolerance_source: str = ""
    description: str = ""
    slow: bool = False

    def get_scene(self):
        return self.scene() if callable(self.scene) else self.scene

    def tolerance_for(self, metric):
        if isinstance(self.tolerance, dict):
            return self.tolerance.get(metric)
        return self.tolerance


@dataclass
class MethodRun:
    result: Any  # contact.result.Result
    wall_s: float
    peak_memory_bytes: int
    memory_method: str


def run_case(case, realization=0, memory="rss"):
    """Run every method of `case` on its scene: {method: MethodRun}."""
    scene = case.get_scene()
    runs = {}
    for name in case.methods:
        if name not in METHODS:
            raise KeyError(f"method {name!r} of case {case.name!r} is not registered; known: {sorted(METHODS)}")
        with Meter(memory) as m:
            result = METHODS[name](scene, realization)
        runs[name] = MethodRun(result, m.wall_s, m.peak_memory_bytes, m.memory_method)
    return runs


def scene_resolution(scene):
    """Resolution dict of a scene: nodes, spacing, steps, solver tolerance."""
    s = scene.surface
    return {"N": s.nodes, "spacing_m": s.spacing, "L_m": s.length, "steps": scene.loading.steps,
            "solver_tolerance": scene.solver.tolerance}


def case_params(cases):
    """pytest.param list (id = case name, `slow` mark where declared) for @pytest.mark.parametrize."""
    import pytest
    return [pytest.param(c, id=c.name, marks=[pytest.mark.slow] if c.slow else []) for c in cases]
