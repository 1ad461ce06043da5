"""When a step of the cohesive NCG engages the two-level preconditioner (`gfmd.cohesive_preconditioner`:
ENGAGE_AFTER, and ENGAGE_EARLY with `slow_step`).

The values were chosen from whole-ramp comparisons at N = 2^17 against engaging after ENGAGE_AFTER only, strong and
weak adhesion (docs/design/performance.md): the default converged at every step, cost no more CPU time within the
comparison's noise, and left the reference's branch at isolated jump-in steps only. Here, on the strong-adhesion ramp
of Fig. 3's small scene (N = 4096): the early engagement acts, every step converges with it, and a step it leaves on
another branch is never followed by another.
"""

import numpy as np
import pytest

from gfmd import cohesive_preconditioner as cp
from gfmd.loading import run_realization
from gfmd_contact.core.scene import load_scene
from tests.test_fire_dt_cap import ROOT, SAME_BRANCH


@pytest.fixture(scope="module")
def curves():
    """The ramp with the default engagement and with engagement after ENGAGE_AFTER iterations only."""
    scene = load_scene(ROOT / "studies" / "seed" / "fig3_small_base.toml").replace(**{
        "surface.realizations": 1})
    out = {"default": run_realization(scene, 0).curve}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cp, "ENGAGE_EARLY", cp.ENGAGE_AFTER)
        out["late"] = run_realization(scene, 0).curve
    return out


def test_early_engagement_acts_and_converges(curves):
    assert all(curves["default"]["converged"]) and all(curves["late"]["converged"])
    assert not np.array_equal(curves["default"]["iterations"], curves["late"]["iterations"])


def test_default_rejoins_the_reference_branch(curves):
    """A jump-in step may settle on another equilibrium than the reference's (both converged; which one depends on the
    iterates' path), but the ramp does not follow that branch."""
    p, p_ref = (np.asarray(curves[k]["p"], float) for k in ("default", "late"))
    other = np.flatnonzero(np.abs(p - p_ref) > SAME_BRANCH * np.max(np.abs(p_ref)))
    assert not np.any(np.diff(other) == 1), other
