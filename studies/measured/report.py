"""A real AFM map, periodic cell vs free half-space: κ of a_rel = κ p/(ḡ_r E*) and the pull-off, per quadrant.

Reads the suite of studies/measured/measured_small_q*.toml (`gfmd study run … --out DIR`): per study directory
DIR/measured_small_qK/ its study.json (the tasks and their parameters) and each task's curve.csv, meta.json,
scene.toml and fields.npz. Per quadrant (the ensemble: the map's four quadrants) and boundary:

* κ: `gfmd_contact.core.observables.fit_kappa` on the hard wall's loading branch (0 < a_rel ≤ 0.1, p > 0), with
  ḡ_r as the run recorded it (curve.csv; the periodic cell's seed Eq. 6 takes the step across the seam between
  opposite edges, a real cliff of its indenter; a free region's does not, the seam does not exist there) and
  with ḡ_r recomputed from the saved fields without the seam for both boundaries
  (`local_gradient_squared(…, periodic=False)`). The recomputation with the run's own rule must reproduce
  curve.csv's ḡ_r (checked).
* the contact's share in the edge band (nodes within EDGE nodes of the region's edge) at the hard wall's
  first loading step with a_rel ≥ A_EDGE, against the band's share of the area;
* the pull-off p̄_po (MPa, < 0 tensile) and hysteresis W of each cohesive cycle (meta.json).

Mean ± SE over the quadrants (SE = s/√n) and the paired difference free − periodic. Writes DIR/table.md,
DIR/table.csv and DIR/figures/{area_vs_reduced_pressure,contact_maps,cycles}.png.

    python studies/measured/report.py results/measured_small
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import sys
from pathlib import Path

import numpy as np

from gfmd_contact.core.laws import law_from_scene
from gfmd_contact.core.observables import (
    contact_mask,
    fit_kappa,
    local_gradient_squared,
)
from gfmd_contact.core.scene import load_scene

STUDY = "measured_small_q"
BOUNDARIES = ("periodic", "free")
A_MAX = 0.1
EDGE = 16  # nodes: the edge band's width (15.6 nm on the 0.977 nm grid)
A_EDGE = 0.02


def _rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def _tasks(study_dir):
    """{(boundary, law, φn*): task directory} of one quadrant's study."""
    record = json.loads((study_dir / "study.json").read_text())
    out = {}
    for t in record["tasks"]:
        p = t["parameters"]
        out[(p["surface.boundary"], p["interface.law"], float(p["interface.phi_n_star"]))] = study_dir / "tasks" / t["key"]
    return out


def hard_wall(task):
    """The hard-wall task's loading branch: κ with ḡ_r as recorded and without the seam, and the edge-band share."""
    scene = load_scene(task / "scene.toml")
    e_star = scene.material.contact_modulus
    law = law_from_scene(scene)
    spacing = scene.surface.spacings
    fields = np.load(task / "fields.npz")
    h = fields["h_r0"]
    periodic = scene.surface.boundary == "periodic"
    g2_run, g2_in = local_gradient_squared(h, spacing, periodic), local_gradient_squared(h, spacing, False)
    rows = [r for r in _rows(task / "curve.csv") if r["branch"] == "loading"]
    p, a, gr, gr_in, gr_check, share = [], [], [], [], [], None
    band = np.ones(h.shape, bool)
    band[EDGE:-EDGE, EDGE:-EDGE] = False
    for r in rows:
        k = int(r["step"])
        if f"r0_s{k}_gap" not in fields.files:  # step 0 (fields are saved from step 1): out of contact
            if float(r["a_rel"]) != 0.0:
                raise ValueError(f"{task}: no fields at step {k}, which is in contact")
            contact = np.zeros(h.shape, bool)
        else:
            contact = contact_mask(law, fields[f"r0_s{k}_gap"], fields[f"r0_s{k}_t_n"])
        p.append(float(r["p"]))
        a.append(float(r["a_rel"]))
        gr.append(float(r["g_r"]))
        gr_in.append(math.sqrt(g2_in[contact].mean()) if contact.any() else math.nan)
        gr_check.append(math.sqrt(g2_run[contact].mean()) if contact.any() else math.nan)
        if share is None and a[-1] >= A_EDGE:
            share = (float(contact[band].sum() / contact.sum()), k, a[-1])
    p, a = np.array(p), np.array(a)
    ok = np.isfinite(gr) & np.isfinite(gr_check)
    if not np.allclose(np.array(gr)[ok], np.array(gr_check)[ok], rtol=1e-9):
        raise ValueError(f"{task}: ḡ_r recomputed from the fields differs from curve.csv's")
    return {
        "kappa": fit_kappa(p / (np.array(gr) * e_star), a, A_MAX),
        "kappa_interior": fit_kappa(p / (np.array(gr_in) * e_star), a, A_MAX),
        "g": float(rows[0]["g"]),
        "g_interior": float(np.sqrt(g2_in.mean())),
        "share": share, "band_area": float(band.mean()),
        "curve": (p / (np.array(gr) * e_star), p / (np.array(gr_in) * e_star), a),
    }


