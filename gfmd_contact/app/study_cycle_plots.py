"""Pull-off and hysteresis of a study of load paths against one study axis.

Read from DIR/cycles.csv (`gfmd_contact.app.cycles.write_study_cycles`: one row per task and cycle). Every
point is the mean over a set's realizations with ± 1 standard error bars
(`gfmd_contact.app.averages.mean_standard_error`; a cycle without a value, e.g. one with no unloading, is
left out of its count). One line per combination of the other varied axes and per cycle; x: the
values of AXIS (text values: one tick each). Units: pull-off pressure p̄_off (MPa, < 0 tensile: the most
tensile mean pressure on unloading, Pa in cycles.csv), hysteresis W = ∮ p̄ dδ per unit area (mJ/m²,
J/m² in cycles.csv). Artists carry a gid ("mean" for the curves).

Figures (`CYCLE_STUDY_FIGURES`): pull_off_vs_axis, hysteresis_vs_axis.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .averages import mean_standard_error

CYCLE_STUDY_FIGURES = ("pull_off_vs_axis", "hysteresis_vs_axis")
#: (cycles.csv column, y label, factor from SI to the plotted unit)
_QUANTITIES = {"pull_off_vs_axis": ("pull_off_pressure", r"pull-off pressure $\bar p_\mathrm{off}$ (MPa)", 1e-6),
               "hysteresis_vs_axis": ("hysteresis", r"hysteresis $W = \oint \bar p\,d\delta$ (mJ/m$^2$)", 1e3)}


def read_cycles(study_dir):
    """(axis keys, rows) of DIR/cycles.csv, or None where the study has none (a ramp study)."""
    path = Path(study_dir) / "cycles.csv"
    if not path.is_file():
        return None
    with open(path) as fh:
        reader = csv.DictReader(fh)
        rows = list(reader)
        header = reader.fieldnames or []
    keys = header[1:header.index("realization")] if "realization" in header else []
    return keys, rows


def _number(text):
    try:
        return float(text)
    except ValueError:
        return None


def _cell(text):
    value = _number(text) if text != "" else None
    return math.nan if value is None else value


def cycle_points(keys, rows, over, column):
    """{(other axes' values, cycle): (x values, mean, se, n)} of `column` per set, ordered by x."""
    if over not in keys:
        raise ValueError(f"--over {over!r}: not an axis of the study's cycles.csv; choose one of {', '.join(keys)}")
    others = [k for k in keys if k != over]
    groups = {}
    for r in rows:
        line = (tuple(r[k] for k in others), int(r["cycle"]))
        groups.setdefault(line, {}).setdefault(r[over], []).append(_cell(r[column]))
    out = {}
    for line, by_x in groups.items():
        xs = list(by_x)
        numeric = all(_number(x) is not None for x in xs)
        xs.sort(key=lambda x: _number(x) if numeric else xs.index(x))
        mean, se, n = [], [], []
        for x in xs:
            m, s, c = mean_standard_error(np.array(by_x[x], float)[:, None])
            mean.append(m[0]), se.append(s[0]), n.append(int(c[0]))
        out[line] = (xs, np.array(mean), np.array(se), np.array(n))
    return out


def _axis_values(keys, rows):
    return {k: {r[k] for r in rows} for k in keys}


def default_over(keys, rows):
    """The one axis the study varies (None where it varies several or none: then --over must say which)."""
    varied = [k for k, v in _axis_values(keys, rows).items() if len(v) > 1]
    return varied[0] if len(varied) == 1 else None


def cycle_study_figures(study_dir, over=None):
    """{name: Figure} of `CYCLE_STUDY_FIGURES` for a study with cycles.csv ({} without one, or where the study
    varies several axes and `over` is not given)."""
    table = read_cycles(study_dir)
    if table is None or not table[1]:
        return {}
    keys, rows = table
    over = over or default_over(keys, rows)
    if over is None:
        return {}
    others = [k for k in keys if k != over]
    figs = {}
    for name, (column, ylabel, factor) in _QUANTITIES.items():
        points = cycle_points(keys, rows, over, column)
        fig = Figure(figsize=(5.6, 4.6), layout="constrained")
        ax = fig.subplots()
        numeric = all(_number(x) is not None for line in points.values() for x in line[0])
        ticks = sorted({x for line in points.values() for x in line[0]}, key=lambda x: _number(x) if numeric else x)
        for (rest, cycle), (xs, mean, se, n) in sorted(points.items()):
            x = [_number(v) if numeric else ticks.index(v) for v in xs]
            label = ", ".join(f"{k} = {v}" for k, v in zip(others, rest)) or None
            if len({c for _, c in points}) > 1:
                label = (label + ", " if label else "") + f"cycle {cycle}"
            ax.errorbar(x, mean * factor, yerr=se * factor, marker="o", capsize=3, label=label, gid="mean")
        if not numeric:
            ax.set_xticks(range(len(ticks)), ticks)
        ax.set_xlabel(over)
        ax.set_ylabel(ylabel)
        reps = max(int(n.max()) for *_, n in points.values())
        ax.set_title(f"mean ± standard error over {reps} realization(s)", fontsize=9)
        if column == "pull_off_pressure":
            ax.axhline(0.0, color="0.6", lw=0.8)
        if any(label for label in ax.get_legend_handles_labels()[1]):
            ax.legend(fontsize=8)
        figs[name] = fig
    return figs
