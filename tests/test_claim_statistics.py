"""Every claim's effect size and standard error recomputed by brute force from study.csv.

Each fixture is a synthetic complete study (study.json, base_scene.toml, study.csv, as `gfmd study run`
writes them) with several parameter sets, per-realization values whose scatter differs from set to set
and is correlated between sets through the seed (the same rough profile), and two layouts:
"equal" (every set the same seeds 1 … 5) and "unequal" (3 to 7 realizations per set, seed ranges
offset so that sets share some seeds, not all). The known answer is recomputed here from the csv rows
with plain numpy, not with `gfmd_contact.app.claims` / `gfmd_contact.app.claim_stats`:

* the per-realization quantity (κ fit, a_rel at δ, a_rel where p_r* first reaches a load, …) from the
  rows of that (set, seed), and checked against the value the fixture was built from;
* the effect f(set means) with f written out, its gradient by the complex step (exact to round-off,
  independent of the module's hand-derived gradients), and the covariance of two set means summed
  over the seeds they share (Cov(x̄_a, x̄_b) = Σ_shared cov / (n_a n_b)); in the "equal" layout also
  the textbook route, SE = sd over seeds of Σ g_i x_i(seed) / √n, which needs no covariance formula.

Tolerance: the module and this file compute the same numbers in a different order (sums of at most
~40 terms of order 1, quotients with condition ≤ ~10), so they agree to 40 · 10 · ε ≈ 1e-13 relative
to the size of the terms; ROUNDOFF = 1000 ε ≈ 2.2e-13 of that size is the bound asserted.
"""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from gfmd_contact.core.scene import default_scene, scene_to_toml
from gfmd_contact.app import claims as C

EPS = np.finfo(float).eps
ROUNDOFF = 1000 * EPS
DELTA = np.linspace(-2e-9, 20e-9, 23)  # 1 nm steps: 10 and 20 nm are steps
G = 0.5  # ḡ (m)
RHO = 0.7  # correlation of two sets' values at the same seed
LAYOUTS = {"equal": lambda i: list(range(1, 6)),
           "unequal": lambda i: list(range(1 + i % 3, 1 + i % 3 + (3, 6, 4, 7, 5)[i % 5]))}


def contact_modulus(params):
    m = default_scene().replace(**params).material
    return m.youngs_modulus / (1 - m.poisson_ratio ** 2)


# ---------------------------------------------------------------- the fixture

def draw(sets, layout, spec, seed=0):
    """values[i][seed] = {name: base + scale (ρ z_seed + √(1 − ρ²) e)}: spec(i, params) → {name: (base, scale)}."""
    rng = np.random.default_rng(seed)
    seeds = sorted({s for i in range(len(sets)) for s in LAYOUTS[layout](i)})
    shared = {s: {name: rng.standard_normal() for name in spec(0, sets[0])} for s in seeds}
    out = []
    for i, p in enumerate(sets):
        out.append({s: {name: b + sc * (RHO * shared[s][name] + math.sqrt(1 - RHO**2) * rng.standard_normal())
                        for name, (b, sc) in spec(i, p).items()} for s in LAYOUTS[layout](i)})
    return out


def curve(params, q):
    """Columns over DELTA: p_r* = X t, a_rel = A t^β (t = δ⁺/20 nm), ḡ_r/ḡ = 1 + D; cohesive: p < 0, a_rel = B,
    ḡ_r/ḡ = 1 + 3D at δ < 0."""
    t = np.maximum(DELTA, 0) / 20e-9
    hard = params.get("interface.law") == "hard-wall"
    g_r = np.full(DELTA.size, G * (1 + q.get("D", 0.0)))
    x = q["X"] * t
    a = q["A"] * t ** q.get("beta", 1.0)
    p = x * g_r * contact_modulus(params)
    if hard:
        g_r[t == 0] = np.nan
    else:
        p[DELTA < 0] = -1e-4 * contact_modulus(params)
        g_r[DELTA < 0] = G * (1 + 3 * q.get("D", 0.0))  # before contact: not part of the ḡ_r/ḡ claim
        a[DELTA < 0] = q.get("B", 0.0)
    return {"step": np.arange(DELTA.size), "U": DELTA + 8e-9, "delta": DELTA, "p": p, "a_rel": a, "g_r": g_r,
            "g": np.full(DELTA.size, G), "iterations": np.ones(DELTA.size), "residual": np.zeros(DELTA.size),
            "converged": np.ones(DELTA.size), "wall_s": np.zeros(DELTA.size)}


