"""The observables the seed's claims measure (`gfmd_contact.app.claims`), as plain functions over a study's sets.

Units: SI. A set `s` is a `study_data.SetInfo`: `s.stacked` holds its realizations × steps curves
(`plots.stack_curves`; NaN where a realization has no such step) of p (mean pressure), δ (penetration),
a_rel, ḡ (rms gradient) and ḡ_r (rms gradient in contact); `s.e_star` is E*, `s.seeds` maps a
realization to its surface seed. The quantities:

* per realization, from its own curve alone: p_r* = p/(ḡ_r E*), κ (the slope of a_rel vs p_r*),
  a value at a given δ, a_rel where p_r* (or p/E*) first reaches a level, the nonlinearity
  N = 2 a_rel(x/2)/a_rel(x) − 1 and the deviation ⟨|ḡ_r/ḡ − 1|⟩; returned as {realization: value}
  and keyed by seed with `seeded` so that two sets pair realization by realization;
* the sets grouped: the keys that vary, families along one key, a set's hard-wall reference, the
  contexts (values of the modelling-choice keys, `CONTEXT_KEYS`) a claim is evaluated in, and labels.
"""

from __future__ import annotations

import math

import numpy as np

from gfmd_contact.core.observables import fit_kappa

#: the largest δ the seed evaluates (Figs. 4, 5): 20 nm
DELTA_SEED = 20e-9
#: keys whose values are modelling choices, not the seed's: a claim is evaluated per value
CONTEXT_KEYS = ("interface.length_normal", "interface.contact_rule", "interface.contact_gap")
#: keys that make a set the non-adhesive reference or set its adhesion
LAW_KEYS = ("interface.law", "interface.phi_n_star")


# ---------------------------------------------------------------- per-realization quantities

def reduced_pressure_of(s):
    """(R, S) p_r* = p/(ḡ_r E*) of set `s` (NaN without contact)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return s.stacked["p"] / (s.stacked["g_r"] * s.e_star)


def kappa_per_realization(s, a_max=0.1):
    """{realization: κ} of set `s`: `fit_kappa` on each realization's own curve (0 < a_rel ≤ a_max, p > 0)."""
    pr = reduced_pressure_of(s)
    out = {}
    for i, r in enumerate(s.stacked.realizations):
        try:
            out[r] = fit_kappa(pr[i], s.stacked["a_rel"][i], a_max=a_max)[0]
        except ValueError:
            pass
    return out


def seeded(s, values):
    """{seed: value} of set `s` from {realization: value}: realizations of two sets pair by their seed."""
    return {s.seeds.get(r, r): v for r, v in values.items()}


def max_delta(s):
    """The largest δ (m) every realization of `s` reached."""
    return float(np.nanmin(np.nanmax(s.stacked["delta"], axis=1)))


def at_delta(s, column, delta):
    """{realization: value of `column` at the step with δ nearest `delta`} (NaN if it stopped before)."""
    st = s.stacked
    values = column(s) if callable(column) else st[column]
    out = {}
    for i, r in enumerate(st.realizations):
        d = st["delta"][i]
        ok = np.isfinite(d)
        if not ok.any() or np.nanmax(d) < delta - 1e-3 * abs(delta) - 1e-15:
            out[r] = math.nan
            continue
        k = int(np.nanargmin(np.where(ok, np.abs(d - delta), np.inf)))
        out[r] = float(values[i][k])
    return out


