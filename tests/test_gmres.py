"""gfmd.gmres against scipy.sparse.linalg.gmres: the same info, products and solution (to the tolerance) on
random well- and ill-conditioned non-symmetric systems, with and without a preconditioner."""

import numpy as np
import pytest
from scipy.sparse.linalg import LinearOperator, gmres as scipy_gmres

from gfmd.gmres import gmres

N = 120


def _system(kind, seed):
    """(A, b): a random non-symmetric matrix of the kind named, and a right-hand side."""
    rng = np.random.default_rng(seed)
    if kind == "well":  # eigenvalues clustered around 1
        a = np.eye(N) + 0.3 * rng.standard_normal((N, N)) / np.sqrt(N)
    elif kind == "ill":  # condition number ~1e4, non-normal: GMRES needs several restart cycles
        a = np.diag(np.geomspace(1.0, 1e4, N)) + 0.05 * np.triu(rng.standard_normal((N, N)), 1)
    else:  # "indefinite": eigenvalues on both sides of 0, GMRES stagnates
        a = np.diag(np.linspace(-1.0, 1.0, N) + 1e-3) + 0.1 * rng.standard_normal((N, N)) / np.sqrt(N)
    return a, rng.standard_normal(N)


def _counted(a):
    calls = []

    def matvec(v):
        calls.append(1)
        return a @ v
    return matvec, calls


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("kind, rtol, restart, cycles, expected", [
    ("well", 1e-10, 10, 5, 0), ("ill", 1e-6, 60, 8, 0), ("ill", 1e-3, 30, 5, 5), ("indefinite", 1e-8, 20, 3, 3)])
def test_gmres_matches_scipy(kind, rtol, restart, cycles, expected, seed):
    a, b = _system(kind, seed)
    ours, ours_calls = _counted(a)
    theirs, their_calls = _counted(a)
    x, info = gmres(ours, b, rtol, restart, cycles)
    x_ref, info_ref = scipy_gmres(LinearOperator((N, N), matvec=theirs, dtype=float), b, rtol=rtol,
                                  restart=restart, maxiter=cycles)
    assert info == info_ref == expected
    assert len(ours_calls) == len(their_calls)
    residual = np.linalg.norm(b - a @ x)
    if info == 0:
        assert residual <= rtol * np.linalg.norm(b)
        # both solutions meet the tolerance: they differ by at most A⁻¹ of two residuals
        bound = np.linalg.norm(np.linalg.inv(a), 2) * 2 * rtol * np.linalg.norm(b)
        assert np.linalg.norm(x - x_ref) <= bound
    else:  # the same iteration: the same inexact answer, to round-off amplified by the cycles
        assert residual > rtol * np.linalg.norm(b)
        assert residual == pytest.approx(np.linalg.norm(b - a @ x_ref), rel=1e-6)


@pytest.mark.parametrize("kind", ["well", "ill"])
def test_gmres_left_preconditioned_matches_scipy(kind):
    a, b = _system(kind, 7)
    d = np.diag(a).copy()
    x, info = gmres(lambda v: a @ v, b, 1e-9, 25, 10, psolve=lambda v: v / d)
    m = LinearOperator((N, N), matvec=lambda v: v / d, dtype=float)
    x_ref, info_ref = scipy_gmres(LinearOperator((N, N), matvec=lambda v: a @ v, dtype=float), b, M=m,
                                  rtol=1e-9, restart=25, maxiter=10)
    assert info == info_ref == 0
    assert np.linalg.norm(b - a @ x) <= 1e-9 * np.linalg.norm(b)
    assert np.linalg.norm(x - x_ref) <= 2e-9 * np.linalg.norm(b) * np.linalg.norm(np.linalg.inv(a), 2)


def test_gmres_zero_rhs_and_bad_shape():
    x, info = gmres(lambda v: v, np.zeros(5), 1e-8, 5, 2)
    assert info == 0 and not x.any()
    with pytest.raises(ValueError, match="b must be 1-D"):
        gmres(lambda v: v, np.zeros((2, 2)), 1e-8, 5, 2)
