"""e^x in plain arithmetic for numba loops: LLVM vectorizes a loop that uses it, where libm's exp is a scalar call.

Without Intel's SVML (not a dependency), ``np.exp`` in a numba loop is one libm call per element and keeps LLVM from
vectorizing the loop around it. `exp` here is the textbook reduction

    x = k ln 2 + r,  k = round(x / ln 2),  |r| ≤ ln 2 / 2,   e^x = 2^k · e^r,

with ln 2 split in two (Cody–Waite: k·LN2_HI is exact, so r keeps full precision up to |x| ≈ 745), e^r by its Taylor
polynomial to degree 13 (truncation r¹⁴/14! < 5e-18 relative) and 2^k read from a table. Within 1 ulp of numpy's
exp over the whole double range, subnormal results included (`tests/test_vector_exp.py`); 0 below `EXP_MIN`, +inf
above `EXP_MAX`, NaN for NaN. A loop that inlines it must not be compiled with the ``reassoc`` fast-math flag: that licenses LLVM to
regroup (x − k LN2_HI) − k LN2_LO into x − k (LN2_HI + LN2_LO), which loses the split (measured: 37 ulp on average,
109 at worst); the flags here (`STRICT_FLAGS`) allow fused multiply-adds only.
"""

from __future__ import annotations

import numpy as np

from .kernels import numba

#: the fast-math flags a loop that inlines `exp` may use: contractions (FMA) and signed zeros, no reassociation
STRICT_FLAGS = {"contract", "nsz"}
#: e^x rounds to 0 below this (the largest x whose e^x is below half the smallest subnormal, 2^−1075)
EXP_MIN = -745.1332191019412
#: e^x overflows to +inf above this (ln of the largest double)
EXP_MAX = 709.782712893384
LN2_HI = 6.93147180369123816490e-01  # ln 2's leading 32 bits: k · LN2_HI is exact for |k| < 2^21
LN2_LO = 1.90821492927058770002e-10  # ln 2 − LN2_HI
INV_LN2 = 1.44269504088896338700e00
#: 2^k for k = −1074 … 1023 (subnormal, then normal powers), read at k + 1074
POWERS_OF_TWO = np.ldexp(1.0, np.arange(-1074, 1024))

if numba is not None:
    _POWERS = POWERS_OF_TWO

    @numba.njit(inline="always", fastmath=STRICT_FLAGS)
    def exp(x):
        """e^x (module docstring); inline it into loops compiled with `STRICT_FLAGS`."""
        k = np.floor(x * INV_LN2 + 0.5)
        r = (x - k * LN2_HI) - k * LN2_LO
        p = 1.0 + r * (1.0 + r * (1.0 / 2 + r * (1.0 / 6 + r * (1.0 / 24 + r * (1.0 / 120 + r * (
            1.0 / 720 + r * (1.0 / 5040 + r * (1.0 / 40320 + r * (1.0 / 362880 + r * (1.0 / 3628800 + r * (
                1.0 / 39916800 + r * (1.0 / 479001600 + r * (1.0 / 6227020800)))))))))))))
        j = k if k >= -1074.0 else -1074.0  # in the table for every x, NaN included; out of range is handled below
        j = j if j <= 1023.0 else 1023.0
        p = p * 2.0 if k > 1023.0 else p  # k one past the table (x near EXP_MAX or EXP_MIN): p scaled exactly first,
        p = p * 0.5 if k < -1074.0 else p  # so the product rounds once
        y = p * _POWERS[int(j) + 1074]
        if x < EXP_MIN:
            y = 0.0
        if x > EXP_MAX:
            y = np.inf
        return y

    @numba.njit(fastmath=STRICT_FLAGS)  # not cached: tests inspect its assembly
    def exp_into(x, out):
        """out[i] = e^{x[i]} by `exp` (a vectorized loop; for tests and benchmarks)."""
        for i in range(x.size):
            out[i] = exp(x[i])
        return out
