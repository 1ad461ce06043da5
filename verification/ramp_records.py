"""The shared ramp checked, not trusted: what a run directory records, recomputed from its saved fields.

`gfmd_contact.core.ramp` records, for every method, δ, p̄, a_rel, ḡ_r and ḡ per step in curve.csv; for a load path
the application layer adds each step's branch and cycle (curve.csv) and each cycle's hysteresis W = ∮ p̄ dδ (meta.json
"cycles"). A bug there is shared by GFMD and the FE, so no GFMD–FE comparison can see it. This module
recomputes those numbers with the harness's own plain numpy from what the run saved: fields.npz (x, h, and
per saved step u_z, gap Δn, t_n) and scene.toml (read with tomllib: the path corners, steps, δn and the
contact rule). It imports nothing from `gfmd_contact`, `gfmd` or `reference`.

Definitions recomputed (reference-formulas §0, seed Eqs. 5–6):
    δ_k     = h_i − min h − Δn_i − u_z,i at every node i (the indenter is rigid: z_ind = h − min h + δ0 − U,
              Δn = z_ind − u_z, δ = U − δ0); its spread over the nodes must be round-off too; and δ_k of the
              path itself: corner path[s] + j (path[s+1] − path[s]) / n_s on segment s (np.linspace not used)
    p̄_k     = −Σ t_n / N
    a_rel_k = #{Δn_i ≤ Δtol} / N, Δtol = s δn with s e^{−s} = contact_tolerance, s > 1 (Newton on
              ln s − s = ln tol, own code); rule "compressive": #{t_n < 0}; rule "gap": Δn ≤ contact_gap δn
    ḡ       = √(Σ_i (h_{i+1} − h_i)² / N) / l, l = (x_{N−1} − x_0)/(N − 1) (periodic; Eq. 6 summed over all
              nodes: the forward and backward squares are the same N differences, so ḡ² is their mean)
    ḡ_r     = √(Σ_{i in contact} ½[(h_{i+1} − h_i)² + (h_i − h_{i−1})²] / n) / l
    branch  "loading" where δ_k > δ_{k−1} (step 0: loading), else "unloading"; a new cycle where δ turns
              from falling to rising
    W_c     = Σ ½ (p̄_k + p̄_{k−1})(δ_k − δ_{k−1}) over cycle c's steps, preceded by the cycle's start
              (the last step of cycle c − 1, or step 0)

Step 0 has no saved fields (output.field_steps saves steps 1 … steps): its δ is checked against the path
only, and W's first trapezoid uses the recorded p̄_0 (stated in the record).

Round-off bounds (ε = 2⁻⁵²; each from the operations, for two evaluations of the same formula in any order):
    δ:    each of the ≤ 4 additions per node is exact to ε × its operands, so |Δδ| ≤ 8 ε S_δ,
          S_δ = max|h| + max|Δn| + max|u_z| + |δ0| + |U| (the ramp's U − δ0 included)
    p̄:    a sum of N terms in any order: |Δp̄| ≤ 2 N ε mean|t_n|
    ḡ, ḡ_r: a sum of N positive terms: relative ≤ 2 (N + 8) ε (differences, squares, sqrt, the spacing)
    a_rel: exact (a count), except nodes with |Δn − Δtol| ≤ 8 ε S_δ may fall either side
    W:    Σ_k |½(p̄_k + p̄_{k−1})| (2 e_δ + (n + 4) ε |Δδ_k|) + ½ (e_p,k + e_p,k−1) |Δδ_k|
"""

from __future__ import annotations

import csv
import json
import tomllib
from pathlib import Path

import numpy as np

EPS = float(np.finfo(float).eps)
TEXT_COLUMNS = ("algorithm", "branch", "event")


def read_run(out, realization=0):
    """{"curve": {column: array}, "fields": {step: {x, h, u_z, gap, t_n}}, "meta", "scene"} of one realization
    of the run directory `out`, read with csv / numpy / json / tomllib."""
    out = Path(out)
    with open(out / "curve.csv", newline="") as fh:
        rows = [r for r in csv.DictReader(fh) if int(r["realization"]) == realization]
    curve = {c: np.array([r[c] for r in rows], object if c in TEXT_COLUMNS else float) for c in rows[0]}
    with np.load(out / "fields.npz") as z:
        x, h = z["x"], z[f"h_r{realization}"]
        steps = sorted({int(k.split("_")[1][1:]) for k in z.files if k.startswith(f"r{realization}_s")})
        fields = {k: {"x": x, "h": h, **{n: z[f"r{realization}_s{k}_{n}"] for n in ("u_z", "gap", "t_n")}}
                  for k in steps}
    meta = json.loads((out / "meta.json").read_text())
    scene = tomllib.loads((out / "scene.toml").read_text())
    return {"curve": curve, "fields": fields, "meta": meta, "scene": scene, "x": x, "h": h}


