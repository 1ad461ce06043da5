"""Observables of a load–unload cycle under displacement control, from one realization's curve.

Units: SI (see `gfmd_contact.core.conventions`): δ in m, p̄ in Pa (> 0 compressive, < 0 tensile), energies per
unit nominal area in J/m². The branch and cycle of a step come from `gfmd_contact.core.loading.step_branches`.

Per cycle c (the steps of cycle c, preceded by the last step of cycle c − 1, which is where it starts):

pull_off_pressure  the most tensile mean pressure on the cycle's unloading steps, min p̄ (Pa, < 0 when
                   tensile; None without unloading steps); pull_off_delta its δ (m)
snap_off_delta     δ (m) of the last step on the attached branch before the cycle's last jump-out on
                   unloading (the instability lies within one step after it); without a jump-out, the
                   δ of the first unloading step with a_rel = 0 after one with a_rel > 0; where
                   neither exists (a cohesive law's traction-tolerance rule counts nodes up to
                   Δtol ≈ 9.1 δn as in contact, so a_rel need not reach 0 within the path), the δ
                   of the last unloading step after the pull-off still carrying |p̄| ≥
                   SNAP_OFF_SHARE·|pull-off| (the load released: the next step carries less); None if
                   none applies. snap_off_step the step of the jump, of a_rel = 0 or of the release;
                   snap_off_rule which ("jump-out", "contact lost", "load released")
hysteresis         W = ∮ p̄ dδ (J/m²), trapezoid rule over the cycle's steps in order. With p̄ > 0
                   compressive and δ growing into the surface, W > 0 is the work per unit area the
                   indenter puts in over the cycle and does not get back (dissipated by the jumps);
                   closed: whether the cycle ends at the δ it started from (only then is W a loop
                   integral; otherwise W is the integral along the open path)
events             the jumps of a_rel (`jump_events`)

A jump (`jump_events`) is a step k whose mean-pressure change |p̄_k − p̄_(k−1)| is ≥ JUMP_SHARE of the
realization's range max p̄ − min p̄ and ≥ JUMP_RATIO times the change of each neighbouring step on the
same branch: a discontinuity of p̄(δ), not a fast smooth change (p̄, not a_rel, because a cohesive law's
contact rule counts nodes in its attractive tail, so a_rel changes smoothly well before and after the
jump). It is a "jump-in" where a_rel grows (on loading where a_rel does not change) and a "jump-out"
where it falls (on unloading where it does not change). A displacement step never hangs on it: the
equilibrium after the jump is what the solver converges to from the previous state, so the jump shows
as one large change between adjacent steps; its δ is known to within one step.
"""

from __future__ import annotations

import numpy as np

#: smallest |Δp̄| between adjacent steps that counts as a jump, as a share of the range of p̄
JUMP_SHARE = 0.02
#: a jump's |Δp̄| must exceed that of both neighbouring steps (same branch) by this factor
JUMP_RATIO = 3.0
#: snap-off by release (no jump-out, a_rel > 0 throughout): |p̄| falls below this share of |pull-off|.
#: 1 %: far above the solver's residual and the contact rule's tolerance (1e-3 of the peak traction),
#: far below any load an attached neck carries; beyond the neck p̄ decays like the law's tail,
#: exp(−Δ/δn), so a factor 10 in this share moves the snap-off δ by about ln 10·δn ≈ 2.3 δn.
SNAP_OFF_SHARE = 0.01
#: units of the per-cycle quantities (meta.json "cycle_units")
UNITS = {"pull_off_pressure": "Pa (min p̄ on unloading; < 0 tensile)", "pull_off_delta": "m",
         "snap_off_delta": "m", "snap_off_step": "step index",
         "snap_off_rule": "jump-out | contact lost | load released", "hysteresis": "J/m^2 (∮ p̄ dδ, > 0 dissipated)",
         "closed": "bool", "pull_off_load": "Pa (force control: the load at which contact was lost)", "delta_start": "m", "delta_end": "m",
         "events": "list: kind, step, branch, delta_before/after (m), p_before/after (Pa), a_rel_before/after"}


