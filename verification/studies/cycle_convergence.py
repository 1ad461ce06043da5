"""GFMD load–unload cycle: hysteresis and pull-off convergence with N at fixed physics, and stability at
the extremes of the cycle.

Convergence (`convergence`): `verification.scenes.cycle_self_affine(N)` — the extremes base profile
(L = 256 nm, H = 0.8, h_rms = 4 nm, λr = 64 nm, λs,H = 4 nm, seed 1; half-plane, ν = 0.45), made sticky:
φn* = 0.15 with δn = 0.25 nm — along the closed path δ = −8 → 4 → −8 nm in 48 + 240 steps (Δδ = 0.25 nm loading, 0.05 nm = δn/5
unloading),
on N = 2^10 … 2^15 (δn/l = 1 … 32; N = 2^10 is under-resolved and warned). The profile's spectrum is
fixed by its physical cut-offs, so only the discretization changes with N. Per N: W = ∮ p̄ dδ, the
pull-off pressure (most tensile p̄ on unloading) and the snap-off δ (`gfmd_contact.core.cycle`); the differences
of neighbouring N, |W(N) − W(2N)|/W(2N) and |F(N) − F(2N)|/|F(2N)|, and their observed orders
log2(d(N/2, N)/d(N, 2N)).

Extremes of the cycle (`extreme`), each one run; the outcome recorded (every step converged, NaN,
W, pull-off, snap-off, events, a_rel at the deepest step and at the end):
* "sticky": the convergence scene at N = 2048 (φn* = 0.15, δn = 0.25 nm = 2 l);
* "near full contact": a cohesive sinusoid (a = 50 nm, λ = 1 µm, φn* = 0.15, δn = 1 nm) on a
  half-plane, N = 256, along δ = −2 nm → 0.99 δ_max → −10 nm in 60 + 120 steps, δ_max = ⟨h⟩ − min h = a
  (full contact, `gfmd_contact.core.loading.realization_steps`); slow variant: 0.998 δ_max (the ramp's own
  limit, FULL_CONTACT_MARGIN) on N = 1024;
* "pull-off, fine steps": the sticky scene unloaded in 960 steps (Δδ = 0.0125 nm = δn/20) through the
  pull-off region; snap-off δ and pull-off against the convergence scene's δn/5 unloading;
* "pull-off, coarse steps": unloaded in 24 steps (Δδ = 0.5 nm = 2 δn): the first unloading step leaves
  the attached branch (documented outcome: the loop collapses, W ≈ 0, pull-off underestimated) —
  why the convergence scene unloads in δn/5 steps.

    python -m verification.studies.cycle_convergence [--full] [--write]

`--write` stores them in verification/data/cycle_convergence.json (entries "convergence", "extreme/…"),
which verification/test_cycle_convergence.py reads (it re-runs the CI pair N = CI_PAIR and the CI cases).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gfmd_contact.core import cycle as cyc
from gfmd_contact.core.loading import step_branches
from verification import measured
from verification.scenes import CYCLE_PATH, CYCLE_STEPS, cohesive_sinusoid, cycle_self_affine

NAME = "cycle_convergence"
NODES = tuple(2**k for k in range(10, 16))
CI_PAIR = (2048, 4096)
AMPLITUDE = 50e-9  # of the near-full-contact sinusoid (its δ_max on a half-plane)


def observables(result, scene):
    """The cycle row of `gfmd_contact.core.cycle` plus stability facts of one run."""
    d, p, a = (np.asarray(result.curve[c], float) for c in ("delta", "p", "a_rel"))
    branch, cycle = step_branches(scene.loading)
    (row,) = cyc.cycle_observables(d, p, a, branch, cycle)
    unload = np.asarray(branch[:d.size]) == "unloading"
    return {"converged": bool(result.all_converged), "steps": int(d.size), "steps_planned": int(len(branch)),
            "nan": bool(np.any(~np.isfinite(p)) or np.any(~np.isfinite(a)) or np.any(~np.isfinite(d))),
            "hysteresis": row["hysteresis"], "pull_off_pressure": row["pull_off_pressure"],
            "pull_off_delta": row["pull_off_delta"], "snap_off_delta": row["snap_off_delta"],
            "events": [(e["kind"], e["step"], e["branch"]) for e in row["events"]],
            "delta_max": float(np.max(d)), "a_rel_max": float(np.max(a)), "p_max": float(np.max(p)),
            "a_rel_end": float(a[-1]), "a_rel_min_unloading": float(np.min(a[unload])) if unload.any() else None,
            "messages": [m for m in result.messages if m][:3]}


def run(scene):
    from gfmd_contact.app.methods import run_realization
    t0 = time.perf_counter()
    r = run_realization(scene)
    out = observables(r, scene)
    out["wall_s"] = time.perf_counter() - t0
    return out


_RUNS = {}


def at(n):
    """The convergence scene's observables at N = n (cached per process)."""
    if n not in _RUNS:
        _RUNS[n] = run(cycle_self_affine(n))
    return _RUNS[n]


