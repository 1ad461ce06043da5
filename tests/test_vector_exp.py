"""gfmd.vector_exp: e^x in vectorizable arithmetic, against numpy's exp (libm quality, ≤ 1 ulp)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gfmd import kernels

pytestmark = pytest.mark.skipif(kernels.numba is None, reason="numba not installed")


def _exp(x):
    from gfmd.vector_exp import exp_into

    x = np.ascontiguousarray(x, dtype=float)
    return exp_into(x, np.empty_like(x))


def _within_one_ulp(x):
    with np.errstate(over="ignore"):
        ref = np.exp(x)
    got = _exp(x)
    finite = np.isfinite(ref)
    assert np.array_equal(got[~finite], ref[~finite], equal_nan=True)
    if not finite.any():
        return
    err = np.abs(got[finite] - ref[finite])
    ulp = np.spacing(ref[finite])  # one unit in the last place of the reference (subnormal spacing included)
    worst = int(np.argmax(err / ulp))
    assert err[worst] <= ulp[worst], (x[finite][worst], got[finite][worst], ref[finite][worst])


def test_every_double_range_within_one_ulp():
    """The whole range, both ends: the table's last powers (k = 1024 and −1075 scale p first), the subnormal results,
    the flush to 0 below EXP_MIN and the overflow above EXP_MAX."""
    from gfmd.vector_exp import EXP_MAX, EXP_MIN

    x = np.r_[np.linspace(-760.0, 720.0, 2_000_001), np.nextafter(EXP_MIN, [-np.inf, np.inf]),
              np.nextafter(EXP_MAX, [-np.inf, np.inf]), EXP_MIN, EXP_MAX, 0.0, -0.0]
    _within_one_ulp(x)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(allow_nan=True, allow_infinity=True, width=64), min_size=1, max_size=64))
def test_any_doubles_within_one_ulp(xs):
    _within_one_ulp(np.array(xs))


def test_special_values():
    got = _exp(np.array([np.nan, np.inf, -np.inf, -1e300, 1e300, 0.0]))
    assert np.isnan(got[0]) and got[1] == np.inf and got[2] == 0.0 and got[3] == 0.0 and got[4] == np.inf
    assert got[5] == 1.0


def test_no_libm_call_in_the_loop():
    """The point of the module: the loop that inlines `exp` calls no libm exp (which keeps LLVM from vectorizing)."""
    from gfmd.vector_exp import exp_into

    _exp(np.zeros(8))
    asm = exp_into.inspect_asm(exp_into.signatures[0])
    assert "pd" in asm  # packed (or scalar) double arithmetic was emitted: the listing is the kernel's
    assert not [line for line in asm.splitlines() if "$exp" in line or "exp@" in line]
