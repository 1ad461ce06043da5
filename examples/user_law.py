"""A user-defined traction law: energy, traction and tangent as Python functions, run by GFMD and the FE.
======================================================================================================

Two laws given through `gc.user_law`: the seed's Eq. 3 re-expressed from its formula (which must
reproduce the built-in law), and a Morse-type law V = φn[(1 − e^{−Δn/ℓ})² − 1] with the same work
of separation φn and the same peak traction φn/(e δn) (ℓ = e δn/2), a different shape. The cell
is the sinusoid of examples/gfmd_vs_fe.py (amplitude 50 nm, L = 1 µm, layer D = L, φn* = 0.01,
δn = 1 nm); each law runs with GFMD and the FE. Plots T_n(Δn) of the laws, p(δ), and how far the
re-expressed Eq. 3 lies from the built-in law. The functions take numpy arrays of gaps Δn (m) and
return J/m², Pa (> 0 tensile) and Pa/m; `gc.user_law` checks them against each other first.

    python examples/user_law.py [--size small|full] [--out DIR]
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
    "loading": {"initial_separation": 6e-9, "final_penetration": 60e-9, "steps": 6},
    "output": {"field_steps": 1},
}, name="user_law")
scene = gc.change(scene, SIZES[args.size])
PHI, DN = scene.work_normal, scene.interface.length_normal  # φn (J/m²), δn (m)
ELL = np.e * DN / 2  # the Morse length giving Eq. 3's peak traction φn/(e δn)


def eq3_energy(gap):
    s = gap / DN
    return -PHI * (1 + s) * np.exp(-s)


def eq3_traction(gap):
    s = gap / DN
    return PHI / DN * s * np.exp(-s)


def eq3_tangent(gap):
    s = gap / DN
    return PHI / DN**2 * (1 - s) * np.exp(-s)


def morse_energy(gap):
    return PHI * ((1 - np.exp(-gap / ELL)) ** 2 - 1)


def morse_traction(gap):
    e = np.exp(-gap / ELL)
    return 2 * PHI / ELL * (1 - e) * e


def morse_tangent(gap):
    e = np.exp(-gap / ELL)
    return 2 * PHI / ELL**2 * (2 * e * e - e)


laws = {"Eq. 3 (user)": gc.user_law(eq3_energy, eq3_traction, eq3_tangent, length=DN, name="Eq. 3 (user)"),
        "Morse (user)": gc.user_law(morse_energy, morse_traction, morse_tangent, length=ELL, name="Morse (user)")}
for name, law in laws.items():
    print(f"{name}: peak traction {law.peak_traction:.4g} Pa at Δn = {law.peak_gap * 1e9:.3f} nm, "
          f"contact gap {law.contact_gap * 1e9:.3f} nm")

warnings.filterwarnings("ignore", message="under-resolved")  # the cell is the point, not the resolution
out = args.out / "user_law"
runs = {("built-in", "gfmd"): gc.run(scene, out=out / "builtin-gfmd", method="gfmd", overwrite=True, progress=False)}
for name, law in laws.items():
    for method in ("gfmd", "fe"):
        runs[name, method] = gc.run(scene, out=out / f"{name.split()[0].lower()}-{method}", method=method, law=law,
                                    overwrite=True, progress=False)
e_star = scene.material.contact_modulus
base, same = runs["built-in", "gfmd"].curve, runs["Eq. 3 (user)", "gfmd"].curve
print(f"GFMD, Eq. 3 as a user law vs built-in: max |Δp|/E* = {np.max(np.abs(same['p'] - base['p'])) / e_star:.1e}, "
      f"algorithms {runs['Eq. 3 (user)', 'gfmd'].meta['method']} and {runs['built-in', 'gfmd'].meta['method']}")
print("meta.json says:", runs["Morse (user)", "gfmd"].meta["notes"][-1])

fig, axes = plt.subplots(1, 3, figsize=(13, 3.6), layout="constrained")
gap = np.linspace(-0.5, 8, 400) * DN
for (name, law), c in zip(laws.items(), ("tab:blue", "tab:red")):
    axes[0].plot(gap * 1e9, law.tractions(gap)[0] / law.peak_traction, color=c, label=name)
axes[0].axhline(0, color="0.7", lw=0.8)
axes[0].set(xlabel="Δn (nm)", ylabel="$T_n / T_\\mathrm{peak}$ (> 0 tensile)", ylim=(-2, 1.2))
axes[0].legend()
styles = {"gfmd": "o-", "fe": "s--"}
colors = {"built-in": "k", "Eq. 3 (user)": "tab:blue", "Morse (user)": "tab:red"}
for (name, method), run in runs.items():
    c = run.curve
    axes[1].plot(c["delta"] * 1e9, c["p"] / e_star, styles[method], color=colors[name], ms=3, mfc="none",
                 label=f"{name}, {run.meta['method']}")
axes[1].set(xlabel="δ (nm)", ylabel="$p/E^*$")
axes[1].legend(fontsize=7)
axes[2].semilogy(same["delta"] * 1e9, np.abs(same["p"] - base["p"]) / e_star + 1e-20, "o-", ms=3,
                 label="GFMD: Eq. 3 user − built-in")
fe_user, fe_morse = runs["Eq. 3 (user)", "fe"].curve, runs["Morse (user)", "fe"].curve
axes[2].semilogy(same["delta"] * 1e9, np.abs(same["p"] - fe_user["p"]) / e_star + 1e-20, "s--", ms=3,
                 label="Eq. 3 user: GFMD − FE")
axes[2].semilogy(same["delta"] * 1e9, np.abs(runs["Morse (user)", "gfmd"].curve["p"] - fe_morse["p"]) / e_star + 1e-20,
                 "^:", ms=3, color="tab:red", label="Morse: GFMD − FE")
axes[2].set(xlabel="δ (nm)", ylabel="$|\\Delta p|/E^*$")
axes[2].legend(fontsize=7)
fig.suptitle(f"user-defined laws: sinusoid on a layer D = L, φn* = 0.01, δn = 1 nm, N = {scene.surface.nodes}")
path = args.out / "user_law.png"
fig.savefig(path, dpi=120)
print(f"wrote {path}")