def order(e_coarse, e_fine, ratio=2.0):
    return float(np.log(e_coarse / e_fine) / np.log(ratio)) if e_coarse > 0 and e_fine > 0 else float("nan")


def differences(a, b):
    """Relative differences of W and pull-off between two runs (b the finer)."""
    return {"hysteresis": abs(a["hysteresis"] - b["hysteresis"]) / abs(b["hysteresis"]),
            "pull-off": abs(a["pull_off_pressure"] - b["pull_off_pressure"]) / abs(b["pull_off_pressure"])}


def convergence(nodes=NODES):
    t0 = time.perf_counter()
    runs = [at(n) for n in nodes]
    diffs = [differences(a, b) for a, b in zip(runs, runs[1:])]
    errors = {m: [d[m] for d in diffs] for m in ("hysteresis", "pull-off")}
    orders = {m: [order(x, y) for x, y in zip(e, e[1:])] for m, e in errors.items()}
    return {"N": list(nodes), "W": [r["hysteresis"] for r in runs], "pull_off": [r["pull_off_pressure"] for r in runs],
            "snap_off_delta": [r["snap_off_delta"] for r in runs], "converged": [r["converged"] for r in runs],
            "errors": errors, "orders": orders, "wall_s": time.perf_counter() - t0,
            "run_s": [r["wall_s"] for r in runs]}


# ----------------------------------------------------------------------------- extremes of the cycle
def _full_contact(fraction, n):
    return cohesive_sinusoid(n).replace(**{"material.thickness": "inf", "interface.phi_n_star": 0.15,
                                           "loading.path": [-2e-9, fraction * AMPLITUDE, -10e-9],
                                           "loading.steps": [60, 120], "output.field_steps": 0})


FINE_UNLOADING_STEPS = 960
COARSE_UNLOADING_STEPS = 24
#: label -> (scene factory, slow)
EXTREMES = {
    "sticky": (lambda: cycle_self_affine(2048), False),
    "sticky, N = 2^15": (lambda: cycle_self_affine(2**15), True),
    "near full contact": (lambda: _full_contact(0.99, 256), False),
    "near full contact, 0.998 δ_max": (lambda: _full_contact(0.998, 1024), True),
    "pull-off, fine steps": (lambda: cycle_self_affine(2048, steps=(48, FINE_UNLOADING_STEPS)), False),
    "pull-off, coarse steps": (lambda: cycle_self_affine(2048, steps=(48, COARSE_UNLOADING_STEPS)), False),
}
_EXTREME = {}


def extreme(label):
    if label not in _EXTREME:
        _EXTREME[label] = run(EXTREMES[label][0]())
    return _EXTREME[label]


def coarse_unloading_step():
    return abs(CYCLE_PATH[2] - CYCLE_PATH[1]) / CYCLE_STEPS[1]


def stored(key):
    return measured.entry(NAME, key)["values"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="the slow extreme cases too")
    ap.add_argument("--write", action="store_true", help="store in verification/data/cycle_convergence.json")
    args = ap.parse_args(argv)
    st = convergence()
    print(f"N {st['N']}\nW {st['W']}\npull-off {st['pull_off']}\nsnap-off δ {st['snap_off_delta']}")
    for m in st["errors"]:
        print(f"{m}: |Δ|/ref {[f'{e:.3g}' for e in st['errors'][m]]} orders {[f'{o:.2f}' for o in st['orders'][m]]}")
    print(f"run s {[f'{w:.1f}' for w in st['run_s']]}, total {st['wall_s']:.1f} s")
    entries = {"convergence": measured.make_entry(
        {k: st[k] for k in ("N", "W", "pull_off", "snap_off_delta", "converged", "errors", "orders")},
        scene="verification.scenes.cycle_self_affine(N)", ci_pair=list(CI_PAIR), wall_s=st["wall_s"])}
    for label, (make, slow) in EXTREMES.items():
        if slow and not args.full:
            continue
        out = extreme(label)
        print(f"{label}: {out}")
        entries[f"extreme/{label}"] = measured.make_entry(out, scene=make())
    if args.write:
        print(measured.write(NAME, entries, description="GFMD load–unload cycle: W and pull-off vs N at fixed "
                                                        "physics (observed orders); stability at the cycle's extremes"))


if __name__ == "__main__":
    main()