def cycle(task):
    """The cycle's pull-off p̄_po (Pa, the most tensile mean pressure on unloading) and hysteresis W (J/m²), as the run
    recorded them (meta.json, `gfmd_contact.core.cycle.cycle_observables`); refused if a step did not converge."""
    meta = json.loads((task / "meta.json").read_text())
    if not meta["all_converged"]:
        raise ValueError(f"{task}: a step did not converge")
    (row,) = meta["cycles"][0]["cycles"]
    if row["pull_off_pressure"] is None:
        raise ValueError(f"{task}: the cycle has no unloading step (stopped at its full-contact limit?)")
    return {"pull_off": row["pull_off_pressure"], "hysteresis": row["hysteresis"]}


def collect(root):
    root = Path(root)
    dirs = sorted(root.glob(f"{STUDY}*"))
    if not dirs:
        raise SystemExit(f"{root}: no {STUDY}* study directories (run the suite first)")
    data = {}
    for d in dirs:
        for (boundary, law, phi), task in _tasks(d).items():
            q = d.name.removeprefix("measured_small_")
            data[(q, boundary, law, phi)] = hard_wall(task) if law == "hard-wall" else cycle(task)
    return data


def _mean_se(values):
    v = np.asarray(values, float)
    return float(v.mean()), float(v.std(ddof=1) / math.sqrt(v.size)) if v.size > 1 else math.nan, v.size


def _pm(m, se, n, scale=1.0, fmt=".3g"):
    return f"{m * scale:{fmt}} ± {se * scale:{fmt}} (n = {n})"


def render(root):
    """(table.md text, table.csv text) of the suite under `root`."""
    data = collect(root)
    quads = sorted({k[0] for k in data})
    phis = sorted({k[3] for k in data if k[2] == "cohesive"})
    md = io.StringIO()
    rows = [("quantity", "quadrant", "periodic", "free")]
    hw = {(k[0], k[1]): v for k, v in data.items() if k[2] == "hard-wall"}
    metrics = (("kappa", "κ (ḡ_r as recorded)", lambda r: r["kappa"][0]),
               ("kappa_interior", "κ (ḡ_r without the seam)", lambda r: r["kappa_interior"][0]),
               ("g", "ḡ (as recorded)", lambda r: r["g"]),
               ("g_interior", "ḡ (without the seam)", lambda r: r["g_interior"]),
               ("edge_share", f"contact share in the {EDGE}-node edge band", lambda r: r["share"][0] if r["share"] else math.nan))
    md.write("| quantity | " + " | ".join(quads) + " | periodic (mean ± SE) | free (mean ± SE) | free − periodic |\n")
    md.write("|---" * (len(quads) + 4) + "|\n")

    def line(label, key, per, scale=1.0):
        vals = {b: [per(q, b) * scale for q in quads] for b in BOUNDARIES}
        cells = [f"{vals['periodic'][i]:.3g} / {vals['free'][i]:.3g}" for i in range(len(quads))]
        diff = [f - p for f, p in zip(vals["free"], vals["periodic"])]
        md.write(f"| {label} | " + " | ".join(cells) + " | " + " | ".join(
            _pm(*_mean_se(v)) for v in (vals["periodic"], vals["free"], diff)) + " |\n")
        for i, q in enumerate(quads):
            rows.append((key, q, f"{vals['periodic'][i]:.6g}", f"{vals['free'][i]:.6g}"))

    for key, label, get in metrics:
        line(label, key, lambda q, b, get=get: get(hw[(q, b)]))
    for phi in phis:
        line(f"pull-off p̄_po (MPa), φn* = {phi:g}", f"pull_off_MPa_phi{phi:g}",
             lambda q, b, phi=phi: data[(q, b, "cohesive", phi)]["pull_off"], 1e-6)
        line(f"hysteresis W (mJ/m²), φn* = {phi:g}", f"hysteresis_mJ_m2_phi{phi:g}",
             lambda q, b, phi=phi: data[(q, b, "cohesive", phi)]["hysteresis"], 1e3)
    r0 = hw[(quads[0], "periodic")]
    md.write(f"\nCells: periodic / free per quadrant. κ fitted on the hard wall's loading steps with "
             f"0 < a_rel ≤ {A_MAX} ({', '.join(str(hw[(q, b)]['kappa'][1]) for q in quads for b in BOUNDARIES)} "
             f"points, quadrant by quadrant, periodic then free). Edge band: {r0['band_area']:.3f} of the area; "
             f"share taken at the first loading step with a_rel ≥ {A_EDGE}.\n")
    tab = io.StringIO()
    csv.writer(tab, lineterminator="\n").writerows(rows)
    return md.getvalue(), tab.getvalue(), data


