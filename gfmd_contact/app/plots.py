"""Figures of a run directory (the seed's Figs. 3–5), written as PNG, SVG or PDF.

Units: axes are labelled with their non-dimensional groups: p_r* = p/(ḡ_r E*),
p/E*, a_rel, ḡ_r/ḡ, and δ in nm (x in µm, z in nm on the interface snapshot).

What is drawn:
* realizations are stacked step by step (`stack_curves`): a realization that
  stopped early (ragged curves, interrupted runs) is padded with NaN, and every
  point is the mean over the realizations that have a value there, with its
  standard error (`gfmd_contact.app.averages.mean_standard_error`); the legend says so and
  gives the realization count n (a range where it differs between points);
* points averaged over fewer than all realizations (a realization stopped
  early, or ḡ_r is undefined without contact) are drawn as open markers: the
  mean of a changing subset can jump where a realization drops out;
* steps where some realization did not converge are marked with red ×;
* on the load–area figure the adhesive branch (p < 0, tensile mean pressure)
  is kept, left of a line at p = 0; the κ fit (seed Eq. 1, non-adhesive only)
  uses p > 0 only.
`make_figures` returns the matplotlib figures (artists carry a `gid`: "mean",
"partial", "nonconverged", "p=0", "kappa-fit"), `plot_run` writes them.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from matplotlib import rc_context
from matplotlib.container import ErrorbarContainer
from matplotlib.figure import Figure

from . import safe_files
from .averages import mean_standard_error
from .io import read_run
from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.observables import fit_kappa, reduced_pressure

#: output formats of `plot_run` (and `gfmd plot --format`)
FORMATS = ("png", "svg", "pdf")
#: file names (without extension) of the figures, in the order they are written
FIGURES = ("area_vs_reduced_pressure", "pressure_vs_delta", "area_vs_delta", "gr_over_g_vs_delta",
           "interface_snapshot")  # a 2+1-D run: contact_map and pressure_map instead (gfmd_contact.app.surface_plots)

_BAR_COLOR = (0.12, 0.47, 0.71, 0.45)  # tab:blue, translucent: dense error bars stay readable
_NC_STYLE = {"marker": "x", "color": "red", "ms": 6, "mew": 1.3, "ls": "none", "zorder": 5}


@dataclass
class Stacked:
    """Curves of all realizations on a common step axis.

    realizations: indices (sorted); step, delta: (S,) the union of steps and their δ (m),
    taken from the longest curve; columns: name → (R, S) array, NaN where a realization
    has no such step.
    """

    realizations: list
    step: np.ndarray
    delta: np.ndarray
    columns: dict

    def __getitem__(self, name):
        return self.columns[name]


def stack_curves(curves):
    """Stack `curves` ({realization: {column: array}}, as from `gfmd_contact.app.io.read_run`) by their `step` column.

    Curves may differ in length (a realization stopped early, an interrupted run):
    missing steps are NaN. δ of each step comes from the longest curve (from the
    others only for steps it lacks). Raises ValueError for no curves or a repeated step.
    """
    if not curves:
        raise ValueError("the run has no curve rows")
    order = sorted(curves)
    steps = {r: np.asarray(curves[r]["step"], float).astype(int) for r in order}
    for r in order:
        if len(np.unique(steps[r])) != len(steps[r]):
            raise ValueError(f"realization {r}: repeated step numbers in curve.csv")
    axis = np.unique(np.concatenate([steps[r] for r in order]))
    names = [c for c in dict.fromkeys(c for r in order for c in curves[r]) if c != "step"]
    columns = {c: np.full((len(order), len(axis)), np.nan) for c in names}
    for i, r in enumerate(order):
        j = np.searchsorted(axis, steps[r])
        for c in names:
            if c in curves[r]:
                columns[c][i, j] = np.asarray(curves[r][c], float)
    delta = np.full(len(axis), np.nan)
    for r in sorted(order, key=lambda r: -len(steps[r])):  # longest first (ties: lowest index)
        row = columns["delta"][order.index(r)]
        delta = np.where(np.isnan(delta), row, delta)
    return Stacked(realizations=order, step=axis, delta=delta, columns=columns)


def error_bar_label(*counts):
    """Legend text for mean ± standard error, given the per-point realization counts drawn."""
    counts = np.concatenate([np.asarray(c, int).ravel() for c in counts])
    counts = counts[counts > 0]
    if counts.size == 0 or counts.max() <= 1:
        return "one realization (no error bars)"
    lo, hi = int(counts.min()), int(counts.max())
    if lo == hi:
        return f"mean ± standard error over n = {hi} realizations"
    return f"mean ± standard error over n = {lo}–{hi} realizations (n varies by step)"


def nonconverged(stacked):
    """(R, S) bool: steps where a realization's solver did not converge (converged == 0)."""
    return stacked["converged"] == 0


