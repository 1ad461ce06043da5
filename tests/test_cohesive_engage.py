"""When a step of the cohesive NCG engages the two-level preconditioner (`gfmd.cohesive_preconditioner`:
ENGAGE_AFTER, and ENGAGE_EARLY with `slow_step`).

The values are chosen from whole-ramp comparisons at N = 2^17 against engaging after ENGAGE_AFTER only
(`benchmarks/bench_cohesive_engage.py`, its JSON; each a pair of simultaneous processes, run twice with the cores
swapped): on every compared scene, strong and weak adhesion, the default converged at every step, costs no more CPU
time than the reference within the comparison's noise, and leaves the reference's branch at isolated jump-in steps
only.
"""

import json
from pathlib import Path

import pytest

from gfmd import cohesive_preconditioner as cp

DATA = Path(__file__).resolve().parents[1] / "benchmarks" / "results" / "bench_cohesive_engage.json"
SCENES = json.loads(DATA.read_text())
DEFAULT = (cp.ENGAGE_AFTER, cp.ENGAGE_EARLY)


def _default(label):
    return next(v for v in SCENES[label]["values"].values() if (v["engage_after"], v["engage_early"]) == DEFAULT)


def test_the_comparisons_cover_strong_and_weak_adhesion_and_the_default():
    phis = {float(label.split("_phi")[1].split("_")[0]) for label in SCENES}
    assert min(phis) <= 0.01 and max(phis) >= 0.15
    for label in SCENES:
        assert _default(label)["converged"] == _default(label)["steps"] == 201


@pytest.mark.parametrize("label", sorted(SCENES))
def test_default_costs_no_more_than_the_reference(label):
    value = _default(label)
    assert value["cpu_ratio"] <= 1.0 + value["noise"]


@pytest.mark.parametrize("label", sorted(SCENES))
def test_default_rejoins_the_reference_branch(label):
    """A jump-in step may settle on another equilibrium than the reference's (both converged; which one depends on the
    iterates' path), but the ramp does not follow that branch: a step on another branch is never followed by another
    (measured: at most one such step per ramp, ν = 0.45, φn* = 0.15, step 200 of 201)."""
    value = _default(label)
    other = value["other_branch_steps"]
    assert all(step + 1 not in other for step in other)
