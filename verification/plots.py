"""Plot dicts for the report (`verification.report` draws them; a record carries them).

Kinds and required keys: profile (x, series), curve (x, series), convergence (h, error),
table (columns, rows), pareto (points), grid (columns, rows); see `verification.report`.
"""

from __future__ import annotations

from .metrics import fitted_order

PLOT_KINDS = ("profile", "curve", "convergence", "table", "pareto", "grid")
_REQUIRED = {"profile": ("x", "series"), "curve": ("x", "series"), "convergence": ("h", "error"),
             "table": ("columns", "rows"), "pareto": ("points",), "grid": ("columns", "rows")}


def validate_plot(plot):
    """Raise ValueError if a plot dict lacks its kind or required keys."""
    if not isinstance(plot, dict) or plot.get("kind") not in PLOT_KINDS:
        raise ValueError(f"plot must be a dict with kind in {PLOT_KINDS}, got {plot!r:.200}")
    missing = [k for k in _REQUIRED[plot["kind"]] if k not in plot]
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