def figures(root, data):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(root) / "figures"
    out.mkdir(exist_ok=True)
    quads = sorted({k[0] for k in data})
    colours = {"periodic": "tab:blue", "free": "tab:orange"}
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2), sharey=True)
    for ax, which, title in ((axes[0], 0, "ḡ_r as recorded (periodic gradient)"),
                             (axes[1], 1, "ḡ_r without the periodic seam")):
        for b in BOUNDARIES:
            for i, q in enumerate(quads):
                r = next(v for k, v in data.items() if k[:3] == (q, b, "hard-wall"))
                x, a = r["curve"][which], r["curve"][2]
                use = (a > 0) & (a <= 0.2) & (x > 0)
                ax.plot(x[use], a[use], "o-", ms=3, color=colours[b], alpha=0.8, label=b if i == 0 else None)
        ax.set_xlabel(r"$p/(\bar g_r E^*)$")
        ax.set_title(title, fontsize=10)
        ax.axhline(A_MAX, color="k", lw=0.5, ls=":")
    axes[0].set_ylabel(r"$a_\mathrm{rel}$")
    axes[0].legend()
    fig.suptitle("di-1.di, four 250 nm quadrants, hard wall, loading", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "area_vs_reduced_pressure.png", dpi=120)
    plt.close(fig)
    _contact_maps(root, out, plt)
    _cycles(root, out, plt)


def _contact_maps(root, out, plt):
    tasks = _tasks(Path(root) / f"{STUDY}1")
    fig, axes = plt.subplots(1, 2, figsize=(9, 4.4))
    for ax, b in zip(axes, BOUNDARIES):
        task = tasks[(b, "hard-wall", 0.01)]
        scene = load_scene(task / "scene.toml")
        f = np.load(task / "fields.npz")
        rows = [r for r in _rows(task / "curve.csv") if r["branch"] == "loading" and float(r["a_rel"]) >= A_EDGE]
        k = int(rows[0]["step"])
        pressure = -f[f"r0_s{k}_t_n"]
        lx, ly = scene.surface.length * 1e9, scene.surface.length_y * 1e9
        im = ax.imshow(np.log10(np.maximum(pressure, 1e6)).T, origin="lower", extent=(0, lx, 0, ly), cmap="magma",
                       vmin=6, vmax=11)
        ax.set_title(f"{b}: step {k}, a_rel = {float(rows[0]['a_rel']):.3f}, p = {float(rows[0]['p']) / 1e6:.3g} MPa",
                     fontsize=9)
        ax.set_xlabel("x (nm)")
    axes[0].set_ylabel("y (nm)")
    fig.colorbar(im, ax=axes, label=r"$\log_{10}(-t_z$ / Pa)")
    fig.suptitle("q1, hard wall: contact pressure", fontsize=10)
    fig.savefig(out / "contact_maps.png", dpi=120)
    plt.close(fig)


def _cycles(root, out, plt):
    tasks = _tasks(Path(root) / f"{STUDY}1")
    phis = sorted(k[2] for k in tasks if k[1] == "cohesive" and k[0] == "periodic")
    fig, axes = plt.subplots(1, len(phis), figsize=(5 * len(phis), 4))
    for ax, phi in zip(np.atleast_1d(axes), phis):
        for b in BOUNDARIES:
            rows = _rows(tasks[(b, "cohesive", phi)] / "curve.csv")
            ax.plot([float(r["delta"]) * 1e9 for r in rows], [float(r["p"]) / 1e6 for r in rows], "-",
                    color="tab:blue" if b == "periodic" else "tab:orange", label=b)
        ax.set_title(f"q1, cohesive φn* = {phi:g}", fontsize=10)
        ax.set_xlabel("δ (nm; free: from the padded cell's mean plane)")
        ax.axhline(0, color="k", lw=0.5)
    np.atleast_1d(axes)[0].set_ylabel("p (MPa)")
    np.atleast_1d(axes)[0].legend()
    fig.tight_layout()
    fig.savefig(out / "cycles.png", dpi=120)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("root", help="the suite's directory (gfmd study run … --out DIR)")
    ap.add_argument("--no-figures", action="store_true")
    args = ap.parse_args(argv)
    md, tab, data = render(args.root)
    Path(args.root, "table.md").write_text(md)
    Path(args.root, "table.csv").write_text(tab)
    if not args.no_figures:
        figures(args.root, data)
    sys.stdout.write(md)


if __name__ == "__main__":
    main()