def nonconverged_label(mask, realizations):
    """Legend text for the × markers: how many steps did not converge, and in which realizations."""
    n = int(mask.sum())
    which = [r for r, row in zip(realizations, mask) if row.any()]
    real = f"realization{'s' if len(which) > 1 else ''} {', '.join(str(r) for r in which)}"
    return f"not converged: {n} step{'s' if n != 1 else ''} ({real}), included in the mean"


def _figure(size=(5.5, 4.4)):
    fig = Figure(figsize=size, layout="constrained")
    return fig, fig.subplots()


def _sci(ax, axis):
    """Powers of ten in an offset label (×10⁻⁴) instead of long decimals like 0.0007."""
    ax.ticklabel_format(axis=axis, style="sci", scilimits=(-3, 4), useMathText=True)


def _legend(fig, ax, ncols=1):
    """Legend below the axes, outside the data."""
    handles, labels = ax.get_legend_handles_labels()
    if handles:  # the data first
        first = sorted(range(len(handles)), key=lambda i: not isinstance(handles[i], ErrorbarContainer))
        handles, labels = [handles[i] for i in first], [labels[i] for i in first]
        fig.legend(handles, labels, loc="outside lower center", ncols=ncols, fontsize=8, frameon=False)


def _mark_partial(ax, x, y, count, total, drawn, label=True):
    """Open markers where the mean is over fewer than all `total` realizations (stopped early, no contact)."""
    at = drawn & (count < total)
    if total > 1 and at.any():
        ax.plot(x[at], y[at], "o", ms=3.5, mfc="white", mec="tab:blue", mew=0.9, ls="none", zorder=4, gid="partial",
                label=f"open: mean over n < {total} realizations (the others stopped early or have no value)"
                if label else None)


def _mark_nonconverged(ax, x, y, mask, realizations, drawn, label=True):
    """Red × at the drawn points (x, y) of steps where any realization did not converge."""
    at = mask.any(axis=0) & drawn & np.isfinite(x) & np.isfinite(y)
    if mask.any():
        ax.plot(x[at], y[at], **_NC_STYLE, gid="nonconverged",
                label=nonconverged_label(mask, realizations) if label else None)


