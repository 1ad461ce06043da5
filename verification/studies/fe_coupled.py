"""GFMD (finite bonded layer) vs the FE cell on the adhesive sinusoid, coupled CZ law: differences vs N and ν.

Scene: `verification.scenes.coupled_sinusoid` (a = 50 nm, L = D = 1 µm, φn* = 0.01, δn = δt = 1 nm,
δ0 = 2 nm, coupled law of seed Eq. 2 with c = φt*/φn* = 0.5), ν ∈ {0.1, 0.3, 0.45, 0.49}, δ from −2 nm
to 18 nm in 10 steps (a_rel ≈ 0.17–0.30). GFMD: FIRE (tolerance 1e-8; u_x and u_z solved); FE:
`reference.fem` P2 (Newton, tolerance 1e-10). Same nodes, same z_ind.

Differences (GFMD the reference; max over the recorded field steps 2, 4, …, 10, resp. over all steps):
t_n(x), t_t(x) relative L2 (and max |Δt| / (φn/δn)); p(δ): max_k |Δp| / max_k |p|; a_rel: max_k |Δa_rel|;
max|t_t|/max|t_n| at the last step; FE and GFMD wall time per load step (informational).

    python -m verification.studies.fe_coupled [--full] [--write]

N = 64, 128 (`--full`: … 512) at every ν; `--write` stores the differences and the observed orders
between neighbouring N in verification/data/fe_coupled.json (entry "ci" or "full"), which
test_fe_coupled.py reads.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from verification import measured
from verification.metrics import field_difference
from verification.runs import fe_vs_gfmd
from verification.scenes import coupled_sinusoid

NAME = "fe_coupled"
RATIOS = (0.1, 0.3, 0.45, 0.49)
NODES = {"ci": (64, 128), "full": (64, 128, 256, 512)}
METRICS = ("tn", "tt", "p", "a", "tn_max", "tt_max", "tt_over_tn")
_CACHE = {}


def _field_differences(rf, rg, name, scale):
    """(max over field steps of the relative L2 difference, of max |diff| / scale) of field `name`."""
    peak = max(np.max(np.abs(rf.fields[k][name] - rg.fields[k][name])) for k in rf.fields) / scale
    return field_difference(rf, rg, name), float(peak)


def compare(n, nu):
    """Run FE P2 and GFMD on coupled_sinusoid(n, nu); differences (dimensionless) and times (s), cached."""
    if (n, nu) in _CACHE:
        return _CACHE[(n, nu)]
    sc = coupled_sinusoid(n, nu)
    out = fe_vs_gfmd(sc, check=False)
    rf, rg = out["rf"], out["rg"]
    assert rf.all_converged, f"FE N={n} ν={nu}: {rf.messages}"
    assert rg.all_converged, f"GFMD N={n} ν={nu}: {rg.messages}"
    for r in (rf, rg):  # the verified range stays below gfmd_contact.core.loading.SLIP_LIMIT
        assert not any("slip regime" in w for w in r.reasons), (r.method, r.reasons)
    traction_scale = sc.work_normal / sc.interface.length_normal  # φn/δn (Pa)
    tn, tn_max = _field_differences(rf, rg, "t_n", traction_scale)
    tt, tt_max = _field_differences(rf, rg, "t_t", traction_scale)
    last = max(rg.fields)
    tt_over_tn = float(np.max(np.abs(rg.fields[last]["t_t"])) / np.max(np.abs(rg.fields[last]["t_n"])))
    out.update(tn_max=tn_max, tt=tt, tt_max=tt_max, tt_over_tn=tt_over_tn,
               gfmd_iterations=int(np.max(rg.curve["iterations"])),
               fe_fallbacks=len(rf.diagnostics["fallback_steps"]))
    print(f"N={n} ν={nu}: t_n L2 {tn:.3g} (max {tn_max:.3g} φn/δn)  t_t L2 {tt:.3g} (max {tt_max:.3g} φn/δn)  "
          f"p {out['p']:.3g}  a_rel {out['a']:.3g}  max|t_t|/max|t_n| {tt_over_tn:.3g}  FE {out['fe_step']:.3f} s/step "
          f"({out['fe_fallbacks']} fallback steps)  GFMD {out['gfmd_step']:.3f} s/step "
          f"(≤ {out['gfmd_iterations']} iterations)")
    _CACHE[(n, nu)] = out
    return out


def orders(outs, nodes, key):
    """Observed orders of `key` between neighbouring N."""
    return [float(np.log(a[key] / b[key]) / np.log(n1 / n0))
            for a, b, n0, n1 in zip(outs, outs[1:], nodes, nodes[1:])]


def study(nodes, ratios=RATIOS):
    """{ν: {"errors" {metric: [per N]}, "orders" {tn, tt, p: [per pair]}, "step_s" {fe, gfmd: [per N]}}}, wall s."""
    t0 = time.perf_counter()
    res = {}
    for nu in ratios:
        outs = [compare(n, nu) for n in nodes]
        res[nu] = {"errors": {m: [float(o[m]) for o in outs] for m in METRICS},
                   "orders": {k: orders(outs, nodes, k) for k in ("tn", "tt", "p")},
                   "step_s": {"fe": [o["fe_step"] for o in outs], "gfmd": [o["gfmd_step"] for o in outs]}}
    return res, time.perf_counter() - t0


def entry(res, nodes, wall, subset):
    return measured.make_entry({"N": list(nodes), **{f"nu={nu:g}": {"errors": r["errors"], "orders": r["orders"]}
                                                   for nu, r in res.items()}},
                               scene="verification.scenes.coupled_sinusoid(N, ν)", subset=subset,
                               step_s={f"nu={nu:g}": r["step_s"] for nu, r in res.items()}, wall_s=wall)


def measured_errors(nu, subset="ci"):
    """{metric: [difference per N]} at ν and the N list (verification/data/fe_coupled.json)."""
    values = measured.entry(NAME, subset)["values"]
    return values[f"nu={nu:g}"]["errors"], values["N"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--full", action="store_true", help="N up to 512 (entry 'full'); default N = 64, 128 ('ci')")
    ap.add_argument("--write", action="store_true", help="store the differences in verification/data/fe_coupled.json")
    args = ap.parse_args(argv)
    subset = "full" if args.full else "ci"
    res, wall = study(NODES[subset])
    for nu, r in res.items():
        print(f"ν = {nu}: orders " + ", ".join(f"{k} {[f'{o:.2f}' for o in v]}" for k, v in r["orders"].items()))
    print(f"{wall:.1f} s")
    if args.write:
        print(measured.write(NAME, {subset: entry(res, NODES[subset], wall, subset)},
                             description="GFMD vs FE P2, coupled-law sinusoid c = 0.5: t_n, t_t, p(δ), a_rel "
                                         "differences vs N per ν, orders between neighbouring N"))


if __name__ == "__main__":
    main()
