"""Figures of a study directory like the seed paper's (Figs. 2–8), written as PNG or SVG into DIR/figures/.

Units: axes carry the non-dimensional groups p_r* = p/(ḡ_r E*), p/E*, a_rel, ḡ_r/ḡ; δ in nm,
x in µm and z in nm on the snapshot. E* = E/(1 − ν²) of each set's own scene.

One curve per parameter set (labelled by the values of the keys that vary between the drawn
sets; the legend title names them); every point is the mean over the set's realizations
with ± 1 standard error bars (`gfmd_contact.app.averages.mean_standard_error`; the legend says over
how many realizations). Hard-wall sets (interface.law = "hard-wall") are the non-adhesive
reference and are drawn dashed black (dashed in their adhesive partner's colour when a
panel holds several). With `over=AXIS` each panel holds the sets that differ only in AXIS
(one panel per combination of the other keys; the legend title is AXIS). Open markers: a
mean over fewer than all of a set's realizations; red ×: a step where some realization
did not converge. A partial study (tasks missing or failed, or still running: then the
finished tasks' curve.csv are read) is drawn from what is there, with a red note on every
figure.

Figures (`FIGURES`): kappa_fit (Fig. 2: a_rel vs p_r* per hard-wall set, the fit range
0 < a_rel ≤ 0.1 shaded, κ ± SE over realizations), area_vs_reduced_pressure (Fig. 3a, adhesive
branch p < 0 included), area_vs_reduced_pressure_zoom (Fig. 3b), pressure_vs_delta,
area_vs_delta, gr_over_g_vs_delta (Fig. 4a–c), interface_snapshot (Fig. 5: one realization
at the largest saved δ, indenter gray, adhesive surface green, non-adhesive red; a 1+1-D study),
contact_maps (its 2+1-D stand-in: the same sets' contact maps, black = contact) and
area_vs_pressure (Figs. 7–8: a_rel vs p/E*). Artists carry a gid ("mean", "reference",
"kappa-fit", "fit-range", "partial", "nonconverged", "partial-study", "errorbar-label").
A study of load paths (DIR/cycles.csv) adds pull_off_vs_axis and hysteresis_vs_axis against AXIS
(`gfmd_contact.app.study_cycle_plots`; without --over: the one axis the study varies).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib import rc_context
from matplotlib.figure import Figure

from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.observables import contact_mask

from . import safe_files
from .averages import mean_standard_error
from .claim_measures import (LAW_KEYS, KEY_LABELS, _param_text, kappa_per_realization, reduced_pressure_of,
                             reference_of, set_label, varying)
from .claim_stats import stats
from .plots import _NC_STYLE, _sci, error_bar_label
from .study_cycle_plots import cycle_study_figures
from .study_data import read_study_dir

#: output formats of `plot_study`
FORMATS = ("png", "svg")
FIGURES = ("kappa_fit", "area_vs_reduced_pressure", "area_vs_reduced_pressure_zoom", "pressure_vs_delta",
           "area_vs_delta", "gr_over_g_vs_delta", "interface_snapshot", "area_vs_pressure")
#: a study of 2+1-D surfaces draws FIGURES with contact_maps in place of interface_snapshot
FIGURES_2D = tuple("contact_maps" if f == "interface_snapshot" else f for f in FIGURES)
_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan",
           "tab:gray", "tab:red")
_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">", "h")
_XLABEL = {"p_r": r"reduced pressure $p_r^* = p\,/\,(\bar g_r E^*)$", "p_E": r"mean pressure $p/E^*$",
           "delta": r"penetration $\delta$ (nm)"}


def _key_title(keys):
    return ", ".join(KEY_LABELS.get(k, (k,))[0] + f" ({k})" for k in keys)


def _panels(data, over):
    """[(title, main sets, reference sets, label keys)] of the figure panels."""
    sets = data.with_data
    refs = [s for s in sets if s.hard_wall]
    main = [s for s in sets if not s.hard_wall]
    if not main or over in LAW_KEYS:
        main, refs = sets, []
    keys = [k for k in data.keys]
    if over is None:
        lab = varying(main, keys) if len(main) > 1 else []
        lab = [k for k in lab if k != "interface.law"]
        return [("", main, refs, lab)]
    if over not in keys:
        raise ValueError(f"--over {over!r}: not a key the study varies; choose one of {', '.join(keys)}")
    rest = [k for k in varying(main, keys) if k != over and not (refs and k in LAW_KEYS)]
    groups = {}
    for s in main:
        groups.setdefault(tuple(repr(s.params.get(k)) for k in rest), []).append(s)
    out = []
    for g in groups.values():
        title = ", ".join(_param_text(k, g[0].params.get(k)) for k in rest)
        sig = {s.signature for s in g}
        out.append((title, g, [r for r in refs if r.signature in sig], [over]))
    return out


def _figure(n, size=(5.6, 4.6)):
    cols = min(n, 3)
    rows = (n + cols - 1) // cols
    fig = Figure(figsize=(size[0] * cols, size[1] * rows + 0.4), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False).ravel())
    for a in axes[n:]:
        a.set_visible(False)
    return fig, axes[:n]


def _note(fig, data):
    note = data.partial_note()
    if note:
        fig.suptitle(note, color="red", fontsize=9, gid="partial-study")


def _series(s, xname, yname):
    """(x, y) realizations × steps arrays of set `s`."""
    st = s.stacked
    with np.errstate(invalid="ignore", divide="ignore"):
        if xname == "p_r":
            x = reduced_pressure_of(s)
        elif xname == "p_E":
            x = st["p"] / s.e_star
        else:
            x = np.broadcast_to(st.delta * 1e9, st["p"].shape)
        y = {"a_rel": st["a_rel"], "p_E": st["p"] / s.e_star, "gr_g": st["g_r"] / st["g"]}[yname]
    return np.asarray(x, float), np.asarray(y, float)


def _draw_set(ax, s, xname, yname, color, marker, label, style="-", ref=False):
    """Mean ± SE curve of one set; returns the counts drawn (for the error-bar label)."""
    x, y = _series(s, xname, yname)
    with np.errstate(invalid="ignore", divide="ignore"):
        mx, sx, cx = mean_standard_error(x)
        my, sy, cy = mean_standard_error(y)
    if xname == "delta":
        sx = np.zeros_like(sx)
    ok = np.isfinite(mx) & np.isfinite(my)
    every = max(1, int(ok.sum()) // 25)  # error bars on every k-th point: dense curves stay readable
    ax.errorbar(mx[ok], my[ok], xerr=sx[ok] if xname != "delta" else None, yerr=sy[ok], fmt=style,
                marker=None if ref else marker, ms=2.5, lw=1.2 if ref else 0.8, color=color, ecolor=color,
                elinewidth=0.6, capsize=0, alpha=0.95, errorevery=every, gid="reference" if ref else "mean",
                label=label)
    count = np.minimum(cx, cy)
    part = ok & (count < s.realizations)
    if part.any() and s.realizations > 1:
        ax.plot(mx[part], my[part], "o", ms=3.5, mfc="white", mec=color, mew=0.8, ls="none", zorder=4,
                gid="partial")
    nc = (s.stacked["converged"] == 0).any(axis=0) & ok
    if nc.any():
        ax.plot(mx[nc], my[nc], **_NC_STYLE, gid="nonconverged")
    return count[ok], int(nc.sum()), bool(part.any() and s.realizations > 1)


def _overlay(data, over, xname, yname, ylabel, title, zoom=False):
    panels = _panels(data, over)
    fig, axes = _figure(len(panels))
    for ax, (ptitle, main, refs, lab) in zip(axes, panels):
        counts, nc, part = [], 0, False
        for i, s in enumerate(main):
            c, n, p = _draw_set(ax, s, xname, yname, _COLORS[i % len(_COLORS)], _MARKERS[i % len(_MARKERS)],
                                set_label(s, lab) if lab else set_label(s, []))
            counts.append(c)
            nc, part = nc + n, part or p
        for r in refs:
            partner = [i for i, s in enumerate(main) if s.signature == r.signature]
            color = "black" if len(refs) == 1 or not partner else _COLORS[partner[0] % len(_COLORS)]
            rl = [k for k in varying(refs, data.keys) if k not in LAW_KEYS] if len(refs) > 1 else []
            c, n, p = _draw_set(ax, r, xname, yname, color, "", set_label(r, rl) + " (non-adhesive reference)",
                                style="--", ref=True)
            counts.append(c)
            nc, part = nc + n, part or p
        if xname in ("p_r", "p_E"):
            ax.axvline(0, color="0.6", lw=0.6, ls=":")
        if yname == "p_E":
            ax.axhline(0, color="0.6", lw=0.6, ls=":")
        ax.plot([], [], " ", gid="errorbar-label", label=error_bar_label(*counts).replace(
            "mean ± standard error", "error bars: ± 1 standard error"))
        if part:
            ax.plot([], [], "o", mfc="white", mec="0.3", ls="none", label="open: mean over fewer realizations")
        if nc:
            ax.plot([], [], **{**_NC_STYLE, "label": f"red ×: {nc} step(s) where a realization did not converge"})
        ax.set(xlabel=_XLABEL[xname], ylabel=ylabel, title=(title + (f"\n{ptitle}" if ptitle else "")))
        if xname != "delta":
            _sci(ax, "x")
        if yname == "p_E":
            _sci(ax, "y")
        if zoom:
            _zoom(ax, main + refs, xname)
        ax.legend(fontsize=7, title=_key_title(lab) if lab else None, title_fontsize=7, frameon=False)
    _note(fig, data)
    return fig


def _zoom(ax, sets, xname):
    """Fig. 3b: the adhesive branch and small loads (|p_r*| up to 2.5 × the most tensile mean point)."""
    lo, top = 0.0, 0.0
    xs = []
    for s in sets:
        x, y = _series(s, xname, "a_rel")
        with np.errstate(invalid="ignore"):
            mx = mean_standard_error(x)[0]
            my = mean_standard_error(y)[0]
        ok = np.isfinite(mx) & np.isfinite(my)
        if ok.any():
            lo = min(lo, float(np.min(mx[ok])))
            xs.append((mx[ok], my[ok]))
    if lo < 0:
        hi = -2.5 * lo
        lo *= 1.3
    else:
        pos = [float(np.max(x)) for x, _ in xs if x.size]
        hi = 0.1 * max(pos) if pos else 1.0
        lo = -0.05 * hi
    for x, y in xs:
        w = (x >= lo) & (x <= hi)
        if w.any():
            top = max(top, float(np.max(y[w])))
    ax.set_xlim(lo, hi)
    ax.set_ylim(-0.02 * (top or 1), 1.1 * top or 1.0)


def kappa_figure(data):
    """Fig. 2: every hard-wall set's a_rel vs p_r* with its κ fit line, fit range shaded, κ ± SE."""
    hw = [s for s in data.with_data if s.hard_wall]
    if not hw:
        return None
    fig, (ax,) = _figure(1, size=(6.4, 5.2))
    lab = varying(hw, data.keys)
    ax.axhspan(0, 0.1, color="0.92", lw=0, zorder=0, gid="fit-range", label="fit range 0 < a_rel ≤ 0.1 (p > 0)")
    counts, xmax, means, part = [], 0.0, [], False
    for i, s in enumerate(hw):
        color, marker = _COLORS[i % len(_COLORS)], _MARKERS[i % len(_MARKERS)]
        k = stats(kappa_per_realization(s))
        c, _, _ = _draw_set(ax, s, "p_r", "a_rel", color, marker,
                            f"{set_label(s, lab)}: κ = {k[0]:.3f} ± {k[1]:.2g} (n = {k[2]})")
        counts.append(c)
        part = part or (bool((c < s.realizations).any()) and s.realizations > 1)
        x, y = _series(s, "p_r", "a_rel")
        with np.errstate(invalid="ignore"):
            mx, my = mean_standard_error(x)[0], mean_standard_error(y)[0]
        means.append((mx, my))
        fit = np.isfinite(mx) & (mx > 0) & (my > 0) & (my <= 0.1)
        if fit.any() and np.isfinite(k[0]):
            top = float(np.max(mx[fit]))
            xmax = max(xmax, top)
            xs = np.linspace(0, top, 20)
            ax.plot(xs, k[0] * xs, "-", color=color, lw=1.6, alpha=0.6, gid="kappa-fit")
    if xmax > 0:  # the fit range and as much again: the seed's Fig. 2 window
        hi = 2.5 * xmax
        top = max([float(np.nanmax(np.where((mx <= hi) & np.isfinite(my), my, 0.0))) for mx, my in means] + [0.0])
        ax.set_xlim(-0.05 * hi, hi)
        ax.set_ylim(-0.03 * (top or 0.1), 1.15 * (top or 0.1))
    if part:
        ax.plot([], [], "o", mfc="white", mec="0.3", ls="none", label="open: mean over fewer realizations")
    ax.plot([], [], "-", color="0.4", lw=1.6, alpha=0.6, label=r"fit $a_\mathrm{rel} = \kappa\,p_r^*$ "
            "(κ: mean ± SE of the per-realization fits)")
    ax.plot([], [], " ", gid="errorbar-label", label=error_bar_label(*counts).replace(
        "mean ± standard error", "error bars: ± 1 standard error"))
    ax.set(xlabel=_XLABEL["p_r"], ylabel=r"relative contact area $a_\mathrm{rel}$",
           title="Non-adhesive contact: κ fit (seed Fig. 2)")
    _sci(ax, "x")
    ax.legend(fontsize=7, title=_key_title(lab) if lab else None, title_fontsize=7, frameon=False)
    _note(fig, data)
    return fig


