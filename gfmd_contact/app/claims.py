"""The seed paper's claims (Figs. 2–8) measured on a study directory: effect sizes, standard errors, verdicts.

Units: SI in the tables (`gfmd_contact.app.study`); effect sizes are dimensionless (p/E*, p_r* = p/(ḡ_r E*),
a_rel, ḡ_r/ḡ, relative differences). Everything here is a plain function over the study's
per-realization table (study.csv, or the finished tasks' curve.csv while a study is
incomplete), read by `read_study_dir`:

* per (set, realization) a value is computed from that realization's curve alone
  (a κ fit, a_rel at a given δ, a_rel where p_r* first reaches a target, …; `gfmd_contact.app.claim_measures`),
  keyed by its seed;
* a set's value is the mean over its realizations, its standard error SE = s/√n
  (s: sample standard deviation, n: realizations with a value; 0 for n = 1);
* an effect size is a function of set means (a difference, a mean over sets, a relative range);
  its SE is the delta method's with the covariance of the set means estimated from the seeds the
  sets share (the same rough profile, scaled): for a difference of two sets with the same seeds
  the paired SE, with no seed shared √(SE₁² + SE₂²) (`gfmd_contact.app.claim_stats`);
* the verdict compares the effect with the claim's limit at two standard errors:
  "reproduced" when the whole interval value ± 2 SE is on the claim's side, "not reproduced"
  when it is wholly on the other side, "inconclusive (within 2 SE)" otherwise (and whenever fewer
  than two realizations give the value: no standard error); "not in this
  study" when the study lacks the sets (e.g. no φn* axis); and "depends on δn / the contact
  rule" when the study varies interface.length_normal (or a contact-rule key) and the verdict
  differs between its values (each value's number is listed).

`CLAIMS` lists the claims with their definitions (the report prints them); `evaluate(data)`
returns one `ClaimResult` per claim.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .claim_measures import (CONTEXT_KEYS, DELTA_SEED, KEY_LABELS, LAW_KEYS, _param_text, area_at,  # noqa: F401
                             at_delta, at_level, common_target, contexts, eval_delta, families, gr_deviation,
                             kappa_per_realization, max_delta, nonlinearity, reduced_pressure_of, reference_of,
                             seeded, set_label, varying)
from .claim_stats import (DEPENDS, INCONCLUSIVE, NOT_IN_STUDY, NOT_REPRODUCED, REPRODUCED, SINGLE,  # noqa: F401
                          difference, effect, linear, relative_range, relative_range_gradient, stats,
                          verdict_below, verdict_positive)
from .study_data import COLUMNS, SetInfo, StudyData, StudyDirError, read_study_dir  # noqa: F401

#: the seed's κ (Fig. 2, §3)
KAPPA_SEED = 1.75


# ---------------------------------------------------------------- claims

@dataclass
class Measurement:
    context: str  # '' or e.g. 'δn = 0.25 nm'
    value: float
    se: float
    n: int
    verdict: str
    details: str


@dataclass
class ClaimResult:
    id: str
    figure: str
    claim: str
    definition: str
    study: str
    verdict: str
    measurements: list


def _fmt(x, digits=3):
    return "nan" if x is None or not np.isfinite(x) else f"{x:.{digits}g}"


def _pm(m, se, n=None):
    return f"{_fmt(m)} ± {_fmt(se, 2)}" + (f" (n = {n})" if n is not None else "")


def _hw(sets):
    return [s for s in sets if s.hard_wall]


def _coh(sets):
    return [s for s in sets if not s.hard_wall]


def claim_kappa(sets, keys):
    hw = _hw(sets)
    if not hw:
        return None
    per = [(s, seeded(s, kappa_per_realization(s))) for s in hw]
    per = [(s, v) for s, v in per if stats(v)[2] > 0]
    if not per:
        return None
    # the mean over sets of the set means; sets share seeds, so their means covary (claim_stats)
    kappa, se, n = linear([v for _, v in per], [1 / len(per)] * len(per))
    dev = abs(kappa - KAPPA_SEED)
    verdict = verdict_below(dev, se, 0.1 * KAPPA_SEED)
    lab = varying([s for s, _ in per], keys)
    details = "; ".join(f"{set_label(s, lab) or 'hard wall'}: κ = {_pm(*stats(v))}" for s, v in per)
    return Measurement("", kappa, se, n, verdict, details)


def _relative_range(samples):
    """(r, SE, n) of (max − min)/mean of the set means (`claim_stats.relative_range`), or None."""
    rr = relative_range(samples)
    return None if rr is None else rr[:3]


def claim_kappa_independent(key):
    def measure(sets, keys):
        fams = families(_hw(sets), keys, key)
        if not fams:
            return None
        worst = None
        parts = []
        for fam in fams:
            rr = _relative_range([seeded(s, kappa_per_realization(s)) for s in fam])
            if rr is None:
                continue
            parts.append(", ".join(f"{_param_text(key, s.value(key))}: κ = {_pm(*stats(kappa_per_realization(s)))}"
                                   for s in fam))
            if worst is None or rr[0] > worst[0]:
                worst = rr
        if worst is None:
            return None
        return Measurement("", worst[0], worst[1], worst[2], verdict_below(worst[0], worst[1], 0.1),
                           " | ".join(parts))
    return measure


def _phi_family(sets, keys):
    """Families along φn* among the cohesive sets (with their hard-wall reference first, if any)."""
    fams = families(_coh(sets), keys, "interface.phi_n_star")
    return [([reference_of(f[0], sets)] if reference_of(f[0], sets) else []) + f for f in fams]


def _phi_text(s):
    return "hard wall" if s.hard_wall else f"φn* = {s.value('interface.phi_n_star'):g}"


def claim_nonlinearity(sets, keys):
    fams = _phi_family(sets, keys)
    if not fams:
        return None
    fam = fams[0]
    d = eval_delta(fam)
    vals = {s.index: seeded(s, nonlinearity(s, d)) for s in fam}
    coh = [s for s in fam if not s.hard_wall]
    m, se, n = difference(vals[coh[-1].index], vals[coh[0].index])
    details = ", ".join(f"{_phi_text(s)}: {_pm(*stats(vals[s.index]))}" for s in fam) + f" (δ = {d * 1e9:.3g} nm)"
    return Measurement("", m, se, n, verdict_positive(m, se), details)


def claim_adhesive_branch(sets, keys):
    coh = [s for s in _coh(sets) if s.adhesive]
    if not coh:
        return None
    per = []
    for s in coh:
        st = s.stacked
        v = {r: float(np.nanmax(np.where(st["p"][i] < 0, st["a_rel"][i], 0.0), initial=0.0))
             for i, r in enumerate(st.realizations)}
        per.append((s, stats(v)))
    s, m = min(per, key=lambda t: t[1][0])
    lab = varying(coh, keys)
    details = ", ".join(f"{set_label(x, lab)}: {_pm(*mm)}" for x, mm in per)
    return Measurement("", m[0], m[1], m[2], verdict_positive(m[0], m[1]), details)


def claim_pressure_independent(sets, keys):
    fams = _phi_family(sets, keys)
    if not fams:
        coh = [s for s in _coh(sets) if reference_of(s, sets)]
        if not coh:
            return None
        fams = [[reference_of(coh[0], sets)] + [s for s in coh if s.signature == coh[0].signature]]
    fam = fams[0]
    d = eval_delta(fam)
    ref = fam[0]
    p_ref = seeded(ref, at_delta(ref, lambda z: z.stacked["p"] / z.e_star, d))
    worst, parts = None, []
    for s in fam[1:]:
        p = seeded(s, at_delta(s, lambda z: z.stacked["p"] / z.e_star, d))
        common = [r for r in p if r in p_ref and p_ref[r] and np.isfinite(p_ref[r]) and np.isfinite(p[r])]
        if common:  # per realization (same seed): p/p_ref − 1; realizations differ 10× in p at one δ
            m, se, n = stats([p[r] / p_ref[r] - 1 for r in common])
        else:  # no shared seed: p̄/p̄_ref − 1, delta method through both means
            mp, mr = stats(p)[0], stats(p_ref)[0]
            m, se, n = effect([p, p_ref], mp / mr - 1, [1 / mr, -mp / mr**2])
        rel = (abs(m), se, n)
        parts.append(f"{_phi_text(s)}: p/E* = {_pm(*stats(p))}, relative difference {_pm(m, se)}")
        if worst is None or rel[0] > worst[0]:
            worst = rel
    details = f"{_phi_text(ref)} (reference): p/E* = {_pm(*stats(p_ref))}; " + "; ".join(parts) + \
        f" (δ = {d * 1e9:.3g} nm)"
    return Measurement("", worst[0], worst[1], worst[2], verdict_below(worst[0], worst[1], 0.1), details)


def claim_area_grows(sets, keys):
    fams = _phi_family(sets, keys)
    if not fams:
        return None
    fam = fams[0]
    d = eval_delta(fam)
    vals = {s.index: seeded(s, at_delta(s, "a_rel", d)) for s in fam}
    m, se, n = difference(vals[fam[-1].index], vals[fam[0].index])
    details = ", ".join(f"{_phi_text(s)}: {_pm(*stats(vals[s.index]))}" for s in fam) + f" (δ = {d * 1e9:.3g} nm)"
    return Measurement("", m, se, n, verdict_positive(m, se), details)


def claim_gr_to_one(sets, keys):
    coh = [s for s in _coh(sets) if s.adhesive]
    if not coh:
        return None
    per = [(s, stats(gr_deviation(s))) for s in coh]
    s, m = max(per, key=lambda t: t[1][0])
    lab = varying(coh, keys)
    hw = _hw(sets)
    details = ", ".join(f"{set_label(x, lab)}: {_pm(*mm)}" for x, mm in per)
    if hw:
        details += f"; hard wall (for contrast): {_pm(*stats(gr_deviation(hw[0])))}"
    return Measurement("", m[0], m[1], m[2], verdict_below(m[0], m[1], 0.1), details)


def claim_hrms(sets, keys):
    fams = families([s for s in _coh(sets) if s.adhesive], keys, "surface.h_rms")
    if not fams:
        return None
    fam = fams[0]
    d = eval_delta(fam)
    x = common_target(fam, "p_r", d)
    vals = {s.index: seeded(s, area_at(s, "p_r", x)) for s in fam}
    m, se, n = difference(vals[fam[0].index], vals[fam[-1].index])
    details = ", ".join(f"h_rms = {s.value('surface.h_rms') * 1e9:g} nm: a_rel = {_pm(*stats(vals[s.index]))}"
                        for s in fam) + f" (at p_r* = {_fmt(x)})"
    return Measurement("", m, se, n, verdict_positive(m, se), details)


def claim_hurst(sets, keys):
    fams = families([s for s in _coh(sets) if s.adhesive], keys, "surface.hurst")
    if not fams:
        return None
    fam = fams[0]
    d = eval_delta(fam + [r for r in (reference_of(s, sets) for s in fam) if r])
    x = common_target(fam, "p_r", d)
    terms, eff, parts = {}, {}, []  # per H: (samples, weights, offset) of its adhesion effect
    for s in fam:
        a = seeded(s, area_at(s, "p_r", x))
        ref = reference_of(s, sets)
        if ref is not None:
            terms[s.index] = ([a, seeded(ref, area_at(ref, "p_r", x))], [1.0, -1.0], 0.0)
        else:
            terms[s.index] = ([a], [1.0], -KAPPA_SEED * x)
        eff[s.index] = linear(*terms[s.index])
        parts.append(f"H = {s.value('surface.hurst'):g}: {_pm(*eff[s.index])}")
    low = fam[0]
    s2 = min(fam[1:], key=lambda s: eff[s.index][0])
    # effect(H₂) − effect(H_low) as one combination: the H's share seeds, so their effects covary
    (sa, wa, oa), (sb, wb, ob) = terms[s2.index], terms[low.index]
    m, se, n = linear(sa + sb, list(wa) + [-w for w in wb], oa - ob)
    strongest = max(fam, key=lambda s: eff[s.index][0])
    details = "adhesion effect a_rel(adhesive) − a_rel(hard wall): " + ", ".join(parts) + \
        f" (at p_r* = {_fmt(x)}); strongest at H = {strongest.value('surface.hurst'):g} (seed: 0.5)"
    return Measurement("", m, se, n, verdict_positive(m, se), details)


def _spread_at_pressure(fam):
    """(relative_range_gradient of a_rel at a common p/E* over `fam`, its samples, [(set, stats)], p/E*)."""
    d = eval_delta(fam)
    x = common_target(fam, "p_E", d)
    samples = [seeded(s, area_at(s, "p_E", x)) for s in fam]
    return relative_range_gradient(samples), samples, [(s, stats(v)) for s, v in zip(fam, samples)], x


def claim_eps_f(sets, keys):
    coh = [s for s in _coh(sets) if s.adhesive]
    fams = families(coh, keys, "surface.rollon_wavelength")
    if not fams:
        return None
    by_h = {}
    for fam in fams:
        rg, samples, vals, x = _spread_at_pressure(fam)
        if rg is not None:
            by_h[fam[0].value("surface.hurst")] = (effect(samples, rg[0], rg[1]), vals, x, samples, rg[1])
    parts = [f"H = {h:g}: spread {_pm(*rr[:2])} [" + ", ".join(
        f"λ_sH = {s.value('surface.rollon_wavelength') * 1e9:g} nm: {_fmt(m[0])}" for s, m in vals)
        + f"] at p/E* = {_fmt(x)}" for h, (rr, vals, x, _, _) in sorted(by_h.items())]
    if len(by_h) < 2:
        return Measurement("", math.nan, math.nan, 0, NOT_IN_STUDY, "; ".join(parts) + " (needs two H)")
    lo, hi = by_h[min(by_h)], by_h[max(by_h)]
    # spread(H_lo) − spread(H_hi) as one function of both families' set means (they share seeds)
    m, se, n = effect(lo[3] + hi[3], lo[0][0] - hi[0][0], list(lo[4]) + list(-hi[4]))
    verdict = verdict_positive(m, se)
    if verdict == REPRODUCED and verdict_below(hi[0][0], hi[0][1], 0.1) == NOT_REPRODUCED:
        verdict = NOT_REPRODUCED
    return Measurement("", m, se, n, verdict, "; ".join(parts))


def claim_negligible(key):
    def measure(sets, keys):
        fams = families([s for s in _coh(sets) if s.adhesive], keys, key)
        if not fams:
            return None
        worst, parts = None, []
        for fam in fams:
            rg, samples, vals, x = _spread_at_pressure(fam)
            if rg is None:
                continue
            rr = effect(samples, rg[0], rg[1])
            others = [k for k in varying(fam + [s for f in fams for s in f], keys) if k != key]
            head = set_label(fam[0], others) if others else ""
            parts.append((f"{head}: " if head else "") + ", ".join(
                f"{_param_text(key, s.value(key))}: a_rel = {_pm(*m)}" for s, m in vals) + f" at p/E* = {_fmt(x)}")
            if worst is None or rr[0] > worst[0]:
                worst = rr
        if worst is None:
            return None
        return Measurement("", worst[0], worst[1], worst[2], verdict_below(worst[0], worst[1], 0.1),
                           " | ".join(parts))
    return measure


@dataclass(frozen=True)
class Claim:
    id: str
    figure: str
    claim: str
    definition: str
    measure: object  # (sets, keys) → Measurement or None (the study lacks the sets)


CLAIMS = (
    Claim("kappa", "Fig. 2", "Non-adhesive contact: a_rel = κ p_r* with κ ≈ 1.75",
          "κ per realization: least-squares slope through the origin of a_rel vs p_r* = p/(ḡ_r E*) over its "
          "steps with p > 0 and 0 < a_rel ≤ 0.1 (gfmd_contact.core.observables.fit_kappa); per hard-wall set the mean ± SE "
          "over realizations; value: the mean over hard-wall sets (SE: delta method, the sets' means covary through "
          "their shared seeds). Reproduced if |κ − 1.75| ± 2 SE "
          "≤ 0.175 (10 %).", claim_kappa),
    Claim("kappa-nu", "Fig. 2", "κ is independent of the Poisson ratio ν",
          "Hard-wall sets that differ only in ν: (max − min)/mean of the set κ's (largest over such groups); SE "
          "by the delta method through the two extreme sets and the mean (paired over shared seeds). Reproduced "
          "if ≤ 0.1 at 2 SE.",
          claim_kappa_independent("material.poisson_ratio")),
    Claim("kappa-H", "Fig. 2", "κ is independent of the Hurst exponent H",
          "As for ν, over hard-wall sets that differ only in H.", claim_kappa_independent("surface.hurst")),
    Claim("kappa-hrms", "Fig. 2", "κ is independent of h_rms",
          "As for ν, over hard-wall sets that differ only in h_rms.", claim_kappa_independent("surface.h_rms")),
    Claim("nonlinearity", "Fig. 3a", "Adhesion breaks the linearity of a_rel–p_r*, the more so the larger φn*",
          "Nonlinearity per realization: N = 2 a_rel(x/2)/a_rel(x) − 1 with x its p_r* at δ_eval = min(20 nm, "
          "largest δ all sets reach) and a_rel(x/2) where p_r* first reaches x/2 on the loading branch (p > 0); "
          "N = 0 for a_rel ∝ p_r*, > 0 when area grows faster at small loads. Value: N(largest φn*) − "
          "N(smallest φn*): the difference of the set means, SE paired over shared seeds. Reproduced if > 0 "
          "at 2 SE.", claim_nonlinearity),
    Claim("adhesive-branch", "Fig. 3b", "Adhesive contacts have a_rel > 0 at tensile mean pressure p < 0",
          "Per realization: the largest a_rel over its steps with p < 0 (0 if none); value: the smallest set mean "
          "over the adhesive sets. Reproduced if > 0 at 2 SE.", claim_adhesive_branch),
    Claim("pressure-delta", "Fig. 4a", "p(δ) is nearly independent of φn* (adhesive ≈ non-adhesive)",
          "p/E* at δ_eval = min(20 nm, largest δ all sets reach): for each adhesive set and realization "
          "p/p_ref − 1 against the same realization (seed) of the hard wall (else of the smallest φn*); per set "
          "its mean ± SE; value: the largest |mean| over φn*. Reproduced if ≤ 0.1 at 2 SE.",
          claim_pressure_independent),
    Claim("area-delta", "Fig. 4b", "a_rel at fixed δ grows with φn*",
          "a_rel at δ_eval (step nearest): largest φn* minus the hard wall (else the smallest φn*), set means, SE "
          "paired over shared seeds. Reproduced if > 0 at 2 SE.", claim_area_grows),
    Claim("gr-over-g", "Fig. 4c", "ḡ_r/ḡ → 1 for adhesive contacts",
          "Per realization: the mean over its steps with contact (ḡ_r defined, δ ≥ 0) of |ḡ_r/ḡ − 1|; value: "
          "the largest set mean over the adhesive sets. Reproduced if ≤ 0.1 at 2 SE.", claim_gr_to_one),
    Claim("hrms", "Fig. 6a", "Smaller h_rms gives more contact area at a given p_r* (adhesive)",
          "a_rel where p_r* first reaches x* = half the smallest p_r* any realization has at δ_eval; value: a_rel(smallest "
          "h_rms) − a_rel(largest h_rms), SE paired over shared seeds. Reproduced if > 0 at 2 SE.", claim_hrms),
    Claim("hurst", "Fig. 6b", "The effect of adhesion is weakest at the smallest H (strongest at H = 0.5)",
          "Adhesion effect per H: a_rel(adhesive) − a_rel(its hard-wall reference) at p_r* = x* (as for h_rms; "
          "without a reference 1.75 x*); value: the smallest effect over the larger H's minus the effect at the "
          "smallest H, SE paired over the seeds the (up to four) sets share. Reproduced if > 0 at 2 SE (where it is "
          "strongest is listed).", claim_hurst),
    Claim("eps-f", "Fig. 7", "ε_f (roll-on wavelength) matters at H = 0.2, not at H = 0.8",
          "a_rel where p/E* first reaches half the smallest p/E* any realization has at δ_eval; per H the spread (max − min)/"
          "mean over λ_sH; value: spread(smallest H) − spread(largest H) (SE: delta method over both H's sets, "
          "paired over shared seeds). "
          "Reproduced if > 0 at 2 SE and the largest H's spread is not > 0.1 at 2 SE.", claim_eps_f),
    Claim("nu", "Fig. 8", "The Poisson ratio ν changes a_rel–p/E* negligibly (adhesive)",
          "a_rel at a common p/E* (as for ε_f) over adhesive sets that differ only in ν: (max − min)/mean, "
          "largest over groups. Reproduced if ≤ 0.1 at 2 SE.", claim_negligible("material.poisson_ratio")),
    Claim("friction", "Fig. 8", "Interface friction c = φt*/φn* changes a_rel–p/E* negligibly",
          "As for ν, over adhesive sets that differ only in c (interface.tangential_ratio).",
          claim_negligible("interface.tangential_ratio")),
)


def evaluate(data, claims=CLAIMS):
    """One ClaimResult per claim for a StudyData (`read_study_dir`)."""
    out = []
    keys = [k for k in data.keys if k not in CONTEXT_KEYS]
    for c in claims:
        ms = []
        for label, sets in contexts(data):
            try:
                m = c.measure(sets, keys)
            except (ValueError, ZeroDivisionError, IndexError, KeyError):
                m = None
            if m is not None:
                m.context = label
                if m.n < 2 and m.verdict in (REPRODUCED, NOT_REPRODUCED):
                    m.verdict = SINGLE  # one realization: no standard error to judge the effect by
                ms.append(m)
        verdicts = {m.verdict for m in ms if m.verdict != NOT_IN_STUDY}
        if not verdicts:
            verdict = NOT_IN_STUDY
        elif len(verdicts) == 1:
            verdict = verdicts.pop()
        else:
            verdict = DEPENDS
        out.append(ClaimResult(c.id, c.figure, c.claim, c.definition, data.name, verdict, ms))
    return out