def path_deltas(loading):
    """δ_k (m) of the path (corners loading["path"], loading["steps"] increments per segment), k = 0 … steps."""
    corners, counts = loading["path"], loading["steps"]
    counts = [counts] * (len(corners) - 1) if isinstance(counts, int) else counts
    out = [float(corners[0])]
    for s, n in enumerate(counts):
        a, b = float(corners[s]), float(corners[s + 1])
        out += [a + j * (b - a) / n for j in range(1, n + 1)]
    return np.array(out)


def tolerance_gap(interface):
    """The contact rule's gap threshold (m), None for the compressive rule (module docstring)."""
    rule = interface.get("contact_rule", "traction-tolerance")
    dn = float(interface["length_normal"])
    if rule == "compressive" or interface["law"] == "hard-wall":
        return None
    if rule == "gap":
        return float(interface["contact_gap"]) * dn
    target = np.log(float(interface["contact_tolerance"]))
    s = 1.0 - 2.0 * target  # Newton on f(s) = ln s − s − ln tol, from the right of the root (f convex there)
    for _ in range(100):
        step = (np.log(s) - s - target) / (1.0 / s - 1.0)
        s -= step
        if abs(step) <= 4 * EPS * s:
            break
    return s * dn


def spacing(x):
    return float((x[-1] - x[0]) / (x.size - 1))


def whole_rms_gradient(h, l):
    """ḡ (module docstring)."""
    d = np.roll(h, -1) - h
    return float(np.sqrt(np.sum(d * d) / h.size) / l)


def contact_rms_gradient(h, l, contact):
    """ḡ_r (module docstring); NaN without contact."""
    if not contact.any():
        return float("nan")
    right = np.roll(h, -1) - h
    left = h - np.roll(h, 1)
    return float(np.sqrt(np.sum((0.5 * (right * right + left * left))[contact]) / contact.sum()) / l)


def recompute(run):
    """Per saved step: δ from the fields (mean and spread over the nodes), p̄, a_rel (and its round-off range),
    ḡ, ḡ_r and the bounds of the module docstring; arrays over `steps` (the saved steps)."""
    x, h = run["x"], run["h"]
    l, n = spacing(x), h.size
    interface = run["scene"]["interface"]
    dtol = tolerance_gap(interface)
    keys = ("step", "delta", "delta_spread", "p", "a_rel", "a_lo", "a_hi", "g", "g_r", "e_delta", "e_p")
    out = {k: [] for k in keys}
    for k, f in sorted(run["fields"].items()):
        gap, u, t = f["gap"], f["u_z"], f["t_n"]
        d_nodes = h - np.min(h) - gap - u
        scale = np.max(np.abs(h)) + np.max(np.abs(gap)) + np.max(np.abs(u)) + 2 * np.max(np.abs(d_nodes))
        e_delta = 8 * EPS * scale
        if dtol is None:
            contact = t < 0
            lo = hi = contact
        else:
            contact = gap <= dtol
            lo, hi = gap <= dtol - e_delta, gap <= dtol + e_delta
        row = {"step": k, "delta": float(np.mean(d_nodes)), "delta_spread": float(np.ptp(d_nodes)),
               "p": float(-np.sum(t) / n), "a_rel": float(contact.sum() / n), "a_lo": float(lo.sum() / n),
               "a_hi": float(hi.sum() / n), "g": whole_rms_gradient(h, l), "g_r": contact_rms_gradient(h, l, contact),
               "e_delta": e_delta, "e_p": 2 * n * EPS * float(np.mean(np.abs(t)))}
        for key in keys:
            out[key].append(row[key])
    return {k: np.array(v) for k, v in out.items()}


def branches(delta):
    """(branch, cycle) per step from δ_k alone (module docstring)."""
    branch, cycle, c = ["loading"], [0], 0
    for k in range(1, delta.size):
        rising = delta[k] > delta[k - 1]
        if rising and branch[-1] == "unloading":
            c += 1
        branch.append("loading" if rising else "unloading")
        cycle.append(c)
    return np.array(branch, object), np.array(cycle)


def hysteresis(delta, p, cycle, e_delta, e_p):
    """{cycle: (W (J/m²), round-off bound)} by the trapezoid rule (module docstring); e_delta, e_p per step."""
    out = {}
    for c in np.unique(cycle):
        idx = np.flatnonzero(cycle == c)
        path = np.concatenate([[idx[0] - 1], idx]) if idx[0] > 0 else idx
        d, q, ed, ep = delta[path], p[path], e_delta[path], e_p[path]
        dd, mid = np.diff(d), 0.5 * (q[1:] + q[:-1])
        w = float(np.sum(mid * dd))
        bound = float(np.sum(np.abs(mid) * (ed[1:] + ed[:-1] + (dd.size + 4) * EPS * np.abs(dd))
                             + 0.5 * (ep[1:] + ep[:-1]) * np.abs(dd)))
        out[int(c)] = (w, bound)
    return out


