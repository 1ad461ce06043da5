"""Differences between two results, and observed orders (dimensionless)."""

from __future__ import annotations

import numpy as np


def worst(values):
    """The largest of `values`, NaN if any of them is NaN (Python's max drops a NaN unless it comes
    first, so a failed measurement could pass as a small error)."""
    v = np.asarray(list(values), float)
    if v.size == 0:
        raise ValueError("worst() of no values")
    return float(np.max(v))


def worst_signed(values):
    """The value of largest magnitude, sign kept; NaN if any is NaN."""
    v = np.asarray(list(values), float)
    if v.size == 0:
        raise ValueError("worst_signed() of no values")
    return float(np.nan if np.isnan(v).any() else v[np.argmax(np.abs(v))])


def relative_l2(a, b, reference=None):
    """‖a − b‖₂ / ‖reference‖₂ (reference defaults to a); 0 if both are zero, inf if only the reference is."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    ref = a if reference is None else np.asarray(reference, float)
    num, den = float(np.linalg.norm(a - b)), float(np.linalg.norm(ref))
    if den == 0:
        return 0.0 if num == 0 else float("inf")
    return num / den


def field_difference(result, reference, name, steps=None):
    """Max over `steps` (default: `result`'s recorded field steps) of ‖result − reference‖₂/‖reference‖₂
    of field `name`."""
    steps = result.fields if steps is None else steps
    return worst(relative_l2(result.fields[k][name], reference.fields[k][name], reference.fields[k][name])
                 for k in steps)


def curve_difference(result, reference, column):
    """max_k |result − reference| / max_k |reference| of a load-curve column."""
    ref = np.asarray(reference.curve[column], float)
    return float(np.max(np.abs(np.asarray(result.curve[column], float) - ref)) / np.max(np.abs(ref)))


def max_abs_difference(result, reference, column="a_rel"):
    """max_k |result − reference| of a load-curve column (absolute; a_rel by default)."""
    return float(np.max(np.abs(np.asarray(result.curve[column], float) - np.asarray(reference.curve[column], float))))


def fitted_order(h, error):
    """Least-squares slope of log(error) vs log(h) over the finite positive points; NaN if < 2."""
    h, e = np.asarray(h, float), np.asarray(error, float)
    ok = np.isfinite(h) & np.isfinite(e) & (h > 0) & (e > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(h[ok]), np.log(e[ok]), 1)[0])


def observed_orders(nodes, errors):
    """Observed orders log(e_i/e_{i+1}) / log(N_{i+1}/N_i) between neighbouring resolutions."""
    return [float(np.log(a / b) / np.log(n1 / n0)) for a, b, n0, n1 in zip(errors, errors[1:], nodes, nodes[1:])]


def worst_refinement_ratio(errors):
    """The smallest e_i / e_{i+1} between neighbouring resolutions (the worst measured convergence step)."""
    return min(float(a / b) for a, b in zip(errors, errors[1:]))