def at_level(x, y, target):
    """y where x first reaches `target` along the steps (linear between the two steps); NaN if never."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    hit = np.nonzero(x >= target)[0]
    if hit.size == 0:
        return math.nan
    k = int(hit[0])
    if k == 0 or x[k] == x[k - 1]:
        return float(y[k])
    w = (target - x[k - 1]) / (x[k] - x[k - 1])
    return float(y[k - 1] + w * (y[k] - y[k - 1]))


def area_at(s, xname, target):
    """{realization: a_rel where x first reaches target}, x = "p_r" (p_r*) or "p_E" (p/E*), only p > 0 steps."""
    x = reduced_pressure_of(s) if xname == "p_r" else s.stacked["p"] / s.e_star
    out = {}
    for i, r in enumerate(s.stacked.realizations):
        xi = np.where(s.stacked["p"][i] > 0, x[i], np.nan)
        out[r] = at_level(xi, s.stacked["a_rel"][i], target)
    return out


def _x_at_delta(s, xname, delta):
    col = (lambda z: reduced_pressure_of(z)) if xname == "p_r" else (lambda z: z.stacked["p"] / z.e_star)
    return list(at_delta(s, col, delta).values())


def common_target(sets, xname, delta):
    """Half the smallest x (p_r* or p/E*) any realization of `sets` has at δ: a load every realization
    reaches on its loading branch (realizations of one set can differ by 10× in p at the same δ)."""
    xs = [x for s in sets for x in _x_at_delta(s, xname, delta)]
    xs = [x for x in xs if np.isfinite(x) and x > 0]
    return 0.5 * min(xs) if xs else math.nan


def eval_delta(sets):
    """δ at which claims at a fixed δ are evaluated: min(20 nm, the largest δ every set reached)."""
    return min([DELTA_SEED] + [max_delta(s) for s in sets])


def nonlinearity(s, delta):
    """{realization: 2 a_rel(x_max/2)/a_rel(x_max) − 1}, x = p_r*, x_max = its p_r* at δ (0 for a_rel ∝ p_r*)."""
    pr = reduced_pressure_of(s)
    xmax = at_delta(s, lambda z: pr, delta)
    amax = at_delta(s, "a_rel", delta)
    out = {}
    for i, r in enumerate(s.stacked.realizations):
        x = np.where(s.stacked["p"][i] > 0, pr[i], np.nan)
        half = at_level(x, s.stacked["a_rel"][i], 0.5 * xmax[r]) if np.isfinite(xmax[r]) and xmax[r] > 0 else math.nan
        out[r] = 2 * half / amax[r] - 1 if amax[r] and np.isfinite(amax[r]) else math.nan
    return out


def gr_deviation(s):
    """{realization: mean over its steps with contact (finite ḡ_r, δ ≥ 0) of |ḡ_r/ḡ − 1|}."""
    st = s.stacked
    out = {}
    for i, r in enumerate(st.realizations):
        ratio = st["g_r"][i] / st["g"][i]
        ok = np.isfinite(ratio) & (st["delta"][i] >= 0)
        out[r] = float(np.mean(np.abs(ratio[ok] - 1))) if ok.any() else math.nan
    return out


# ---------------------------------------------------------------- grouping sets

def varying(sets, keys):
    """The keys whose values differ between `sets`."""
    return [k for k in keys if len({repr(s.params.get(k)) for s in sets}) > 1]


def families(sets, keys, along):
    """Groups of `sets` that differ only in `along` (every other study key equal), with ≥ 2 values of it."""
    groups = {}
    for s in sets:
        sig = tuple((k, repr(s.params.get(k))) for k in keys if k != along)
        groups.setdefault(sig, []).append(s)
    return [sorted(g, key=lambda s: s.value(along)) for g in groups.values()
            if len({repr(s.value(along)) for s in g}) > 1]


def reference_of(s, sets):
    """The hard-wall set with the same surface, material, loading and δn as `s`, or None."""
    for r in sets:
        if r.hard_wall and r is not s and r.signature == s.signature:
            return r
    return None


def contexts(data):
    """[(label, sets)]: the sets split by the values of the modelling-choice keys the study varies."""
    ctx = [k for k in CONTEXT_KEYS if k in data.keys and len({repr(s.params.get(k)) for s in data.sets}) > 1]
    if not ctx:
        return [("", data.with_data)]
    groups = {}
    for s in data.with_data:
        groups.setdefault(tuple(s.params.get(k) for k in ctx), []).append(s)
    return [(", ".join(_param_text(k, v) for k, v in zip(ctx, vals)), g) for vals, g in groups.items()]


#: short names and units of scene keys in labels: key → (symbol, scale, unit)
KEY_LABELS = {
    "surface.hurst": ("H", 1, ""), "surface.h_rms": ("h_rms", 1e9, " nm"),
    "surface.rollon_wavelength": ("λ_sH", 1e9, " nm"), "surface.rolloff_wavelength": ("λ_r", 1e9, " nm"),
    "surface.nodes": ("N", 1, ""), "material.poisson_ratio": ("ν", 1, ""),
    "interface.phi_n_star": ("φn*", 1, ""), "interface.tangential_ratio": ("c", 1, ""),
    "interface.length_normal": ("δn", 1e9, " nm"), "interface.length_tangential": ("δt", 1e9, " nm"),
    "interface.law": ("law", None, ""), "interface.contact_rule": ("contact rule", None, ""),
    "interface.contact_gap": ("contact gap", 1, " δn"),
}


def _param_text(key, value):
    sym, scale, unit = KEY_LABELS.get(key, (key, 1, ""))
    if scale is None or not isinstance(value, (int, float)) or isinstance(value, bool):
        return f"{sym} = {value}"
    return f"{sym} = {value * scale:g}{unit}"


def set_label(s, keys):
    """'H = 0.8, φn* = 0.15' for the given keys ('hard wall' for a hard-wall set, without φn*)."""
    if s.hard_wall:
        rest = [_param_text(k, s.params.get(k)) for k in keys if k not in LAW_KEYS]
        return ", ".join(["hard wall"] + rest)
    return ", ".join(_param_text(k, s.params.get(k)) for k in keys if k != "interface.law") or "cohesive"