def write_study(path, sets, values):
    """A complete study directory: sets = [params], values[i] = {seed: curve parameters} (`curve`)."""
    path.mkdir(parents=True)
    keys = list(dict.fromkeys(k for p in sets for k in p))
    tasks = [{"set": i, "parameters": p, "realization": r, "seed": s, "key": f"t{i}r{r}", "status": "run"}
             for i, p in enumerate(sets) for r, s in enumerate(sorted(values[i]))]
    (path / "study.json").write_text(json.dumps({
        "complete": True, "study": path.name, "zip": {}, "tasks": tasks,
        "axes": {k: list(dict.fromkeys(p[k] for p in sets)) for k in keys}}))
    (path / "base_scene.toml").write_text(scene_to_toml(default_scene()))
    with open(path / "study.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["set"] + keys + ["realization", "seed", "task"] + list(C.COLUMNS))
        for t in tasks:
            c = curve(sets[t["set"]], values[t["set"]][t["seed"]])
            for k in range(DELTA.size):
                w.writerow([t["set"]] + [sets[t["set"]].get(key, "") for key in keys]
                           + [t["realization"], t["seed"], t["key"]] + [repr(float(c[col][k])) for col in C.COLUMNS])
    return path


def study(tmp_path, name, sets, layout, spec):
    values = draw(sets, layout, spec)
    path = write_study(tmp_path / f"{name}-{layout}", sets, values)
    return path, values, {r.id: r for r in C.evaluate(C.read_study_dir(path))}


# ---------------------------------------------------------------- brute force from study.csv

def rows(path):
    """{(set, seed): {column: array over the steps}} read from study.csv, and {set: params}."""
    groups, params = {}, {}
    with open(path / "study.csv") as fh:
        for row in csv.DictReader(fh):
            groups.setdefault((int(row["set"]), int(row["seed"])), []).append(row)
    tasks = json.loads((path / "study.json").read_text())["tasks"]
    params = {t["set"]: t["parameters"] for t in tasks}
    out = {k: {c: np.array([float(r[c]) for r in sorted(v, key=lambda r: float(r["step"]))])
               for c in ("delta", "p", "a_rel", "g_r", "g")} for k, v in groups.items()}
    return out, params


def per_set(table, quantity):
    """{set: {seed: quantity(columns, set)}}."""
    out = {}
    for (i, s), c in sorted(table.items()):
        out.setdefault(i, {})[s] = quantity(c, i)
    return out


def at_20nm(c, values):
    return values[np.argmin(np.abs(c["delta"] - 20e-9))]


def first_reach(x, y, p, target):
    """y where x (loading branch, p > 0, increasing here) reaches target: linear between steps."""
    ok = p > 0
    return float(np.interp(target, x[ok], y[ok])) if x[ok].max() >= target else math.nan  # never reaches it


def complex_step_gradient(f, means):
    h = 1e-30
    return np.array([f(means + 1j * h * np.eye(means.size)[j]).imag / h for j in range(means.size)])


def brute_effect(f, samples, layout):
    """(f(x̄), SE, n): complex-step gradient, covariance of the means summed over shared seeds (NaN: no value)."""
    samples = [{k: v for k, v in s.items() if np.isfinite(v)} for s in samples]
    means = np.array([np.mean(list(s.values())) for s in samples])
    value = f(means.astype(complex)).real
    g = complex_step_gradient(f, means.astype(complex))
    k = len(samples)
    cov = np.zeros((k, k))
    for i in range(k):
        for j in range(k):
            a, b = samples[i], samples[j]
            shared = sorted(set(a) & set(b))
            if len(shared) >= 2:
                xa = np.array([a[s] for s in shared])
                xb = np.array([b[s] for s in shared])
                s_ab = np.sum((xa - xa.mean()) * (xb - xb.mean())) / (len(shared) - 1)  # per shared seed
                cov[i, j] = s_ab * len(shared) / (len(a) * len(b))
    q = g @ cov @ g
    se = math.sqrt(q) if q >= 0 else float(np.abs(g) @ np.sqrt(np.diag(cov)))  # the correlated bound
    if layout == "equal" and all(set(x) == set(samples[0]) for x in samples):  # textbook: one value per seed
        seeds = sorted(samples[0])
        z = np.array([sum(g[i] * samples[i][s] for i in range(k)) for s in seeds])
        textbook = float(np.std(z, ddof=1) / math.sqrt(len(seeds)))
        assert se == pytest.approx(textbook, rel=ROUNDOFF * 10, abs=ROUNDOFF * np.abs(g).sum() * np.abs(z).max())
    n = min(len(s) for s, gi in zip(samples, g) if gi != 0)
    return value, se, n


def plain_stats(sample):
    v = np.array(list(sample.values()))
    v = v[np.isfinite(v)]
    return float(v.mean()), float(v.std(ddof=1) / math.sqrt(v.size)) if v.size > 1 else 0.0, v.size


def rel_range(m):
    """(max − min)/|mean| of complex-stepped means (max/min on the real parts)."""
    hi, lo = np.argmax(m.real), np.argmin(m.real)
    tot = np.mean(m)
    return (m[hi] - m[lo]) / (tot * np.sign(tot.real))


def assert_measurement(m, want, scale):
    """value and SE of a Measurement equal to round-off of the size `scale` of the terms; n exactly."""
    value, se, n = want
    assert abs(m.value - value) <= ROUNDOFF * scale, (m.value, value)
    assert abs(m.se - se) <= ROUNDOFF * scale, (m.se, se)
    assert m.n == n
    assert se > 1e-6 * scale  # a standard error that can tell formulas apart


# ---------------------------------------------------------------- Fig. 2: κ and its independence of ν, H, h_rms

FIG2 = [{"interface.law": "hard-wall", "surface.hurst": h, "surface.h_rms": hr, "material.poisson_ratio": nu}
        for h in (0.2, 0.8) for hr in (1e-8, 3e-8) for nu in (0.1, 0.45)]


def fig2_spec(i, p):
    """κ differs by H, h_rms and ν (so every range is nonzero), scatter by set; X sets p_r* at 20 nm."""
    kappa = 1.75 + 0.1 * (p["surface.hurst"] < 0.5) + 0.03 * (p["surface.h_rms"] > 2e-8) \
        + 0.02 * (p["material.poisson_ratio"] > 0.2)
    return {"kappa": (kappa, 0.01 + 0.012 * i), "X": (0.1, 0.01)}


def fig2_values(values):
    return [{s: {"X": q["X"], "A": q["kappa"] * q["X"]} for s, q in v.items()} for v in values]


def brute_kappa(path):
    table, params = rows(path)

    def fit(c, i):
        x = c["p"] / (c["g_r"] * contact_modulus(params[i]))
        use = np.isfinite(x) & (x > 0) & (c["a_rel"] > 0) & (c["a_rel"] <= 0.1)
        return float(x[use] @ c["a_rel"][use] / (x[use] @ x[use]))
    return per_set(table, fit), params


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_kappa_claims_against_brute_force(tmp_path, layout):
    values = draw(FIG2, layout, fig2_spec)
    path = write_study(tmp_path / f"fig2-{layout}", FIG2, fig2_values(values))
    res = {r.id: r for r in C.evaluate(C.read_study_dir(path))}
    kappa, params = brute_kappa(path)
    for i, v in enumerate(values):  # the fit recovers the κ the curves were built with
        for s, q in v.items():
            assert abs(kappa[i][s] - q["kappa"]) <= ROUNDOFF * 10 * q["kappa"]
    sets = sorted(kappa)
    assert_measurement(res["kappa"].measurements[0],
                       brute_effect(lambda m: np.mean(m), [kappa[i] for i in sets], layout), 2.0)
    for cid, key in (("kappa-nu", "material.poisson_ratio"), ("kappa-H", "surface.hurst"),
                     ("kappa-hrms", "surface.h_rms")):
        fams = {}
        for i in sets:
            fams.setdefault(tuple((k, v) for k, v in params[i].items() if k != key), []).append(i)
        ranges = [brute_effect(rel_range, [kappa[i] for i in fam], layout) for fam in fams.values()]
        assert_measurement(res[cid].measurements[0], max(ranges, key=lambda e: e[0]), 1.0)


# ---------------------------------------------------------------- Figs. 3–4: φn* family with its hard wall

FIG3 = [{"interface.law": "hard-wall", "interface.phi_n_star": 0.15}] + \
    [{"interface.law": "cohesive", "interface.phi_n_star": phi} for phi in (0.001, 0.01, 0.15)]


def fig3_spec(i, p):
    hard = p["interface.law"] == "hard-wall"
    return {"X": (0.1 * (1 - 0.1 * i), 0.003 + 0.003 * i), "A": (0.1 + 0.1 * i, 0.01 + 0.01 * i),
            "beta": (1.0 if hard else 1 - 0.15 * i, 0 if hard else 0.02 + 0.02 * i),
            "D": (0.0, 0.0) if hard else (0.01 * i, 0.002 + 0.002 * i), "B": (0.0, 0.0) if hard else
            (0.02 * i, 0.003 + 0.003 * i)}


def fig3_brute(path):
    table, params = rows(path)
    e = {i: contact_modulus(p) for i, p in params.items()}

    def pr(c, i):
        return c["p"] / (c["g_r"] * e[i])

    def nonlin(c, i):
        x = pr(c, i)
        xm, am = at_20nm(c, x), at_20nm(c, c["a_rel"])
        return 2 * first_reach(x, c["a_rel"], c["p"], xm / 2) / am - 1

    def gr_dev(c, i):
        r = c["g_r"] / c["g"]
        ok = np.isfinite(r) & (c["delta"] >= 0)
        return float(np.mean(np.abs(r[ok] - 1)))
    return {"p": per_set(table, lambda c, i: at_20nm(c, c["p"]) / e[i]),
            "a": per_set(table, lambda c, i: at_20nm(c, c["a_rel"])),
            "N": per_set(table, nonlin), "gr": per_set(table, gr_dev),
            "branch": per_set(table, lambda c, i: float(np.max(np.where(c["p"] < 0, c["a_rel"], 0.0))))}


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_phi_family_claims_against_brute_force(tmp_path, layout):
    path, values, res = study(tmp_path, "fig3", FIG3, layout, fig3_spec)
    b = fig3_brute(path)
    for i, v in enumerate(values):  # the known answers the curves were built with
        for s, q in v.items():
            assert b["a"][i][s] == pytest.approx(q["A"], rel=ROUNDOFF)
            assert b["p"][i][s] == pytest.approx(q["X"] * G * (1 + q["D"]), rel=ROUNDOFF * 10)
            assert b["N"][i][s] == pytest.approx(2 * 0.5 ** q["beta"] - 1, abs=ROUNDOFF * 10)
            if i:
                assert b["gr"][i][s] == pytest.approx(abs(q["D"]), rel=ROUNDOFF * 100)
    coh = [1, 2, 3]
    # nonlinearity: N(largest φn*) − N(smallest φn*)
    assert_measurement(res["nonlinearity"].measurements[0],
                       brute_effect(lambda m: m[1] - m[0], [b["N"][1], b["N"][3]], layout), 1.0)
    # area-delta: a_rel(largest φn*) − a_rel(hard wall) at 20 nm
    assert_measurement(res["area-delta"].measurements[0],
                       brute_effect(lambda m: m[1] - m[0], [b["a"][0], b["a"][3]], layout), 1.0)
    # adhesive-branch: the set with the smallest mean; gr-over-g: the set with the largest mean
    assert_measurement(res["adhesive-branch"].measurements[0],
                       min((plain_stats(b["branch"][i]) for i in coh), key=lambda t: t[0]), 1.0)
    assert_measurement(res["gr-over-g"].measurements[0],
                       max((plain_stats(b["gr"][i]) for i in coh), key=lambda t: t[0]), 1.0)
    # pressure-delta: per shared seed p/p_ref − 1 (mean of ratios), the largest |mean| over φn*
    rel = []
    for i in coh:
        shared = sorted(set(b["p"][i]) & set(b["p"][0]))
        r = plain_stats({s: b["p"][i][s] / b["p"][0][s] - 1 for s in shared})
        rel.append((abs(r[0]), r[1], r[2]))
    assert_measurement(res["pressure-delta"].measurements[0], max(rel, key=lambda t: t[0]), 1.0)


def test_pressure_delta_without_a_shared_seed_is_the_ratio_of_means(tmp_path):
    """The reference's seeds disjoint from the adhesive sets': p̄/p̄_ref − 1 with both means' SE."""
    sets = FIG3[:1] + FIG3[2:]
    values = draw(sets, "unequal", fig3_spec)
    values[0] = {s + 100: q for s, q in values[0].items()}
    path = write_study(tmp_path / "disjoint", sets, values)
    res = {r.id: r for r in C.evaluate(C.read_study_dir(path))}
    b = fig3_brute(path)
    rel = [brute_effect(lambda m: m[0] / m[1] - 1, [b["p"][i], b["p"][0]], "unequal") for i in (1, 2)]
    m = max(rel, key=lambda t: abs(t[0]))
    assert_measurement(res["pressure-delta"].measurements[0], (abs(m[0]), m[1], m[2]), 1.0)


# ---------------------------------------------------------------- Fig. 6: h_rms and H with hard-wall references

def fig6_spec(i, p):
    hard = p["interface.law"] == "hard-wall"
    return {"X": (0.1 * (1 - 0.1 * i), 0.002 + 0.002 * i), "A": (0.15 + 0.05 * i, 0.01 + 0.008 * i),
            "beta": (1.0, 0.0) if hard else (0.9 - 0.1 * i, 0.02 + 0.015 * i)}


def area_at_common_load(b_table, params, fam):
    """a_rel where p_r* first reaches half the smallest p_r* any realization of `fam` has at 20 nm."""
    e = {i: contact_modulus(p) for i, p in params.items()}
    pr = {k: c["p"] / (c["g_r"] * e[k[0]]) for k, c in b_table.items()}
    target = 0.5 * min(at_20nm(b_table[k], pr[k]) for k in b_table if k[0] in fam)
    return target, per_set(b_table, lambda c, i: first_reach(c["p"] / (c["g_r"] * e[i]), c["a_rel"], c["p"], target))


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_hrms_claim_against_brute_force(tmp_path, layout):
    sets = [{"interface.law": "cohesive", "interface.phi_n_star": 0.15, "surface.h_rms": h} for h in (1e-8, 1.5e-8, 3e-8)]
    path, _, res = study(tmp_path, "fig6a", sets, layout, fig6_spec)
    table, params = rows(path)
    _, a = area_at_common_load(table, params, {0, 1, 2})
    assert_measurement(res["hrms"].measurements[0], brute_effect(lambda m: m[0] - m[1], [a[0], a[2]], layout), 1.0)


@pytest.mark.parametrize("low_reference", [True, False], ids=["with-reference", "no-reference-at-low-H"])
@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_hurst_claim_against_brute_force(tmp_path, layout, low_reference):
    hs = (0.2, 0.5, 0.8)
    sets = [{"interface.law": "cohesive", "interface.phi_n_star": 0.15, "surface.hurst": h} for h in hs] + \
        [{"interface.law": "hard-wall", "interface.phi_n_star": 0.15, "surface.hurst": h} for h in hs
         if low_reference or h != 0.2]
    path, _, res = study(tmp_path, f"fig6b-{low_reference}", sets, layout, fig6_spec)
    table, params = rows(path)
    x, a = area_at_common_load(table, params, {0, 1, 2})
    ref = {params[i]["surface.hurst"]: i for i in params if params[i]["interface.law"] == "hard-wall"}
    effects = {}
    for i, h in enumerate(hs):
        effects[i] = brute_effect(lambda m: m[0] - m[1], [a[i], a[ref[h]]], layout) if h in ref else \
            (plain_stats(a[i])[0] - C.KAPPA_SEED * x,)
    h2 = min((1, 2), key=lambda i: effects[i][0])
    if low_reference:
        want = brute_effect(lambda m: (m[0] - m[1]) - (m[2] - m[3]), [a[h2], a[ref[hs[h2]]], a[0], a[ref[0.2]]],
                            layout)
    else:
        want = brute_effect(lambda m: (m[0] - m[1]) - (m[2] - C.KAPPA_SEED * x), [a[h2], a[ref[hs[h2]]], a[0]],
                            layout)
    assert_measurement(res["hurst"].measurements[0], want, 1.0)


# ---------------------------------------------------------------- Figs. 7, 8: relative spreads at a common p/E*

def spreads(path, key):
    """{family (the other keys' values): (sets, {set: {seed: a_rel at the family's common p/E*}})}."""
    table, params = rows(path)
    e = {i: contact_modulus(p) for i, p in params.items()}
    fams = {}
    for i, p in params.items():
        fams.setdefault(tuple((k, v) for k, v in p.items() if k != key), []).append(i)
    out = {}
    for f, members in fams.items():
        target = 0.5 * min(at_20nm(c, c["p"] / e[k[0]]) for k, c in table.items() if k[0] in members)
        sub = {k: c for k, c in table.items() if k[0] in members}
        out[f] = (sorted(members, key=lambda i: params[i][key]),
                  per_set(sub, lambda c, i: first_reach(c["p"] / e[i], c["a_rel"], c["p"], target)))
    return out, params


def fig7_spec(i, p):
    low = p["surface.hurst"] < 0.5
    lam = p["surface.rollon_wavelength"]
    return {"X": (0.1 * (1 - 0.1 * (i % 3)), 0.004 + 0.003 * i),
            "A": (0.2 + (0.3 if low else 0.01) * lam / 2e-8, 0.01 + 0.004 * i), "beta": (0.8, 0.02 + 0.01 * i)}


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_eps_f_claim_against_brute_force(tmp_path, layout):
    sets = [{"interface.law": "cohesive", "interface.phi_n_star": 0.15, "surface.hurst": h,
             "surface.rollon_wavelength": lam} for h in (0.2, 0.8) for lam in (2.5e-9, 1e-8, 2e-8)]
    path, _, res = study(tmp_path, "fig7", sets, layout, fig7_spec)
    fams, params = spreads(path, "surface.rollon_wavelength")
    by_h = {params[m[0]]["surface.hurst"]: [a[i] for i in m] for m, a in fams.values()}
    k = len(by_h[0.2])
    want = brute_effect(lambda m: rel_range(m[:k]) - rel_range(m[k:]), by_h[0.2] + by_h[0.8], layout)
    assert_measurement(res["eps-f"].measurements[0], want, 1.0)


def fig8_spec(i, p):
    return {"X": (0.1 * (1 - 0.1 * i), 0.002 + 0.002 * i),
            "A": (0.3 + 0.02 * p["material.poisson_ratio"] + 0.05 * p["interface.tangential_ratio"] + 0.01 * i,
                  0.01 + 0.005 * i), "beta": (0.8, 0.02 + 0.01 * i)}


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_nu_and_friction_claims_against_brute_force(tmp_path, layout):
    sets = [{"interface.law": "cohesive", "interface.phi_n_star": 0.15, "material.poisson_ratio": nu,
             "interface.tangential_ratio": c, "interface.length_tangential": 1e-9}
            for nu in (0.1, 0.3, 0.45) for c in (0.0, 0.5)]
    path, _, res = study(tmp_path, "fig8", sets, layout, fig8_spec)
    for cid, key in (("nu", "material.poisson_ratio"), ("friction", "interface.tangential_ratio")):
        fams, _ = spreads(path, key)
        ranges = [brute_effect(rel_range, [a[i] for i in members], layout) for members, a in fams.values()]
        assert_measurement(res[cid].measurements[0], max(ranges, key=lambda e: e[0]), 1.0)


# ---------------------------------------------------------------- the statistics on their own

def test_difference_reduces_to_the_textbook_cases():
    """Same seeds: the paired SE sd(a − b)/√n; no shared seed: √(SE_a² + SE_b²) (unequal n)."""
    rng = np.random.default_rng(3)
    z = rng.standard_normal(6)
    a = {s: 1.0 + z[s] + 0.3 * rng.standard_normal() for s in range(6)}
    b = {s: 0.5 + 0.8 * z[s] + 0.5 * rng.standard_normal() for s in range(6)}
    d = np.array([a[s] - b[s] for s in range(6)])
    m, se, n = C.difference(a, b)
    assert abs(m - d.mean()) <= ROUNDOFF * 4 and abs(se - d.std(ddof=1) / math.sqrt(6)) <= ROUNDOFF * 4 and n == 6
    c = {s + 10: v for s, v in list(b.items())[:4]}
    va, vc = np.array(list(a.values())), np.array(list(c.values()))
    m, se, n = C.difference(a, c)
    want = math.hypot(va.std(ddof=1) / math.sqrt(6), vc.std(ddof=1) / math.sqrt(4))
    assert abs(m - (va.mean() - vc.mean())) <= ROUNDOFF * 4 and abs(se - want) <= ROUNDOFF * 4 and n == 4


def test_inconsistent_pairwise_covariance_falls_back_to_the_correlated_bound():
    """Two shared seeds that covary far more than the rest: gᵀCg < 0; the SE is then SE_a + SE_b, not 0."""
    a = {1: 0.0, 2: 1.0, **{s: 0.5 for s in range(3, 21)}}
    b = {1: 0.0, 2: 1.0, **{s: 0.5 for s in range(21, 39)}}
    va, vb = np.array(list(a.values())), np.array(list(b.values()))
    se_a, se_b = va.std(ddof=1) / math.sqrt(20), vb.std(ddof=1) / math.sqrt(20)
    s_ab = np.cov([0.0, 1.0], [0.0, 1.0])[0, 1]
    assert se_a**2 + se_b**2 - 2 * s_ab * 2 / 400 < 0  # the estimated quadratic form is negative here
    m, se, n = C.difference(a, b)
    assert abs(se - (se_a + se_b)) <= ROUNDOFF and m == 0.0 and n == 20


def test_sets_equal_to_round_off_give_the_se_of_their_difference():
    """κ at two ν on the same profiles differs by ~1e-11: the SE is that of the per-seed difference (taken
    before squaring), not the round-off of Var(ā) + Var(b̄) − 2 Cov(ā, b̄) (≈ 1e-9 here)."""
    rng = np.random.default_rng(5)
    a = {s: 1.8 + 0.05 * rng.standard_normal() for s in range(10)}
    b = {s: v + 1e-11 * rng.standard_normal() for s, v in a.items()}
    d = np.array([a[s] - b[s] for s in range(10)])
    m, se, n = C.difference(a, b)
    assert se == pytest.approx(d.std(ddof=1) / math.sqrt(10), rel=1e-3)  # 1e-11 of 1.8: 5 digits are left
