"""Contact rules, GFMD vs FE, each method counting contact with its own code.

Study, scenes and metric: `verification.studies.contact_rules` (cohesive φn* = 0.01 and hard-wall sinusoid
on a layer, rules "traction-tolerance", "compressive", "gap" with contact_gap = 1; GFMD FIRE vs FE P2;
max over the load steps of |Δa_rel|, in nodes). Measured in verification/data/contact_rules.json
(regenerate: `python -m verification.studies.contact_rules --write`; `--full` for N = 64 … 512).

Tolerance: a_rel is quantised by 1/N, so the bound is in nodes: per (law, rule) the largest difference
measured over N = 64 … 512 (entry "full"), which does not grow with N (also asserted on the data): 0 nodes
for the cohesive law under every rule and for the hard wall under "gap", 2 for the hard wall's
compressive set (one node per contact edge whose traction is ~0 and whose sign the two discretisations
give differently; the seed's rule for the hard wall is that set).
"""

from __future__ import annotations

import pytest

from verification import measured
from verification.studies import contact_rules as cr

METHODS = ("gfmd-fire", "fe-p2")


def bound(law, rule):
    """Largest max |Δa_rel|·N measured over N = 64 … 512 (verification/data/contact_rules.json, entry "full")."""
    nodes, _ = cr.measured_nodes("full")
    return max(nodes[law][rule])


def source(law, rule):
    e = measured.entry(cr.NAME, "full")
    return (f"verification.studies.contact_rules (verification/data/contact_rules.json, {e['code_version']}, "
            f"{e['date']}): the largest difference over N = {e['values']['N']} for {law}, {rule!r}: "
            f"{bound(law, rule):g} nodes")


@pytest.mark.parametrize("law", cr.LAWS)
@pytest.mark.parametrize("rule", list(cr.RULES))
@pytest.mark.parametrize("n", [64, 128])
def test_contact_rule_gfmd_vs_fe(n, law, rule, verification_record):
    out = cr.compare(n, law, rule)
    tol = bound(law, rule)
    verification_record(case=f"contact-rules/{law}-sinusoid/{rule}", metric="max |Δa_rel| · N (nodes)",
                        value=out["nodes"], tolerance=tol, methods=METHODS, tolerance_source=source(law, rule),
                        resolution={"N": n, "D/L": 1, "elements": "P2"}, scene=cr.scene(n, law, rule), measured=tol)
    assert out["nodes"] <= tol + 1e-9
    assert out["a_gfmd"].max() > 0.3  # the rule counts a real contact, not an empty set on both sides


def test_contact_rule_difference_does_not_grow_with_n(verification_record):
    """The bound above rests on the data: the node count of the difference does not grow from N = 64 to 512."""
    nodes, ns = cr.measured_nodes("full")
    worst = {f"{law}/{rule}": values for law in nodes for rule, values in nodes[law].items()}
    grows = {k: v for k, v in worst.items() if v[-1] > v[0]}
    verification_record(case="contact-rules/resolution", metric="rules whose |Δa_rel|·N grows from N = 64 to 512",
                        value=len(grows), tolerance=0, methods=METHODS, resolution={"N": ns},
                        tolerance_source="verification/data/contact_rules.json entry 'full': the difference is a "
                                         "fixed number of edge nodes, i.e. |Δa_rel| ∝ 1/N")
    assert not grows, grows
