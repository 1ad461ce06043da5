"""The process-zone resolution check (gfmd_contact.core.stickiness) is checked, not trusted: its limit is re-measured.

Study, scene and metric: `verification.studies.process_zone` (adhesive sinusoid, w = 7 J/m², δn = 0.1 nm,
l_pz = E* w/σ_max² = 0.93 nm; error = max over 8 loads of |Δp̄|/max|p̄| and |Δa_rel| against N = 8192).
The stored limit (verification/data/process_zone.json; the check's constant equals it) lies between the grids
N = 2048 (l_pz/l = 1.90) and N = 3072 (2.85) of this case. Re-measured here: the error at N = 2048
must exceed the 1 % that defines the limit and the check must warn there; at N = 3072 the error must
stay within 1 % and the check must not warn. A limit stored too low (a wrong data file, a unit
slip in l_pz such as the prefactor or a missing e²) or a check that does not read it fails here.
"""

from __future__ import annotations

from gfmd_contact.core import stickiness
from gfmd_contact.core.model import build_model
from verification import measured
from verification.studies import process_zone as pz

CASE = "stickiness/process-zone-resolution"
DELTA_N = 0.1e-9
BELOW, ABOVE = 2048, 3072


def _errors(nodes, reference):
    import numpy as np

    p, a = pz.curve(nodes, DELTA_N)
    p_ref, a_ref = reference
    return max(float(np.max(np.abs(p - p_ref)) / np.max(np.abs(p_ref))), float(np.max(np.abs(a - a_ref))))


def test_process_zone_limit_separates_the_grids(verification_record):
    limit = measured.value(pz.NAME, "ci", "min_process_zone_nodes")
    error_limit = measured.value(pz.NAME, "ci", "error_limit")
    assert stickiness.measured_process_zone_limit()[0] == limit  # the check reads the stored limit
    reference = pz.curve(pz.REFERENCE_NODES, DELTA_N)
    lpz = pz.process_zone(DELTA_N)
    rows = {}
    for n in (BELOW, ABOVE):
        ratio = lpz / (pz.LENGTH / n)
        warned = any(w.startswith("under-resolved process zone") for w in build_model(pz.scene(n, DELTA_N)).warnings)
        rows[n] = (ratio, _errors(n, reference), warned)
    (r_lo, e_lo, w_lo), (r_hi, e_hi, w_hi) = rows[BELOW], rows[ABOVE]
    verification_record(
        case=CASE, metric=f"max(|Δp̄|/max p̄, |Δa_rel|) at l_pz/l = {r_hi:.3g} (≥ limit {limit:.3g})", value=e_hi,
        tolerance=error_limit, methods=("gfmd-fire",),
        tolerance_source="the 1 % that defines the limit (verification.studies.process_zone)",
        resolution={"N": [BELOW, ABOVE], "reference_N": pz.REFERENCE_NODES, "lpz_nodes": [r_lo, r_hi],
                    "errors": [e_lo, e_hi], "warned": [w_lo, w_hi]},
        notes=f"below the limit (l_pz/l = {r_lo:.3g}) the error is {e_lo:.3g} and the check warns: {w_lo}")
    assert r_lo < limit <= r_hi
    assert e_lo > error_limit and w_lo, (e_lo, w_lo)
    assert e_hi <= error_limit and not w_hi, (e_hi, w_hi)