def _load_area(scene, st, e_star, label, nc):
    with np.errstate(invalid="ignore", divide="ignore"):
        p_r = reduced_pressure(st["p"], st["g_r"], e_star)
        mx, sx, cx = mean_standard_error(p_r)
        my, sy, cy = mean_standard_error(st["a_rel"])
    ok = np.isfinite(mx) & np.isfinite(my)  # adhesive branch (p < 0) included
    tensile = ok & (mx < 0)
    if tensile.any():  # second panel: the adhesive branch, squeezed against p = 0 on the full scale
        fig = Figure(figsize=(10, 4.4), layout="constrained")
        ax, zoom = fig.subplots(1, 2, gridspec_kw={"width_ratios": (1.35, 1)})
    else:
        (fig, ax), zoom = _figure(), None
    style = dict(fmt="-o", ms=3, lw=0.6, elinewidth=0.7, capsize=0, color="tab:blue", ecolor=_BAR_COLOR)
    for i, a in enumerate((ax, zoom) if zoom else (ax,)):
        first = i == 0
        a.axvline(0.0, color="0.45", lw=0.8, ls=":", gid="p=0",
                  label=("p = 0 (left: tensile mean pressure, adhesive branch)" if law_from_scene(scene).adhesive
                         else "p = 0") if first else None)
        a.errorbar(mx[ok], my[ok], xerr=sx[ok], yerr=sy[ok], gid="mean",
                   label=f"{label}\n{error_bar_label(cx[ok], cy[ok])}" if first else None, **style)
        _mark_partial(a, mx, my, np.minimum(cx, cy), len(st.realizations), ok, label=first)
        _mark_nonconverged(a, mx, my, nc, st.realizations, ok, label=first)
        a.set(xlabel=r"reduced pressure $p_r^* = p\,/\,(\bar g_r E^*)$")
        _sci(a, "x")
    if not law_from_scene(scene).adhesive:  # seed Eq. 1 holds for non-adhesive contact only
        try:
            kappa, npts = fit_kappa(mx, my)
            xs = np.linspace(0, np.nanmax(mx[ok & (mx > 0)]), 50)
            ax.plot(xs, kappa * xs, "k--", lw=1, gid="kappa-fit",
                    label=rf"fit $a_\mathrm{{rel}} = \kappa\,p_r^*$ over $a_\mathrm{{rel}} \leq 0.1$: "
                          rf"$\kappa$ = {kappa:.3f} ({npts} points)")
        except ValueError:
            pass
    ax.set(ylabel=r"relative contact area $a_\mathrm{rel}$", title="Load–area relation")
    if zoom is not None:
        w = float(-np.min(mx[tensile]))
        lo, hi = -1.3 * w, 2.5 * w
        window = ok & (mx >= lo) & (mx <= hi)
        top = float(np.max(my[window] + sy[window])) * 1.1 or 1.0
        zoom.set(xlim=(lo, hi), ylim=(-0.02 * top, top), title="Adhesive branch (shaded range, enlarged)")
        ax.axvspan(lo, hi, color="0.92", lw=0, zorder=0)
    _legend(fig, ax)
    return fig


def _versus_delta(st, values, ylabel, title, label, nc, zero_line=False):
    fig, ax = _figure()
    x = st.delta * 1e9
    with np.errstate(invalid="ignore", divide="ignore"):
        m, se, count = mean_standard_error(values)
    ok = np.isfinite(m)
    ax.axvline(0, color="0.7", lw=0.6)
    if zero_line:
        ax.axhline(0, color="0.7", lw=0.6)
    ax.errorbar(x[ok], m[ok], yerr=se[ok], fmt="-o", ms=2, lw=0.8, elinewidth=0.7, capsize=0, color="tab:blue",
                ecolor=_BAR_COLOR,
                gid="mean", label=f"{label}\n{error_bar_label(count[ok])}")
    _mark_partial(ax, x, m, count, len(st.realizations), ok)
    _mark_nonconverged(ax, x, m, nc, st.realizations, ok)
    ax.set(xlabel=r"penetration $\delta$ (nm)", ylabel=ylabel, title=title)
    _sci(ax, "y")
    _legend(fig, ax)
    return fig


def saved_steps(curves, fields, realization):
    """Steps of `realization` whose fields were saved (and that its curve has), ascending; a step the method
    has no state of (NaN fields, `gfmd_contact.core.ramp.StepSolution.relaxed`) has nothing to draw and is left out."""
    r = realization
    steps = sorted(int(k.split("_")[1][1:]) for k in fields if k.startswith(f"r{r}_s") and k.endswith("_u_z"))
    have = {int(s) for s in np.asarray(curves[r]["step"], float)}
    return [s for s in steps if s in have and np.all(np.isfinite(fields[f"r{r}_s{s}_u_z"]))]


