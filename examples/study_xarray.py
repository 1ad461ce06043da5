"""A small parameter study on Dask, its summary opened as an xarray Dataset.
=========================================================================

The default scene with the hard wall and two adhesion strengths φn* (zipped with
interface.law: they vary together) × two values of δn (an axis): six parameter sets,
each over the same random realizations, run as one resumable study (rerun the script
and every finished task is reused). The summary (summary.nc) has one dimension per
axis, "zip" and "step"; a_rel vs p/E* is read from it with `.sel`. SI units throughout.

    python examples/study_xarray.py [--size small|full] [--out DIR] [--workers K]
"""

import argparse
import os
from pathlib import Path

import matplotlib.pyplot as plt

import gfmd_contact as gc

SIZES = {"small": {"surface.nodes": 1024, "surface.rollon_wavelength": 5e-9, "surface.realizations": 1,
                   "loading.steps": 10},
         "full": {"surface.nodes": 4096, "surface.realizations": 2, "loading.steps": 60}}

def main():
    parser = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])  # the gallery runs it without __doc__
    parser.add_argument("--size", choices=SIZES, default=os.environ.get("GFMD_EXAMPLE_SIZE", "full"))
    parser.add_argument("--out", type=Path, default=Path("results/examples"))
    parser.add_argument("--workers", type=int, default=2, help="Dask worker processes")
    args = parser.parse_args()

    base = gc.change(gc.default_scene(), SIZES[args.size])
    study = gc.make_study(base, name="study_xarray",
                          axes={"interface.length_normal": [1e-9, 2e-9]},
                          zip={"interface.law": ["hard-wall", "cohesive", "cohesive"],
                               "interface.phi_n_star": [0.15, 0.01, 0.15]})
    print(f"{len(study.sets)} parameter sets, {len(study.tasks)} tasks")
    result = gc.run_study(study, args.out / "study_xarray", workers=args.workers, progress=False)
    print(result)

    ds = result.summary                                  # xarray.Dataset of summary.nc
    print(ds)
    e_star = base.material.contact_modulus
    fig, axes = plt.subplots(1, ds.sizes["interface.length_normal"], figsize=(9, 3.6), layout="constrained",
                             sharey=True, squeeze=False)
    for ax, dn in zip(axes[0], ds["interface.length_normal"].values):
        for z in range(ds.sizes["zip"]):
            one = ds.sel({"interface.length_normal": dn}).isel(zip=z)
            law, phi = str(one["interface.law"].values), float(one["interface.phi_n_star"].values)
            label = "hard wall" if law == "hard-wall" else f"φn* = {phi:g}"
            ax.plot(one["p"] / e_star, one["a_rel"], "k--" if law == "hard-wall" else "o-", ms=2.5, label=label)
        ax.axvline(0, color="gray", lw=0.5)
        ax.set(title=f"δn = {dn * 1e9:g} nm", xlabel="mean pressure $p/E^*$")
    axes[0, 0].set(ylabel="relative contact area $a_\\mathrm{rel}$")
    axes[0, 0].legend(fontsize=8)
    path = args.out / "study_xarray.png"
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")
    if args.size == "full":  # the seed's figures of the study, as `gfmd study plot DIR` draws them
        print(f"{len(gc.plot_study(result))} figures in {result.dir / 'figures'}")


if __name__ == "__main__":  # Dask starts its workers by spawning: a script needs this guard
    main()