def _saved_steps(fields, r=0):
    return sorted(int(k.split("_")[1][1:]) for k in fields if k.startswith(f"r{r}_s") and k.endswith("_u_z"))


def _snapshot_sets(data):
    """The sets Fig. 5 shows: the most adhesive set and its hard-wall reference (either may be absent)."""
    sets = data.with_data
    coh = [s for s in sets if not s.hard_wall and s.adhesive]
    ref = None
    if coh:
        adh = max(coh, key=lambda s: s.scene.interface.phi_n_star)
        ref = reference_of(adh, sets) or next((s for s in sets if s.hard_wall), None)
    else:
        adh = None
        ref = next((s for s in sets if s.hard_wall), None)
    return [s for s in (adh, ref) if s is not None]


def _load_fields(data, s, real):
    """(fields dict, saved steps) of set `s`, realization `real` (None when its fields.npz is absent)."""
    key = s.tasks.get(real)
    path = data.path / "tasks" / str(key) / "fields.npz"
    if key is None or not path.is_file():
        return None
    with np.load(path) as f:
        fields = {k: f[k] for k in f.files}
    steps = _saved_steps(fields)
    return (fields, steps) if steps else None


def contact_maps_figure(data):
    """2+1-D stand-in for Fig. 5: contact maps of the sets Fig. 5 would show, one realization, largest saved δ.

    Each panel: the run's own contact set (`gfmd_contact.core.observables.contact_mask` with the set's law, as its
    a_rel) of the step nearest the first panel's δ; black = contact. None without 2+1-D sets or saved fields.
    """
    shown = [s for s in _snapshot_sets(data) if s.scene.surface.two_d]
    if not shown:
        return None
    real = min(set.intersection(*(set(s.stacked.realizations) for s in shown)) or shown[0].stacked.realizations)
    loaded = [(s, *got) for s in shown if (got := _load_fields(data, s, real)) is not None]
    if not loaded:
        return None

    def delta_of(st, k):
        steps = list(st.step)
        return float(st["delta"][st.realizations.index(real)][steps.index(k)]) if k in steps else np.nan

    target = delta_of(loaded[0][0].stacked, loaded[0][2][-1])
    fig, axes = _figure(len(loaded), size=(4.6, 4.6))
    for ax, (s, fields, steps) in zip(np.atleast_1d(axes), loaded):
        k = min(steps, key=lambda k: abs(delta_of(s.stacked, k) - target) if np.isfinite(target) else -k)
        gap, t_n = fields[f"r0_s{k}_gap"], fields[f"r0_s{k}_t_n"]
        contact = np.asarray(contact_mask(law_from_scene(s.scene), gap, t_n), bool)
        x, y = fields["x"] * 1e6, fields["y"] * 1e6
        ax.imshow(contact.T, origin="lower", extent=(x[0], x[-1], y[0], y[-1]), cmap="Greys", vmin=0, vmax=1,
                  interpolation="nearest", gid="contact")
        what = "hard wall" if s.hard_wall else f"φn* = {s.scene.interface.phi_n_star:g}"
        ax.set(xlabel=r"$x$ (µm)", ylabel=r"$y$ (µm)",
               title=f"set {s.index}, {what}: δ = {delta_of(s.stacked, k) * 1e9:.3g} nm, a_rel = {contact.mean():.3g}")
    fig.suptitle(f"Contact maps at the largest saved δ (realization {real}; 2+1-D stand-in for seed Fig. 5)")
    _note(fig, data)
    return fig


