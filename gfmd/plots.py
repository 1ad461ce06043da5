"""Seed-style figures of a run directory (seed Figs. 3–5), written as PNG.

Units: axes are labelled with their non-dimensional groups: p_r* = p/(ḡ_r E*),
p/E*, a_rel, ḡ_r/ḡ, and δ in nm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .ensemble import mean_standard_error
from .io import read_run
from .observables import fit_kappa


def _figure(size):
    fig = Figure(figsize=size)
    return fig, fig.subplots()


def _stack(curves, name):
    return np.array([c[name] for _, c in sorted(curves.items())], dtype=float)


def plot_run(run_dir, snapshot_delta=None):
    """Write the figures of `run_dir` into run_dir/plots/; returns the list of PNG paths.

    snapshot_delta: δ (m) of the interface snapshot (nearest saved step; default: last saved).
    """
    run_dir = Path(run_dir)
    scene, curves, fields, meta = read_run(run_dir)
    out = run_dir / "plots"
    out.mkdir(exist_ok=True)
    e_star = scene.material.contact_modulus
    delta = curves[min(curves)]["delta"]
    p, a_rel, g_r, g = (_stack(curves, k) for k in ("p", "a_rel", "g_r", "g"))
    with np.errstate(invalid="ignore", divide="ignore"):
        p_r = p / (g_r * e_star)
    label = f"{scene.interface.law}" + (f", φn* = {scene.interface.phi_n_star:g}" if scene.interface.cohesive else "")
    nreal = len(curves)
    paths = []

    def save(fig, name):
        fig.tight_layout()
        path = out / name
        fig.savefig(path, dpi=120)
        paths.append(path)

    # Fig. 3: a_rel vs p_r*
    fig, ax = _figure((5, 4))
    mx, sx, _ = mean_standard_error(p_r)
    my, sy, _ = mean_standard_error(a_rel)
    ok = np.isfinite(mx) & (mx > 0)
    ax.errorbar(mx[ok], my[ok], xerr=sx[ok], yerr=sy[ok], fmt="o", ms=3, label=f"{label} ({nreal} real.)")
    if not scene.interface.cohesive:  # seed Eq. 1 holds for non-adhesive contact only
        try:
            kappa, npts = fit_kappa(mx, my)
            xs = np.linspace(0, np.nanmax(mx[ok]), 50)
            ax.plot(xs, kappa * xs, "k--", lw=1, label=f"fit a_rel ≤ 0.1: κ = {kappa:.3f} ({npts} pts)")
        except ValueError:
            pass
    ax.set(xlabel="reduced pressure p/(ḡ_r E*)", ylabel="relative contact area a_rel", title="load–area (seed Fig. 3)")
    ax.legend(fontsize=8)
    save(fig, "area_vs_reduced_pressure.png")

    # Fig. 4a–c: vs δ
    for name, values, ylabel in (("pressure_vs_delta.png", p / e_star, "p/E*"),
                                 ("area_vs_delta.png", a_rel, "a_rel"),
                                 ("gr_over_g_vs_delta.png", g_r / g, "ḡ_r/ḡ")):
        fig, ax = _figure((5, 4))
        m, se, _ = mean_standard_error(values)
        ax.errorbar(delta * 1e9, m, yerr=se, fmt="-o", ms=2, label=label)
        ax.set(xlabel="penetration δ (nm)", ylabel=ylabel, title=f"{ylabel} vs δ (seed Fig. 4)")
        ax.axvline(0, color="0.7", lw=0.5)
        ax.legend(fontsize=8)
        save(fig, name)

    # Fig. 5: interface snapshot
    r0 = min(curves)
    steps = sorted(int(k.split("_")[1][1:]) for k in fields if k.startswith(f"r{r0}_s") and k.endswith("_u_z"))
    if steps:
        target = delta[steps[-1]] if snapshot_delta is None else snapshot_delta
        k = min(steps, key=lambda s: abs(delta[s] - target))
        x = fields["x"]
        u_z = fields[f"r{r0}_s{k}_u_z"]
        gap = fields[f"r{r0}_s{k}_gap"]
        z_ind = u_z + gap
        fig, ax = _figure((8, 3.5))
        ax.fill_between(x * 1e6, z_ind * 1e9, np.max(z_ind) * 1e9 + 5, color="0.6", label="rigid indenter")
        ax.plot(x * 1e6, u_z * 1e9, color="tab:green" if scene.interface.cohesive else "tab:red", lw=0.8,
                label="elastic surface u_z")
        ax.set(xlabel="x (µm)", ylabel="z (nm)",
               title=f"interface at δ = {delta[k] * 1e9:.2f} nm, realization {r0} (seed Fig. 5)")
        ax.legend(fontsize=8, loc="lower right")
        save(fig, "interface_snapshot.png")
    return paths
