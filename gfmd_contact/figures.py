"""The seed's figures of a run or a study, as matplotlib Figures or files.

Axes carry the non-dimensional groups p_r* = p/(ḡ_r E*), p/E*, a_rel, ḡ_r/ḡ, and δ in nm
(`gfmd_contact.app.plots`, `gfmd_contact.app.study_plots`).
"""

from __future__ import annotations

from pathlib import Path


def _dir(thing):
    return Path(getattr(thing, "dir", thing))


def run_figures(result, delta=None, realization=None):
    """The figures of a run as {name: matplotlib.figure.Figure}.

    Parameters
    ----------
    result : RunResult, str or pathlib.Path
        A run (or its directory).
    delta : float, optional
        Penetration δ (m) of the interface snapshot (nearest saved step; default the last).
    realization : int, optional
        Realization of the snapshot (default: the first with saved fields).

    Returns
    -------
    dict
        area_vs_reduced_pressure (seed Fig. 3), pressure_vs_delta, area_vs_delta,
        gr_over_g_vs_delta (Fig. 4), interface_snapshot (Fig. 5; if fields were saved).
    """
    from gfmd_contact.app.plots import make_figures

    return make_figures(_dir(result), snapshot_delta=delta, realization=realization)


def plot_run(result, fmt="png", delta=None, realization=None):
    """Write the figures of a run into its plots/ folder (as `gfmd plot DIR`); returns their paths.

    Parameters
    ----------
    result : RunResult, str or pathlib.Path
    fmt : {"png", "svg", "pdf"}
    delta : float, optional
        δ (m) of the interface snapshot.
    realization : int, optional
        Realization of the snapshot.

    Returns
    -------
    list of pathlib.Path
    """
    from gfmd_contact.app.plots import plot_run as write

    return write(_dir(result), snapshot_delta=delta, fmt=fmt, realization=realization)


def study_figures(study, over=None):
    """The figures of a study as {name: matplotlib.figure.Figure}.

    Parameters
    ----------
    study : StudyResult, str or pathlib.Path
    over : str, optional
        A varied dotted key: one panel per combination of the other keys, one curve per value of it.

    Returns
    -------
    dict
        kappa_fit (seed Fig. 2; hard-wall sets), area_vs_reduced_pressure and _zoom (Fig. 3),
        pressure_vs_delta, area_vs_delta, gr_over_g_vs_delta (Fig. 4), interface_snapshot
        (Fig. 5), area_vs_pressure (Figs. 7–8).
    """
    from gfmd_contact.app.study_plots import make_study_figures

    return make_study_figures(_dir(study), over=over)


def plot_study(study, fmt="png", over=None):
    """Write the figures of a study into its figures/ folder (as `gfmd study plot DIR`); returns their paths.

    Parameters
    ----------
    study : StudyResult, str or pathlib.Path
    fmt : {"png", "svg"}
    over : str, optional
        See `study_figures`.

    Returns
    -------
    list of pathlib.Path
    """
    from gfmd_contact.app.study_plots import plot_study as write

    return write(_dir(study), fmt=fmt, over=over)