def snapshot_figure(data):
    """Fig. 5: the most adhesive set and its hard-wall reference, one realization, at the largest saved δ."""
    shown = _snapshot_sets(data)
    if not shown or any(s.scene.surface.two_d for s in shown):  # 2+1-D: contact_maps_figure instead
        return None
    real = min(set.intersection(*(set(s.stacked.realizations) for s in shown)) or shown[0].stacked.realizations)
    loaded = [(s, *got) for s in shown if (got := _load_fields(data, s, real)) is not None]
    if not loaded:
        return None
    first, ffirst, sfirst = loaded[0]
    k0 = sfirst[-1]
    d = first.stacked
    i = d.realizations.index(real)
    delta_of = lambda st, k: float(st["delta"][st.realizations.index(real)][list(st.step).index(k)])  # noqa: E731
    target = delta_of(d, k0) if k0 in list(d.step) else np.nan
    fig, (ax,) = _figure(1, size=(9, 4.2))
    x = ffirst["x"] * 1e6
    z_ind = (ffirst[f"r0_s{k0}_u_z"] + ffirst[f"r0_s{k0}_gap"]) * 1e9
    lines = [z_ind]
    for s, fields, steps in loaded:
        k = min(steps, key=lambda k: abs(delta_of(s.stacked, k) - target) if k in list(s.stacked.step) else np.inf)
        u = fields[f"r0_s{k}_u_z"] * 1e9
        lines.append(u)
        what = "non-adhesive (hard wall)" if s.hard_wall else f"adhesive, φn* = {s.scene.interface.phi_n_star:g}"
        ax.plot(x, u, color="tab:red" if s.hard_wall else "tab:green", lw=0.8, gid="surface",
                label=f"elastic surface, {what} (set {s.index}, δ = {delta_of(s.stacked, k) * 1e9:.3g} nm)")
    top = max(float(np.max(v)) for v in lines)
    bottom = min(float(np.min(v)) for v in lines)
    span = top - bottom or 1.0
    ax.fill_between(x, z_ind, top + 0.15 * span, color="0.75", lw=0, label="rigid indenter", gid="indenter")
    ax.plot(x, z_ind, color="0.35", lw=0.5)
    ax.set_xlim(x.min(), x.max())
    ax.set_ylim(bottom - 0.05 * span, top + 0.15 * span)
    seed = first.seeds.get(real)
    ax.set(xlabel=r"$x$ (µm)", ylabel=r"$z$ (nm)",
           title=f"Interface at the largest saved δ (realization {real}, random seed {seed}; seed Fig. 5)")
    ax.legend(fontsize=7, loc="lower left", frameon=False)
    _note(fig, data)
    del i
    return fig


