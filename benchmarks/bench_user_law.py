"""Time per load step: the built-in seed Eq. 3 law against the same law re-expressed as a user law.

Usage: python benchmarks/bench_user_law.py [--quick] [--repeats R] [--out DIR]

The user law is Eq. 3 written as three numpy callables (V, T_n, dT_n/dΔn from the formula;
`gfmd_contact.core.user_law`). GFMD: the default scene's self-affine surface on a half-plane (φn* = 0.15,
δn = 1 nm, L = 1.28 µm; δn ≥ 2 l up to N = 2^12, coarser beyond: the timing needs no resolution),
a ramp of STEPS load steps into contact, for N = 2^10 … 2^14 (--quick: 2^10, 2^12). The FE: a
sinusoid on a layer D = L (N = 64, 128). The two laws run alternately, `repeats` times each, and
the time per step is the minimum over the repeats of (Σ of the steps' wall_s) / steps: on a shared
machine the minimum is the least disturbed run. Iterations per step are printed to show the two
runs do the same work (the built-in NCG path keeps its near set and fused Eq. 3 kernels; the user
law's generic path evaluates the callables on every node: `gfmd.algorithms.ncg`).

Writes benchmarks/results/bench_user_law.md. The ratio is what to compare; the machine is shared
(2 cores, other jobs), so absolute times are noisy.
"""

from __future__ import annotations

import argparse
import dataclasses
import datetime
import platform
import sys
from pathlib import Path

import numpy as np

# the script runs from anywhere: the repository goes on sys.path before the project imports (E402)
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import gfmd.loading as gl  # noqa: E402
from gfmd_contact.core.scene import default_scene, scene_from_dict  # noqa: E402
from gfmd_contact.core.user_law import user_law  # noqa: E402
from reference.fem.run import run_realization as fe_realization  # noqa: E402

STEPS = 10


def eq3_user_law(scene):
    """Seed Eq. 3 with the scene's φn, δn as a user law."""
    phi, dn = scene.work_normal, scene.interface.length_normal

    def energy(g):
        s = g / dn
        return -phi * (1 + s) * np.exp(-s)

    def traction(g):
        s = g / dn
        return phi / dn * s * np.exp(-s)

    def tangent(g):
        s = g / dn
        return phi / dn**2 * (1 - s) * np.exp(-s)

    return user_law(energy, traction, tangent, dn, name="Eq. 3 as a user law")


def as_user(scene):
    return dataclasses.replace(scene.replace(**{"interface.law": "user"}), user_law=eq3_user_law(scene))


def gfmd_scene(nodes):
    length = 1.28e-6
    return default_scene().replace(**{"surface.nodes": nodes, "surface.realizations": 1,
                                      "surface.rollon_wavelength": max(4 * length / nodes, length / 4096),
                                      "loading.initial_separation": 2e-9, "loading.final_penetration": 10e-9,
                                      "loading.steps": STEPS, "output.field_steps": 1})


def fe_scene(nodes):
    length = 1e-6
    return scene_from_dict({
        "surface": {"kind": "sinusoid", "length": length, "amplitude": 50e-9, "nodes": nodes},
        "material": {"youngs_modulus": 70e9, "poisson_ratio": 0.3, "thickness": length},
        "interface": {"law": "cohesive", "phi_n_star": 0.01, "length_normal": 1e-9},
        "loading": {"initial_separation": 6e-9, "final_penetration": 30e-9, "steps": STEPS},
        "output": {"field_steps": 1}, "method": {"name": "fe"}}, name="fe_bench")


def per_step(run, scene):
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = run(scene, 0)
    steps = len(r.curve["wall_s"])
    return float(np.sum(r.curve["wall_s"])) / steps, float(np.mean(r.curve["iterations"])), bool(
        np.all(r.curve["converged"])), np.asarray(r.curve["p"])


def measure(method, run, scene, repeats):
    user = as_user(scene)
    best = {"built-in": np.inf, "user": np.inf}
    info = {}
    for _ in range(repeats):
        for name, sc in (("built-in", scene), ("user", user)):
            t, its, ok, p = per_step(run, sc)
            best[name] = min(best[name], t)
            info[name] = (its, ok, p)
    dp = float(np.max(np.abs(info["user"][2] - info["built-in"][2])) / max(np.max(np.abs(info["built-in"][2])), 1e-300))
    return (f"| {method} | {scene.surface.nodes} | {best['built-in'] * 1e3:.2f} | {best['user'] * 1e3:.2f} | "
            f"{best['user'] / best['built-in']:.2f} | {info['built-in'][0]:.1f} / {info['user'][0]:.1f} | "
            f"{'yes' if info['built-in'][1] and info['user'][1] else 'NO'} | {dp:.1e} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "results")
    args = ap.parse_args()
    sizes = (2**10, 2**12) if args.quick else (2**10, 2**12, 2**14)
    measure("gfmd", gl.run_realization, gfmd_scene(256), 1)  # warm-up (numba kernels, imports)
    rows = [measure("gfmd", gl.run_realization, gfmd_scene(n), args.repeats) for n in sizes]
    rows += [measure("fe", fe_realization, fe_scene(n), args.repeats) for n in (64, 128)]
    head = ("| method | N | built-in (ms/step) | user law (ms/step) | ratio user/built-in | iterations/step "
            "built-in / user | converged | max |Δp|/max|p| |\n|---|---|---|---|---|---|---|---|")
    text = (f"# Built-in Eq. 3 vs Eq. 3 as a user law ({datetime.date.today()}, {platform.node()}, "
            f"{STEPS} steps, min of {args.repeats} alternating repeats; shared 2-core machine: ratios only)\n\n"
            + head + "\n" + "\n".join(rows) + "\n")
    print(text)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "bench_user_law.md").write_text(text)


if __name__ == "__main__":
    main()