def jump_events(delta, p, a_rel, branch, cycle):
    """The jumps of a_rel along one realization's curve (module docstring): a list of dicts with kind
    ("jump-in": a_rel grows, "jump-out": it falls), step, branch, cycle and the δ (m), p̄ (Pa) and
    a_rel before and after."""
    a, p = np.asarray(a_rel, float), np.asarray(p, float)
    if p.size < 2:
        return []
    change = np.abs(np.diff(p))
    floor = JUMP_SHARE * (np.max(p) - np.min(p))
    events = []
    for k in range(1, p.size):
        d = change[k - 1]
        neighbours = [change[j - 1] for j in (k - 1, k + 1) if 1 <= j < p.size and branch[j] == branch[k]]
        if not (d > 0 and d >= floor and all(d >= JUMP_RATIO * n for n in neighbours)):
            continue
        grows = a[k] > a[k - 1] if a[k] != a[k - 1] else branch[k] == "loading"
        events.append({"kind": "jump-in" if grows else "jump-out", "step": int(k), "branch": str(branch[k]),
                       "cycle": int(cycle[k]), "delta_before": float(delta[k - 1]), "delta_after": float(delta[k]),
                       "p_before": float(p[k - 1]), "p_after": float(p[k]),
                       "a_rel_before": float(a[k - 1]), "a_rel_after": float(a[k])})
    return events


def hysteresis(delta, p):
    """∮ p̄ dδ (J/m²) by the trapezoid rule along the steps in order (δ in m, p̄ in Pa)."""
    delta, p = np.asarray(delta, float), np.asarray(p, float)
    return float(np.sum(0.5 * (p[1:] + p[:-1]) * np.diff(delta)))


def cycle_observables(delta, p, a_rel, branch, cycle, events=None):
    """Per cycle, the dict of the module docstring (list ordered by cycle), from one realization's
    curve: δ (m), p̄ (Pa), a_rel and the steps' branch and cycle (`gfmd_contact.core.loading.step_branches`,
    cut to the steps run). events: the run's own instability events (force control, `gfmd_contact.core.force`,
    with branch and cycle added) instead of those `jump_events` finds in p̄(δ); a cycle whose jump-out
    detached the body (force control: the load could not be carried) also gets `pull_off_load`, that
    load (Pa), while pull_off_pressure is the most tensile p̄ still carried."""
    delta, p, a = (np.asarray(v, float) for v in (delta, p, a_rel))
    branch, cycle = np.asarray(branch, object)[:delta.size], np.asarray(cycle, int)[:delta.size]
    if events is None:
        events = jump_events(delta, p, a, branch, cycle)
    out = []
    for c in np.unique(cycle):
        idx = np.flatnonzero(cycle == c)
        path = np.concatenate([[idx[0] - 1], idx]) if idx[0] > 0 else idx
        unload = idx[branch[idx] == "unloading"]
        row = {"cycle": int(c), "delta_start": float(delta[path[0]]), "delta_end": float(delta[path[-1]]),
               "pull_off_pressure": None, "pull_off_delta": None, "snap_off_delta": None, "snap_off_step": None,
               "snap_off_rule": None}
        if unload.size:
            j = unload[np.argmin(p[unload])]
            row["pull_off_pressure"], row["pull_off_delta"] = float(p[j]), float(delta[j])
            outs = [e for e in events if e["cycle"] == c and e["kind"] == "jump-out" and e["branch"] == "unloading"]
            lost = [k for k in unload if a[k] == 0 and k > 0 and a[k - 1] > 0]
            released = [k for k in unload if k > j and p[j] < 0 and abs(p[k]) < SNAP_OFF_SHARE * abs(p[j])]
            if outs:
                row["snap_off_delta"], row["snap_off_step"] = outs[-1]["delta_before"], outs[-1]["step"]
                row["snap_off_rule"] = "jump-out"
                if outs[-1].get("detached"):
                    row["pull_off_load"] = outs[-1]["load"]
            elif lost:
                row["snap_off_delta"], row["snap_off_step"] = float(delta[lost[0]]), int(lost[0])
                row["snap_off_rule"] = "contact lost"
            elif released:
                row["snap_off_delta"], row["snap_off_step"] = float(delta[released[0] - 1]), int(released[0])
                row["snap_off_rule"] = "load released"
        row["hysteresis"] = hysteresis(delta[path], p[path])
        row["closed"] = bool(np.isclose(delta[path[-1]], delta[path[0]], rtol=0, atol=1e-9 * max(np.ptp(delta), 1e-300)))
        row["events"] = [e for e in events if e["cycle"] == c]
        out.append(row)
    return out


def step_events(n, events):
    """Per step (n steps) the event kind recorded there ("" where none): the curve.csv column `event`."""
    column = [""] * n
    for e in events:
        if e["step"] < n:
            column[e["step"]] = e["kind"]
    return column
