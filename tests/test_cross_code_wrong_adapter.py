"""A deliberately wrong adapter fails the cross-code cases it should, and the right one passes them: the cases
measure the code, not the adapter's good intentions. Two plantings in subclasses of our GFMD adapter: E
passed where E* belongs (the body ≈ 10 % too stiff at ν = 0.3), and the gap's sign flipped (the indenter's
profile upside down)."""

from __future__ import annotations

import numpy as np
import pytest

from verification.cross_code import cases, outcomes
from verification.solvers.gfmd import POISSON, GFMDSolver, scene_of

FAST = (cases.WESTERGAARD, cases.HERTZ, cases.SPHERE, cases.FREE_SPHERE)


class YoungsForContactModulus(GFMDSolver):
    """E* taken as E: the scene's E is set to E*, so its contact modulus is E*/(1 − ν²)."""
    name = "gfmd-wrong-modulus"

    def scene(self, problem):
        return scene_of(problem).replace(**{"material.youngs_modulus": problem.contact_modulus})


class FlippedGap(GFMDSolver):
    """The gap's sign flipped: g = indenter − body read as body − indenter, i.e. the profile upside down."""
    name = "gfmd-flipped-gap"

    def heights(self, problem):
        return -np.asarray(problem.heights, float)


def _passed(solver, case):
    return [r["passed"] for r in outcomes.run_case(solver, case)]


@pytest.mark.parametrize("case", FAST, ids=[c.name for c in FAST])
def test_right_adapter_passes(case):
    assert all(_passed(GFMDSolver(), case)), case.name


@pytest.mark.parametrize("wrong", [YoungsForContactModulus, FlippedGap], ids=["E-for-E*", "gap-sign"])
@pytest.mark.parametrize("case", FAST, ids=[c.name for c in FAST])
def test_wrong_adapter_fails(case, wrong):
    assert POISSON > 0  # else E = E* and the first planting is no bug
    verdicts = _passed(wrong(), case)
    assert not all(verdicts), f"{wrong.name} passed {case.name}: {verdicts}"
