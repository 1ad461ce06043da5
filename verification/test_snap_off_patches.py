"""Snap-off of a rough surface that detaches patch by patch: the cycle's snap-off against the saved fields.

Scene: `verification.scenes.cohesive_self_affine` (H = 0.8, h_rms = 5 nm, L = 1 µm, N = 256, bonded layer D = L)
made sticky (φn* = 0.15, δn = 1 nm) and driven along [−5, 10, −10] nm in 15 + 200 steps (Δδ = 0.1 nm unloading),
fields at every step. On unloading its contact patches let go one after another (several partial jump-outs)
before the last one does; `gfmd_contact.core.cycle` takes the snap-off from the jumps of p̄(δ).

Second route, from the saved fields only (this module's own numpy): a node is attached while its gap lies before
the law's peak, Δn < δn (seed Eq. 3's traction peaks at δn; a node that jumps off lands several δn beyond it).
The body has snapped off at the last unloading step at which the attached set becomes empty; the earlier steps
at which a patch (a periodic run of attached nodes) is lost while others hold are the partial detachments.
Asserted (counts, exact): the recorded snap-off step is that step, the recorded snap-off δ is δ of the step
before it, and the path has at least two partial detachments before it (else the scene would not test the
selection). Taking the first partial jump-out for the snap-off (verification/mutations.py "snap-off-first-jump")
fails by ~80 steps.
"""

from __future__ import annotations

import numpy as np

from gfmd_contact.app.cycles import realization_cycles
from verification.plots import curve_plot
from verification.runs import run_gfmd
from verification.scenes import cohesive_self_affine

CASE = "cycle/snap-off-rough-patches"
METHODS = ("gfmd-fire",)
NODES, LOADING, UNLOADING = 256, 15, 200


def scene():
    return cohesive_self_affine(NODES, 0.8).replace(**{
        "interface.phi_n_star": 0.15, "loading.path": [-5e-9, 10e-9, -10e-9], "loading.steps": [LOADING, UNLOADING],
        "output.field_steps": LOADING + UNLOADING})


def _patches(attached):
    """Number of periodic runs of attached nodes."""
    if attached.all():
        return 1
    a = attached.astype(int)
    return int(np.sum(a - np.roll(a, 1) == 1))


def detachments(result, delta_n):
    """(final snap-off step or None, [steps losing a patch while others hold]) on the unloading steps."""
    steps = range(LOADING + 1, LOADING + UNLOADING + 1)
    counts = {k: _patches(np.asarray(result.fields[k]["gap"]) < delta_n) for k in [LOADING, *steps]}
    final = [k for k in steps if counts[k] == 0 and counts[k - 1] > 0]
    partial = [k for k in steps if 0 < counts[k] < counts[k - 1]]
    last = final[-1] if final else None
    return last, [k for k in partial if last is None or k < last]


def test_snap_off_is_the_last_patch_letting_go(verification_record):
    s = scene()
    result, wall = run_gfmd(s)
    curve = {k: np.asarray(result.curve[k], float) for k in ("delta", "p", "a_rel")}
    (cycle,), _ = realization_cycles(s, curve)
    final, partial = detachments(result, s.interface.length_normal)
    recorded = cycle["snap_off_step"]
    checks = {"|recorded snap-off step − last patch lost (fields)|":
              (abs(recorded - final) if None not in (recorded, final) else np.inf, 0),
              "recorded snap-off δ ≠ δ of the step before it (count)":
              (int(final is None or cycle["snap_off_delta"] != curve["delta"][final - 1]), 0),
              "partial detachments before the snap-off short of 2 (count)": (max(0, 2 - len(partial)), 0)}
    plot = curve_plot(list(curve["delta"]), {"p̄": list(curve["p"])}, xlabel="δ (m)", ylabel="p̄ (Pa)",
                      title=f"rough layer, unloading: patches lost at steps {partial}, last at {final}")
    failed = []
    for i, (metric, (value, tol)) in enumerate(checks.items()):
        verification_record(
            case=CASE, metric=metric, value=float(value), tolerance=tol, methods=METHODS, wall_s=wall, scene=s,
            tolerance_source="a count: exact", resolution={"N": NODES, "steps": LOADING + UNLOADING},
            plots=[plot] if i == 0 else [],
            notes=(f"recorded: step {recorded} ({cycle['snap_off_rule']}), δ {cycle['snap_off_delta']}; fields: "
                   f"partial detachments at {partial}, final at {final}; jump-outs "
                   f"{[e['step'] for e in cycle['events'] if e['kind'] == 'jump-out']}"))
        if value > tol:
            failed.append((metric, value))
    assert not failed, failed
