"""A measured profile from a file: heights written to a text file, read as surface.kind = "file".
==============================================================================================

Stands in for a profilometer trace: a text file with one height (m) per line on a
periodic grid of N points (here synthesised: two waves and a little noise; a real
trace would be detrended and made periodic first). The scene names the file with
surface.path; the same profile is pressed with the hard wall and the cohesive law.
Plots the profile and a_rel vs p/E* of both. SI units throughout.

    python examples/measured_profile.py [--size small|full] [--out DIR]
"""

import argparse
import os
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import gfmd_contact as gc

SIZES = {"small": {"nodes": 512, "steps": 15}, "full": {"nodes": 2048, "steps": 60}}

parser = argparse.ArgumentParser(description=(__doc__ or "").partition("\n")[0])  # the gallery runs it without __doc__
parser.add_argument("--size", choices=SIZES, default=os.environ.get("GFMD_EXAMPLE_SIZE", "full"))
parser.add_argument("--out", type=Path, default=Path("results/examples"))
args = parser.parse_args()
size = SIZES[args.size]

# the "measurement": heights in m on N points over a period L = 1 µm
L, N = 1e-6, size["nodes"]
x = np.arange(N) * L / N
rng = np.random.default_rng(7)
h = (20e-9 * np.cos(2 * np.pi * x / L) + 6e-9 * np.cos(2 * np.pi * 5 * x / L + 1.0)
     + 0.5e-9 * rng.standard_normal(N))
args.out.mkdir(parents=True, exist_ok=True)
profile = args.out / "measured_profile.txt"
np.savetxt(profile, h, header=f"heights (m) of a periodic profile, L = {L} m, N = {N}")

scene = gc.load_scene(f"""
[surface]
kind = "file"
path = "{profile.resolve()}"
length = {L}
nodes = {N}

[material]
youngs_modulus = 70e9
poisson_ratio = 0.3

[interface]
law = "cohesive"
phi_n_star = 0.02
length_normal = 1e-9

[loading]
initial_separation = 12e-9
final_penetration = 15e-9
steps = {size["steps"]}
""", name="measured_profile")

e_star = scene.material.contact_modulus
fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 6), layout="constrained")
top.plot(x * 1e6, h * 1e9, lw=0.8)
top.set(xlabel="x (µm)", ylabel="h (nm)", title=f"profile read from {profile.name} (N = {N})")
for law in ("hard-wall", "cohesive"):
    run = gc.run(gc.change(scene, {"interface.law": law}), out=args.out / "measured_profile" / law,
                 overwrite=True, progress=False)
    c = run.curve
    bottom.plot(c["p"] / e_star, c["a_rel"], "k--" if law == "hard-wall" else "o-", ms=3,
                label=law if law == "hard-wall" else f"cohesive, φn* = {scene.interface.phi_n_star}")
    print(f"{law}: {run.meta['method']}, a_rel at δ = {c['delta'].iloc[-1] * 1e9:.1f} nm: {c['a_rel'].iloc[-1]:.3f}")
bottom.axvline(0, color="gray", lw=0.5)
bottom.set(xlabel="mean pressure $p/E^*$", ylabel="relative contact area $a_\\mathrm{rel}$")
bottom.legend()
path = args.out / "measured_profile.png"
fig.savefig(path, dpi=120)
print(f"wrote {path}")
