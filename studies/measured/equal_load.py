"""The periodic cohesive cycles of the measured-map suite rerun to the free cycle's peak load instead of its δ.

The suite (studies/measured/measured_small_q*.toml) loads both boundaries to δ = 12 nm, which loads the free
region less deeply (its long-wavelength compliance). This reruns each periodic cohesive cycle from the same
start to the δ at which its loading branch reaches the free cycle's peak mean pressure (interpolated), with the
same step lengths (0.5 nm loading, ≤ 0.35 nm unloading), and prints the hysteresis W and pull-off of the three
cycles: periodic to 12 nm, periodic to the free peak load, free.

    python studies/measured/equal_load.py results/measured_small --work results/measured_equal_load
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import subprocess
from pathlib import Path

import numpy as np

from gfmd_contact.core.scene import load_scene, scene_to_toml

LOAD_STEP, UNLOAD_STEP = 0.5e-9, 0.35e-9


def _curve(task):
    with open(task / "curve.csv", newline="") as f:
        return list(csv.DictReader(f))


def _cycle(run_dir):
    meta = json.loads((Path(run_dir) / "meta.json").read_text())
    if not meta["all_converged"]:
        raise ValueError(f"{run_dir}: a step did not converge")
    return meta["cycles"][0]["cycles"][0]


def delta_at_load(curve, p_target):
    """δ (m) at which the loading branch first reaches the mean pressure p_target (Pa), linearly interpolated."""
    rows = [r for r in curve if r["branch"] == "loading"]
    d = np.array([float(r["delta"]) for r in rows])
    p = np.array([float(r["p"]) for r in rows])
    k = int(np.argmax(p >= p_target))
    if p[k] < p_target or k == 0:
        raise ValueError(f"the loading branch does not cross p = {p_target:.3g} Pa")
    return float(np.interp(p_target, p[k - 1:k + 1], d[k - 1:k + 1]))


def rerun(periodic_task, free_task, work):
    """(periodic to 12 nm, periodic to the free peak load, free) cycle dicts and that δ (m)."""
    p_free = max(float(r["p"]) for r in _curve(free_task))
    delta = delta_at_load(_curve(periodic_task), p_free)
    scene = load_scene(periodic_task / "scene.toml")
    start = scene.loading.path[0]
    steps = [round((delta - start) / LOAD_STEP), math.ceil((delta - start) / UNLOAD_STEP)]
    scene = scene.replace(**{"loading.path": [start, delta, start], "loading.steps": steps, "output.field_steps": 1})
    work.mkdir(parents=True, exist_ok=True)
    toml = work / "scene.toml"
    toml.write_text(scene_to_toml(scene))
    subprocess.run(["gfmd", "run", str(toml), "--out", str(work / "run")], check=True, capture_output=True)
    return _cycle(periodic_task), _cycle(work / "run"), _cycle(free_task), delta


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("root", help="the suite's directory (gfmd study run … --out DIR)")
    ap.add_argument("--work", required=True, help="directory for the reruns")
    args = ap.parse_args(argv)
    print("quadrant,phi_n_star,delta_equal_load_m,W_periodic_J_m2,W_periodic_equal_load_J_m2,W_free_J_m2,"
          "pull_off_periodic_equal_load_Pa,pull_off_free_Pa")
    for study in sorted(Path(args.root).glob("measured_small_q*")):
        record = json.loads((study / "study.json").read_text())
        tasks = {(t["parameters"]["surface.boundary"], t["parameters"]["interface.law"],
                  float(t["parameters"]["interface.phi_n_star"])): study / "tasks" / t["key"] for t in record["tasks"]}
        for phi in sorted(k[2] for k in tasks if k[:2] == ("periodic", "cohesive")):
            q = study.name.removeprefix("measured_small_")
            per, eq, free, delta = rerun(tasks[("periodic", "cohesive", phi)], tasks[("free", "cohesive", phi)],
                                         Path(args.work) / f"{q}_phi{phi:g}")
            print(f"{q},{phi:g},{delta:.6g},{per['hysteresis']:.6g},{eq['hysteresis']:.6g},{free['hysteresis']:.6g},"
                  f"{eq['pull_off_pressure']:.6g},{free['pull_off_pressure']:.6g}", flush=True)


if __name__ == "__main__":
    main()
