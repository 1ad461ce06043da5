"""How small a cohesive length δn GFMD still relaxes: δn/l (l = L/N) and the load step ΔU/δn.

Behind the refusal in `gfmd_contact.core.loading.check_step_in_law_range` (a cohesive ramp whose load step
ΔU exceeds the law's range 600 δn) and the finding that δn/l itself sets no solvability limit above
1e-4 (below `MIN_LENGTH_NORMAL_NODES` = 2 δn is a warning about accuracy, `gfmd_contact.core.model`). Cells: two profiles (the example
scene's self-affine one at N = 1024, L = 10.24 µm, λs = 40 nm; a sinusoid of 5 nm amplitude),
φn* = 0.01, 0.15, E = 70 GPa, ν = 0.45, half-plane, δ0 = 12 nm, final δ = 17 nm, the default
solver (FIRE/NCG, 1e-8, 200,000 iterations), `loading.steps` such that ΔU = 0.145 nm (the example's
200 steps) and 40 steps; δn/l = 1e-4 … 1e-2. A cell's ramp stops at its first non-converged step;
its values: δn/l, ΔU/δn, steps run, steps converged, all converged (1/0: every step the realization runs,
up to its own full-contact limit on a half-plane, converged). `gfmd_contact.core.loading` refuses
ΔU > 600 δn (the law's range); the cells below it are the measurement that a scene it accepts runs.

    python -m verification.studies.length_normal_limit [--write] [--kind K …] [--phi F …] [--steps S …] [--ratio R …]

(the stored data: the default grid, and --steps 5 at φn* = 0.15, self-affine: ΔU/δn = 580 at δn/l = 1e-3,
1,930 at 3e-4, the two sides of the law's range)
"""

from __future__ import annotations

import argparse
import dataclasses
import time

NAME = "length_normal_limit"
RATIOS = (1e-4, 3e-4, 1e-3, 3e-3, 1e-2)
PHI = (0.01, 0.15)
STEPS = (40, 200)
BASE = {
    "surface": {"kind": "self-affine", "length": 10.24e-6, "nodes": 1024, "hurst": 0.8, "h_rms": 10e-9,
                "rolloff_wavelength": 1.28e-6, "rollon_wavelength": 40e-9, "seed": 1, "realizations": 1},
    "material": {"youngs_modulus": 70e9, "poisson_ratio": 0.45, "thickness": "inf"},
    "interface": {"law": "cohesive", "phi_n_star": 0.15, "length_normal": 1e-9},
    "loading": {"initial_separation": 12e-9, "final_penetration": 17e-9, "steps": 200},
    "output": {"field_steps": 0, "workers": 1},
}
SINUSOID = {"kind": "sinusoid", "length": 10.24e-6, "nodes": 1024, "amplitude": 5e-9}


class _Stop(Exception):
    pass


def cell_scene(kind, phi, ratio, steps):
    import copy

    from gfmd_contact.core.scene import scene_from_dict

    d = copy.deepcopy(BASE)
    if kind == "sinusoid":
        d["surface"] = dict(SINUSOID)
    spacing = d["surface"]["length"] / d["surface"]["nodes"]
    d["interface"].update(phi_n_star=phi, length_normal=ratio * spacing)
    scene = scene_from_dict(d, name=f"{kind}-phi{phi:g}-r{ratio:g}-s{steps}")  # 200 steps: in range
    # the cell's own step count, past the scene check when ΔU > 600 δn: the measurement behind that refusal
    return dataclasses.replace(scene, loading=dataclasses.replace(scene.loading, steps=steps))


def run_cell(scene):
    """(steps run, steps converged): the ramp stops at its first non-converged step."""
    from gfmd.loading import run_realization

    seen = {}

    def checkpoint(result, state):
        c = list(result.curve["converged"])
        seen["run"], seen["ok"] = len(c), int(sum(c))
        if not c[-1]:
            raise _Stop

    try:
        run_realization(scene, 0, checkpoint=checkpoint)
    except _Stop:
        pass
    return seen["run"], seen["ok"]


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--kind", nargs="*", default=["self-affine", "sinusoid"])
    ap.add_argument("--phi", type=float, nargs="*", default=list(PHI))
    ap.add_argument("--steps", type=int, nargs="*", default=list(STEPS))
    ap.add_argument("--ratio", type=float, nargs="*", default=list(RATIOS))
    args = ap.parse_args(argv)
    from verification import measured

    for kind in args.kind:
        for phi in args.phi:
            for steps in args.steps:
                for ratio in args.ratio:
                    scene = cell_scene(kind, phi, ratio, steps)
                    t = time.perf_counter()
                    run, ok = run_cell(scene)
                    print(f"{scene.name}: {ok}/{run} steps converged ({time.perf_counter() - t:.0f} s)", flush=True)
                    step = (scene.loading.initial_separation + scene.loading.final_penetration) / steps
                    entry = measured.make_entry(
                        {"delta_n_over_l": ratio, "phi_n_star": phi, "step_over_delta_n": step / scene.interface.length_normal,
                         "steps_run": run, "steps_converged": ok, "all_converged": int(ok == run)},
                        scene=scene)
                    if args.write:  # each cell as it is measured
                        measured.write(NAME, {f"cell/{scene.name}": entry}, __doc__.split("\n")[0])


if __name__ == "__main__":
    main()
