"""Figures of a run whose loading has a path: the p̄–δ and a_rel–p̄ loops.

Units: p̄/E*, δ in nm, a_rel. Each figure draws the mean over realizations per step (realizations
share the steps of the path) as a line per branch (loading: tab:blue, unloading: tab:orange), an arrow
on every segment of the path pointing the way δ goes (gid "direction"), and, per realization, the
events of meta.json "cycles" (`gfmd_contact.core.cycle`): a jump-in as ▲ and a jump-out as ▼ at the state
after the jump, joined to the state before by a dotted line (gid "jump-in" / "jump-out"), and the
pull-off (the most tensile p̄ on unloading) as ★ (gid "pull-off"). The title gives each realization's
hysteresis W = ∮ p̄ dδ (J/m²) of its first cycle.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from gfmd_contact.core.loading import step_branches, step_segments

#: file names of the cycle figures (written with those of `gfmd_contact.app.plots.FIGURES` for a path run)
CYCLE_FIGURES = ("cycle_pressure_vs_delta", "cycle_area_vs_pressure")
_COLORS = {"loading": "tab:blue", "unloading": "tab:orange"}


def _arrow(ax, x, y, j, color, length=24.0):
    """An arrow of `length` points ending at point j, along the curve's direction from point j − 1 to j."""
    i = j - 1
    if i < 0 or not np.isfinite([x[i], x[j], y[i], y[j]]).all():
        return
    ax.autoscale_view()
    d = ax.transData.transform((x[j], y[j])) - ax.transData.transform((x[i], y[i]))
    if not np.hypot(*d) > 0:
        return
    d = d / np.hypot(*d) * length
    ax.annotate("", xy=(x[j], y[j]), xytext=(-d[0], -d[1]), textcoords="offset points", gid="direction",
                arrowprops={"arrowstyle": "-|>", "color": color, "lw": 2.0, "mutation_scale": 14})


def _loop(scene, st, meta, xs, ys, xlabel, ylabel, title, x_of, y_of):
    """One loop figure: xs, ys the per-step mean arrays; x_of, y_of map an event's (δ, p̄, a_rel) to the axes."""
    fig = Figure(figsize=(5.8, 4.6), layout="constrained")
    ax = fig.subplots()
    branch, _ = step_branches(scene.loading)
    segment = step_segments(scene.loading)
    k = st.step.astype(int)
    br, seg = branch[k], segment[k]
    for name, color in _COLORS.items():
        for s in np.unique(seg):
            idx = np.flatnonzero(seg == s)
            if idx.size and br[idx[-1]] == name:
                start = max(idx[0] - 1, 0)  # join the segment to its corner
                ax.plot(xs[start:idx[-1] + 1], ys[start:idx[-1] + 1], "-o", ms=1.5, lw=0.9, color=color, gid=name,
                        label=f"{name} (mean over realizations)" if s == min(seg[br == name]) else None)
    for name, color in _COLORS.items():  # after all lines, so that the axes limits are final
        for s in np.unique(seg):
            idx = np.flatnonzero(seg == s)
            if idx.size and br[idx[-1]] == name:
                # at 80 % of a loading segment, 40 % of an unloading one: apart where the branches coincide
                # near the turning point, and clear of jumps near the segment's ends
                start = max(idx[0] - 1, 0)
                _arrow(ax, xs, ys, start + max(1, int((0.8 if name == "loading" else 0.4) * (idx[-1] - start))), color)
    drawn = set()
    for entry in meta.get("cycles", []):
        for c in entry["cycles"]:
            for e in c["events"]:
                before = (x_of(e["delta_before"], e["p_before"], e["a_rel_before"]),
                          y_of(e["delta_before"], e["p_before"], e["a_rel_before"]))
                after = (x_of(e["delta_after"], e["p_after"], e["a_rel_after"]),
                         y_of(e["delta_after"], e["p_after"], e["a_rel_after"]))
                ax.plot([before[0], after[0]], [before[1], after[1]], ":", color="0.3", lw=0.8)
                ax.plot(*after, "^" if e["kind"] == "jump-in" else "v", color="red", ms=7, ls="none", gid=e["kind"],
                        label=f"{e['kind']} (after the jump)" if e["kind"] not in drawn else None)
                drawn.add(e["kind"])
            if c["pull_off_pressure"] is not None:
                i = int(np.argmin(np.abs(st.delta - c["pull_off_delta"])))
                a = float(np.nanmean(st["a_rel"][:, i]))
                ax.plot(x_of(c["pull_off_delta"], c["pull_off_pressure"], a),
                        y_of(c["pull_off_delta"], c["pull_off_pressure"], a), "*", color="k", ms=9, ls="none",
                        gid="pull-off", label="pull-off (min p̄ on unloading)" if "pull-off" not in drawn else None)
                drawn.add("pull-off")
    ws = [f"{e['cycles'][0]['hysteresis']:.3g}" for e in meta.get("cycles", []) if e["cycles"]]
    ax.set(xlabel=xlabel, ylabel=ylabel, title=title + (f"\nW = ∮p̄dδ = {', '.join(ws)} J/m² (cycle 0)" if ws else ""))
    ax.ticklabel_format(style="sci", scilimits=(-3, 4), useMathText=True)
    fig.legend(loc="outside lower center", ncols=2, fontsize=8, frameon=False)
    return fig


def cycle_figures(scene, st, meta):
    """{name: Figure} of `CYCLE_FIGURES` for a run with a load path (`st`: `gfmd_contact.app.plots.Stacked`)."""
    e_star = scene.material.contact_modulus
    with np.errstate(invalid="ignore"):
        p = np.nanmean(st["p"], axis=0) / e_star
        a = np.nanmean(st["a_rel"], axis=0)
    d = st.delta * 1e9
    return {
        "cycle_pressure_vs_delta": _loop(scene, st, meta, d, p, r"penetration $\delta$ (nm)", r"mean pressure $\bar p/E^*$",
                                         "Load–unload cycle: mean pressure vs penetration",
                                         lambda dd, pp, aa: dd * 1e9, lambda dd, pp, aa: pp / e_star),
        "cycle_area_vs_pressure": _loop(scene, st, meta, p, a, r"mean pressure $\bar p/E^*$",
                                        r"relative contact area $a_\mathrm{rel}$",
                                        "Load–unload cycle: contact area vs mean pressure",
                                        lambda dd, pp, aa: pp / e_star, lambda dd, pp, aa: aa),
    }
