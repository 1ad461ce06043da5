"""GFMD against the independent finite-element reference on one cell.
==================================================================

A sinusoidal indenter (amplitude 50 nm, period L = 1 µm) pressed into an elastic
layer of thickness D = L on a rigid base, with the cohesive law (φn* = 0.01,
δn = 1 nm; δ from −6 nm to 60 nm): the same scene solved by GFMD (`method="gfmd"`)
and by the scikit-fem FE reference (`method="fe"`, P2 elements; the case of
verification/scenes.py `cohesive_sinusoid`); plots p(δ), a_rel(δ) and their
difference. Both solve the same discrete cell (N surface nodes), so the under-resolved
δn (< 2 L/N) that `gc.check` reports is no concern here: the comparison is of the
methods, not of the resolution. SI units throughout.

    python examples/gfmd_vs_fe.py [--size small|full] [--out DIR]
"""

import argparse
import os
import warnings
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import gfmd_contact as gc

SIZES = {"small": {"surface.nodes": 32, "loading.steps": 6}, "full": {"surface.nodes": 128, "loading.steps": 33}}

parser = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])  # the gallery runs it without __doc__
parser.add_argument("--size", choices=SIZES, default=os.environ.get("GFMD_EXAMPLE_SIZE", "full"))
parser.add_argument("--out", type=Path, default=Path("results/examples"))
args = parser.parse_args()

L = 1e-6  # m
scene = gc.load_scene({
    "surface": {"kind": "sinusoid", "length": L, "amplitude": 50e-9, "nodes": 32},
    "material": {"youngs_modulus": 70e9, "poisson_ratio": 0.3, "thickness": L},
    "interface": {"law": "cohesive", "phi_n_star": 0.01, "length_normal": 1e-9},
    "loading": {"initial_separation": 6e-9, "final_penetration": 60e-9, "steps": 6},  # δ0 outside jump-in
    "output": {"field_steps": 2},
}, name="gfmd_vs_fe")
scene = gc.change(scene, SIZES[args.size])

warnings.filterwarnings("ignore", message="under-resolved")  # see the docstring
runs = {m: gc.run(scene, out=args.out / "gfmd_vs_fe" / m, method=m, overwrite=True, progress=False)
        for m in ("gfmd", "fe")}
g, f = runs["gfmd"].curve, runs["fe"].curve
e_star = scene.material.contact_modulus
print(f"methods that ran: {runs['gfmd'].meta['method']} and {runs['fe'].meta['method']}")
print(f"max |p_GFMD − p_FE| / E* = {np.max(np.abs(g['p'] - f['p'])) / e_star:.2e}, "
      f"max |Δa_rel| = {np.max(np.abs(g['a_rel'] - f['a_rel'])):.3f}")

fig, axes = plt.subplots(1, 3, figsize=(12, 3.5), layout="constrained")
for name, c, style in (("gfmd", g, "o-"), ("fe", f, "s--")):
    label = runs[name].meta["method"]
    axes[0].plot(c["delta"] * 1e9, c["p"] / e_star, style, ms=4, mfc="none", label=label)
    axes[1].plot(c["delta"] * 1e9, c["a_rel"], style, ms=4, mfc="none", label=label)
axes[2].semilogy(g["delta"] * 1e9, np.abs(g["p"] - f["p"]) / e_star + 1e-16, "k.-")
axes[0].set(xlabel="δ (nm)", ylabel="$p/E^*$")
axes[1].set(xlabel="δ (nm)", ylabel="$a_\\mathrm{rel}$")
axes[2].set(xlabel="δ (nm)", ylabel="$|p_\\mathrm{GFMD} - p_\\mathrm{FE}|/E^*$")
axes[0].legend()
fig.suptitle(f"sinusoid (50 nm, L = 1 µm) on a layer D = L, cohesive φn* = 0.01, δn = 1 nm, N = {scene.surface.nodes}")
path = args.out / "gfmd_vs_fe.png"
fig.savefig(path, dpi=120)
print(f"wrote {path}")