def _snapshot(scene, curves, fields, realization, snapshot_delta):
    r = realization
    steps = saved_steps(curves, fields, r)
    if not steps:
        return None
    curve = curves[r]
    row = {int(s): i for i, s in enumerate(np.asarray(curve["step"], float))}
    delta_of = {s: float(curve["delta"][row[s]]) for s in steps}
    target = delta_of[steps[-1]] if snapshot_delta is None else snapshot_delta
    k = min(steps, key=lambda s: abs(delta_of[s] - target))
    x = fields["x"] * 1e6
    u_z = fields[f"r{r}_s{k}_u_z"] * 1e9
    z_ind = u_z + fields[f"r{r}_s{k}_gap"] * 1e9
    fig, ax = _figure((8, 3.8))
    top = max(np.max(z_ind), np.max(u_z))
    span = top - min(np.min(z_ind), np.min(u_z))
    ax.fill_between(x, z_ind, top + 0.15 * span, color="0.75", lw=0, label="rigid indenter")
    ax.plot(x, z_ind, color="0.35", lw=0.6)
    ax.plot(x, u_z, color="tab:green" if law_from_scene(scene).adhesive else "tab:red", lw=0.8,
            label=r"elastic surface $u_z$")
    ax.set_xlim(x.min(), x.max())
    ax.set_ylim(min(np.min(z_ind), np.min(u_z)) - 0.05 * span, top + 0.15 * span)
    who = f"realization {r}"
    if "seed" in curve and np.isfinite(curve["seed"][row[k]]):
        who += f", random seed {int(curve['seed'][row[k]])}"
    note = "" if "converged" not in curve or curve["converged"][row[k]] else ", NOT CONVERGED"
    ax.set(xlabel=r"$x$ (µm)", ylabel=r"$z$ (nm)",
           title=f"Interface at δ = {delta_of[k] * 1e9:.2f} nm ({who}{note})")
    _legend(fig, ax, ncols=2)
    return fig


def _snapshot_step(curves, fields, realization, snapshot_delta):
    """(step, δ, row) of the saved step nearest snapshot_delta (default: the last saved), or None."""
    steps = saved_steps(curves, fields, realization)
    if not steps:
        return None
    curve = curves[realization]
    row = {int(s): i for i, s in enumerate(np.asarray(curve["step"], float))}
    delta_of = {s: float(curve["delta"][row[s]]) for s in steps}
    target = delta_of[steps[-1]] if snapshot_delta is None else snapshot_delta
    k = min(steps, key=lambda s: abs(delta_of[s] - target))
    return k, delta_of[k], row[k]


def _maps(scene, curves, fields, realization, snapshot_delta):
    """The contact map and pressure map of a 2+1-D run's saved step ({} without saved fields)."""
    from .surface_plots import surface_maps

    found = _snapshot_step(curves, fields, realization, snapshot_delta)
    if found is None:
        return {}
    k, delta, i = found
    curve = curves[realization]
    note = "" if "converged" not in curve or curve["converged"][i] else ", NOT CONVERGED"
    return surface_maps(scene, fields, realization, k, delta, note)


def method_text(meta):
    """What solved the run, for the legends: meta.json's method, and where a GFMD run's steps name their
    algorithms (meta "algorithms"), the steps per algorithm: "gfmd-ncg: ncg 198 steps, ncg→fire 2"."""
    method = meta.get("method", "")
    counts = meta.get("algorithms") or {}
    if not counts:
        return method
    return f"{method}: " + ", ".join(f"{name or '?'} {n}{' steps' if i == 0 else ''}"
                                     for i, (name, n) in enumerate(counts.items()))


