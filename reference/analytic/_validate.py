"""Input checks shared by the analytic modules (private).

Every public function of `reference.analytic` rejects out-of-range input with
a ValueError that names the offending argument, instead of returning NaN.
"""

import numpy as np


def _as_float_array(name, value):
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a real number or array, got {value!r}") from exc
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return arr


def positive(name, value):
    """Return `value` as float (array) after checking it is finite and > 0."""
    arr = _as_float_array(name, value)
    if np.any(arr <= 0.0):
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return arr


def nonnegative(name, value):
    """Return `value` as float (array) after checking it is finite and >= 0."""
    arr = _as_float_array(name, value)
    if np.any(arr < 0.0):
        raise ValueError(f"{name} must be >= 0, got {value!r}")
    return arr


def finite(name, value):
    """Return `value` as float (array) after checking it is finite."""
    return _as_float_array(name, value)


def in_range(name, value, lower, upper, *, lower_open=False, upper_open=False):
    """Return `value` as float (array) after checking lower <= value <= upper.

    `lower_open` / `upper_open` make the corresponding bound strict.
    """
    arr = _as_float_array(name, value)
    bad_low = arr <= lower if lower_open else arr < lower
    bad_high = arr >= upper if upper_open else arr > upper
    if np.any(bad_low) or np.any(bad_high):
        lb = "(" if lower_open else "["
        ub = ")" if upper_open else "]"
        raise ValueError(f"{name} must lie in {lb}{lower:g}, {upper:g}{ub}, got {value!r}")
    return arr


def scalar(arr):
    """0-d arrays -> Python float; other arrays unchanged."""
    arr = np.asarray(arr)
    return float(arr) if arr.ndim == 0 else arr