def _ratio(diff, bound):
    """(max_k |diff_k| / bound_k, max |diff|): ≤ 1 when every step is within its round-off bound."""
    diff = np.abs(np.asarray(diff, float))
    return float(np.max(diff / np.asarray(bound, float))), float(np.max(diff))


def check(out, realization=0):
    """Every comparison of a run directory against its recomputation: {name: (value, tolerance, max |Δ|)}.
    value: max over steps of |recorded − recomputed| / its round-off bound (tolerance 1), relative for ḡ, ḡ_r;
    or a count of mismatches (branch/cycle, a_rel outside its round-off range, NaN of ḡ_r; tolerance 0).
    Also returns numbers for the record."""
    run = read_run(out, realization)
    curve, meta = run["curve"], run["meta"]
    own = recompute(run)
    steps = own["step"].astype(int)
    rec = {c: curve[c][steps] for c in ("delta", "p", "a_rel", "g", "g_r")}
    res = {}
    res["δ: curve.csv vs fields"] = (*_ratio(rec["delta"] - own["delta"], own["e_delta"]),)
    res["δ: spread over the nodes"] = (*_ratio(own["delta_spread"], own["e_delta"]),)
    loading = run["scene"]["loading"]
    d_path = path_deltas(loading)[: curve["step"].size]
    e_path = 8 * EPS * (np.abs(d_path) + np.abs(curve["U"]) + abs(float(loading["path"][0])))
    res["δ: curve.csv vs path"] = (*_ratio(curve["delta"] - d_path, e_path),)
    res["p̄"] = (*_ratio(rec["p"] - own["p"], own["e_p"]),)
    e_g = 2 * (run["h"].size + 8) * EPS
    res["ḡ (relative)"] = (*_ratio(rec["g"] / own["g"] - 1, e_g),)
    both = np.isfinite(own["g_r"]) & np.isfinite(rec["g_r"])
    res["ḡ_r (relative)"] = (*_ratio(np.append(rec["g_r"][both] / own["g_r"][both] - 1, 0.0), e_g),)
    res = {k: (v, 1.0, d) for k, (v, d) in res.items()}
    outside = (rec["a_rel"] < own["a_lo"]) | (rec["a_rel"] > own["a_hi"])
    res["a_rel: steps outside round-off"] = (int(outside.sum()), 0, float(np.max(np.abs(rec["a_rel"] - own["a_rel"]))))
    res["ḡ_r: NaN mismatches"] = (int(np.sum(np.isfinite(own["g_r"]) != np.isfinite(rec["g_r"]))), 0, 0.0)
    numbers = {"steps": int(curve["step"].size), "saved_steps": int(steps.size), "N": int(run["h"].size),
               "max_e_delta_m": float(np.max(own["e_delta"])), "max_e_p_Pa": float(np.max(own["e_p"])),
               "e_g_rel": e_g}
    if "branch" in curve:
        # every step: step 0's δ from the path (no fields), the others' from the fields; p̄_0 the recorded one
        delta, p = np.array(d_path), np.array(curve["p"])
        delta[steps], p[steps] = own["delta"], own["p"]
        e_d = 8 * EPS * (np.abs(d_path) + abs(float(loading["path"][0])))
        e_d[steps] = own["e_delta"]
        e_p = np.zeros(delta.size)
        e_p[steps] = own["e_p"]
        branch, cycle = branches(delta)
        res["branch/cycle mismatches"] = (int(np.sum(branch != curve["branch"]) + np.sum(cycle != curve["cycle"])),
                                          0, 0.0)
        ws = hysteresis(delta, p, cycle, e_d, e_p)
        recorded = {c["cycle"]: c["hysteresis"] for c in meta["cycles"][realization]["cycles"]}
        res["cycles: count mismatch"] = (abs(len(recorded) - len(ws)), 0, 0.0)
        res["W (meta.json)"] = (*_ratio([recorded.get(c, np.nan) - w for c, (w, _) in ws.items()],
                                        [b for _, b in ws.values()]), )
        res["W (meta.json)"] = (res["W (meta.json)"][0], 1.0, res["W (meta.json)"][1])
        numbers.update(W_J_m2={c: w for c, (w, _) in ws.items()}, W_recorded_J_m2=recorded,
                       W_bound_J_m2={c: b for c, (_, b) in ws.items()}, unloading_steps=int(np.sum(branch == "unloading")))
    return res, numbers