def make_figures(run_dir, snapshot_delta=None, realization=None):
    """The figures of `run_dir` as {name: matplotlib Figure} (names: `FIGURES`; no snapshot without saved fields).

    snapshot_delta: δ (m) of the interface snapshot (nearest saved step; default: last saved);
    realization: index (curve.csv `realization`) of the snapshot (default: the first present that
    has saved fields). A run whose loading has a path adds `gfmd_contact.app.cycle_plots.CYCLE_FIGURES`. Raises ValueError for a realization not in the run, or one without saved
    fields (output.field_steps = 0, or it stopped before the first saved step) when others have them.
    """
    scene, curves, fields, meta = read_run(run_dir)
    if not curves:
        raise ValueError(f"{run_dir}: curve.csv has no rows")
    with_fields = [r for r in sorted(curves) if saved_steps(curves, fields, r)]
    if realization is None:
        realization = with_fields[0] if with_fields else min(curves)
    elif realization not in curves:
        raise ValueError(f"--realization {realization}: no such realization in {run_dir}; "
                         f"available: {', '.join(str(r) for r in sorted(curves))}")
    elif with_fields and realization not in with_fields:
        raise ValueError(f"--realization {realization}: no saved fields for the interface snapshot in {run_dir}; "
                         f"realizations with saved fields: {', '.join(str(r) for r in with_fields)}")
    st = stack_curves(curves)
    e_star = scene.material.contact_modulus
    law = law_from_scene(scene)
    label = f"{law.name}, $\\varphi_n^* = {scene.interface.phi_n_star:g}$" if law.adhesive else law.name
    label += f"; {method_text(meta)}" if method_text(meta) else ""
    nc = nonconverged(st)
    figs = {"area_vs_reduced_pressure": _load_area(scene, st, e_star, label, nc)}
    adhesive = law.adhesive
    for name, values, ylabel, title in (
            ("pressure_vs_delta", st["p"] / e_star, r"mean pressure $p/E^*$", "Mean pressure vs penetration"),
            ("area_vs_delta", st["a_rel"], r"relative contact area $a_\mathrm{rel}$", "Contact area vs penetration"),
            ("gr_over_g_vs_delta", st["g_r"] / st["g"], r"$\bar g_r/\bar g$",
             "rms gradient in contact vs penetration")):
        figs[name] = _versus_delta(st, values, ylabel, title, label, nc,
                                   zero_line=adhesive and name == "pressure_vs_delta")
    if scene.surface.two_d:  # a 2+1-D surface: contact and pressure maps of the step (gfmd_contact.app.surface_plots)
        figs.update(_maps(scene, curves, fields, realization, snapshot_delta))
    else:
        snap = _snapshot(scene, curves, fields, realization, snapshot_delta)
        if snap is not None:
            figs["interface_snapshot"] = snap
    if scene.loading.path:  # a load path: the p̄–δ and a_rel–p̄ loops (gfmd_contact.app.cycle_plots)
        from .cycle_plots import cycle_figures
        figs.update(cycle_figures(scene, st, meta))
    return figs


def plot_run(run_dir, snapshot_delta=None, fmt="png", realization=None, wait=0):
    """Write the figures of `run_dir` into run_dir/plots/ as `fmt` (png, svg or pdf); returns their paths.

    snapshot_delta, realization: see `make_figures`. Raises ValueError for an unknown
    format or a realization not in the run. The folder is locked while figures are written
    (`safe_files.DirLock`; wait: seconds to wait for another plotter, -1 for ever); each figure is
    written atomically, so a kill leaves the figures before it intact and plots/.gfmd.lock behind.
    """
    if fmt not in FORMATS:
        raise ValueError(f"--format {fmt!r}: choose one of {', '.join(FORMATS)}")
    run_dir = Path(run_dir)
    figs = make_figures(run_dir, snapshot_delta=snapshot_delta, realization=realization)
    out = run_dir / "plots"
    paths = []
    with safe_files.locked(out, wait=wait, what="plot folder"):  # one plotter at a time; each figure atomic
        for name, fig in figs.items():
            path = out / f"{name}.{fmt}"
            with rc_context({"pdf.fonttype": 42}):  # TrueType in PDFs: text stays editable
                safe_files.save_figure(fig, path, format=fmt, dpi=200)
            paths.append(path)
    return paths