def make_study_figures(study_dir, over=None, data=None):
    """{name: Figure} of a study directory (`FIGURES`, `FIGURES_2D` for surfaces; figures the study has no sets for are left out)."""
    data = data or read_study_dir(study_dir)
    figs = {}
    k = kappa_figure(data)
    if k is not None:
        figs["kappa_fit"] = k
    figs["area_vs_reduced_pressure"] = _overlay(data, over, "p_r", "a_rel", r"relative contact area $a_\mathrm{rel}$",
                                                "Load–area relation (seed Fig. 3a)")
    figs["area_vs_reduced_pressure_zoom"] = _overlay(data, over, "p_r", "a_rel",
                                                     r"relative contact area $a_\mathrm{rel}$",
                                                     "Small loads and the adhesive branch (seed Fig. 3b)", zoom=True)
    figs["pressure_vs_delta"] = _overlay(data, over, "delta", "p_E", r"mean pressure $p/E^*$",
                                         "Mean pressure vs penetration (seed Fig. 4a)")
    figs["area_vs_delta"] = _overlay(data, over, "delta", "a_rel", r"relative contact area $a_\mathrm{rel}$",
                                     "Contact area vs penetration (seed Fig. 4b)")
    figs["gr_over_g_vs_delta"] = _overlay(data, over, "delta", "gr_g", r"$\bar g_r/\bar g$",
                                          "rms gradient in contact vs penetration (seed Fig. 4c)")
    snap = snapshot_figure(data)
    if snap is not None:
        figs["interface_snapshot"] = snap
    maps = contact_maps_figure(data)
    if maps is not None:
        figs["contact_maps"] = maps
    figs["area_vs_pressure"] = _overlay(data, over, "p_E", "a_rel", r"relative contact area $a_\mathrm{rel}$",
                                        "Contact area vs mean pressure (seed Figs. 7–8)")
    figs.update(cycle_study_figures(study_dir, over=over))  # load paths: pull-off and hysteresis vs the axis
    return figs


def save_figures(figs, out, fmt="png"):
    if fmt not in FORMATS:
        raise ValueError(f"--format {fmt!r}: choose one of {', '.join(FORMATS)}")
    out = Path(out)
    paths = []
    with safe_files.locked(out, what="figure folder"):  # one writer at a time; each figure atomic
        for name, fig in figs.items():
            path = out / f"{name}.{fmt}"
            with rc_context({"svg.fonttype": "none"}):
                safe_files.save_figure(fig, path, format=fmt, dpi=150)
            paths.append(path)
    return paths


def plot_study(study_dir, fmt="png", over=None):
    """Write the figures of `study_dir` into study_dir/figures/ as `fmt`; returns their paths.

    Raises study_data.StudyDirError (a ValueError) for a directory that is not a study directory or
    has no finished task, ValueError for an unknown format or --over key.
    """
    if fmt not in FORMATS:
        raise ValueError(f"--format {fmt!r}: choose one of {', '.join(FORMATS)}")
    figs = make_study_figures(study_dir, over=over)
    return save_figures(figs, Path(study_dir) / "figures", fmt)
