"""gfmd.gmres: restarted GMRES, fused modified Gram–Schmidt, a float32 basis at loose tolerances (the coupled
Newton's linear solver).

* it solves: on random nonsymmetric systems the true residual is ≤ rtol ‖b‖ where it says so (info 0), and x is
  within ‖A⁻¹‖ rtol ‖b‖ of numpy's solve;
* it is scipy's iteration: the same verdict and the same number of products (± 1) as scipy.sparse.linalg.gmres on
  the same system, restart and cycles;
* it says when it did not converge (info = cycles run, the residual above the tolerance), and handles b = 0 and a
  Krylov space that closes early (A = I: one product, exact).
"""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from scipy.sparse.linalg import LinearOperator, gmres as scipy_gmres

from gfmd.gmres import gmres


def system(n, seed, spread):
    """A = I + spread · R/‖R‖₂ (its field of values in the disk |z − 1| ≤ spread), b random."""
    rng = np.random.default_rng(seed)
    r = rng.standard_normal((n, n))
    a = np.eye(n) + spread * r / np.linalg.norm(r, 2)
    return a, rng.standard_normal(n)


def counted(a):
    calls = [0]

    def matvec(x):
        calls[0] += 1
        return a @ x

    return matvec, calls


@settings(deadline=None, max_examples=60)
@given(n=st.integers(1, 120), seed=st.integers(0, 2**32 - 1), spread=st.floats(0.0, 0.5),
       rtol=st.sampled_from([1e-2, 1e-6, 1e-10]), restart=st.integers(1, 60))
def test_gmres_solves_to_its_tolerance(n, seed, spread, rtol, restart):
    """GMRES(m) converges for every m where A's symmetric part is definite (Elman: with |z − 1| ≤ 0.5 on the field
    of values, each product cuts the residual by ≥ √(1 − 0.5²/1.5²) = 0.94, so 1 000 cycles reach 1e-10 even at
    m = 1)."""
    a, b = system(n, seed, spread)
    matvec, _ = counted(a)
    x, info = gmres(matvec, b, rtol, restart, 1000)
    assert info == 0
    b_norm = np.linalg.norm(b)
    assert np.linalg.norm(b - a @ x) <= rtol * b_norm
    exact = np.linalg.solve(a, b)
    assert np.linalg.norm(x - exact) <= 1.01 * np.linalg.norm(np.linalg.inv(a), 2) * rtol * b_norm


@settings(deadline=None, max_examples=40)
@given(n=st.integers(5, 150), seed=st.integers(0, 2**32 - 1), spread=st.floats(0.1, 0.8),
       rtol=st.sampled_from([1e-3, 1e-8]), restart=st.sampled_from([5, 20, 60]))
def test_gmres_is_scipys_iteration(n, seed, spread, rtol, restart):
    a, b = system(n, seed, spread)
    ours, ours_calls = counted(a)
    theirs, their_calls = counted(a)
    x, info = gmres(ours, b, rtol, restart, 5)
    xs, info_s = scipy_gmres(LinearOperator((n, n), matvec=theirs, dtype=float), b, rtol=rtol, restart=restart,
                             maxiter=5)
    assert (info == 0) == (info_s == 0)
    assert abs(ours_calls[0] - their_calls[0]) <= 1
    if info == 0:
        assert np.linalg.norm(x - xs) <= 2.0 * np.linalg.norm(np.linalg.inv(a), 2) * rtol * np.linalg.norm(b)


def test_gmres_says_when_it_did_not_converge():
    """A spread spectrum (1 … 1e4) needs far more than 2 cycles of 3 products: info 2, residual above tolerance."""
    n = 200
    a = np.diag(np.logspace(0, 4, n))
    b = np.ones(n)
    x, info = gmres(lambda v: a @ v, b, 1e-8, 3, 2)
    assert info == 2
    assert np.all(np.isfinite(x))
    assert np.linalg.norm(b - a @ x) > 1e-8 * np.linalg.norm(b)


@pytest.mark.parametrize("n", [1, 7, 64])
def test_gmres_edge_cases(n):
    x, info = gmres(lambda v: 3.0 * v, np.zeros(n), 1e-8, 10, 3)
    assert info == 0 and np.all(x == 0)
    b = np.arange(1.0, n + 1)
    matvec, calls = counted(np.eye(n))
    x, info = gmres(matvec, b, 1e-12, 10, 3)  # A = I: the first Krylov vector is the solution (breakdown)
    assert info == 0
    np.testing.assert_allclose(x, b, rtol=1e-14)
    assert calls[0] == 2  # A v_0, then the true residual


def test_gmres_keeps_its_basis_orthogonal():
    """A symmetric matrix with a spectrum over 5 decades (n = 100, no restart, rtol 1e-10, a float64 basis): the
    Arnoldi basis loses orthogonality under one classical Gram–Schmidt pass, and GMRES then needs ≈ 1.5× the products;
    modified Gram–Schmidt needs scipy's count (± 1) and reaches the same residual."""
    n = 100
    rng = np.random.default_rng(0)
    q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    a = q @ np.diag(np.logspace(0, 5, n)) @ q.T
    b = rng.standard_normal(n)
    ours, ours_calls = counted(a)
    theirs, their_calls = counted(a)
    x, info = gmres(ours, b, 1e-10, n, 3)
    scipy_gmres(LinearOperator((n, n), matvec=theirs, dtype=float), b, rtol=1e-10, restart=n, maxiter=3)
    assert info == 0
    assert np.linalg.norm(b - a @ x) <= 1e-10 * np.linalg.norm(b)
    assert abs(ours_calls[0] - their_calls[0]) <= 1


@pytest.mark.parametrize("single", [True, False])
@pytest.mark.parametrize("rtol", [1e-1, 1e-3])
def test_gmres_single_and_double_basis_reach_the_tolerance(single, rtol):
    """The float32 basis (the default for rtol ≥ SINGLE_BASIS_RTOL, the Newton steps' forcing) and the float64 one
    both reach the tolerance, in the same number of products (± 1) on a system of the Newton steps' kind (a
    spectrum over 3 decades, restarts)."""
    n = 3000
    rng = np.random.default_rng(7)
    q, _ = np.linalg.qr(rng.standard_normal((n, 60)))
    a = np.eye(n) + q @ np.diag(np.logspace(0, 3, 60)) @ q.T + 0.2 * rng.standard_normal((n, n)) / np.sqrt(n)
    b = rng.standard_normal(n)
    matvec, calls = counted(a)
    x, info = gmres(matvec, b, rtol, 20, 10, single=single)
    assert info == 0
    assert np.linalg.norm(b - a @ x) <= rtol * np.linalg.norm(b)
    reference, ref_calls = counted(a)
    gmres(reference, b, rtol, 20, 10, single=False)
    assert abs(calls[0] - ref_calls[0]) <= 1


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_projection_backends_agree(dtype):
    """The fused modified Gram–Schmidt (numba) and the numpy loop: the same coefficients and remainder, which is
    orthogonal to the basis rows (to the basis's precision)."""
    from gfmd import gmres as module

    rng = np.random.default_rng(3)
    n, j = 500, 6
    q, _ = np.linalg.qr(rng.standard_normal((n, j + 1)))
    basis = np.zeros((10, n), dtype=dtype)
    basis[:j + 1] = q.T
    w0 = rng.standard_normal(n)
    results = []
    for project in (module._project_numpy, module._project_fused):
        w = w0.copy()
        results.append((project(basis, j, w), w))
    tol = 1e-12 if dtype == np.float64 else 1e-5
    np.testing.assert_allclose(results[0][0], results[1][0], rtol=tol, atol=tol)
    np.testing.assert_allclose(results[0][1], results[1][1], atol=tol * np.linalg.norm(w0))
    assert np.max(np.abs(basis[:j + 1].astype(float) @ results[1][1])) <= tol * np.linalg.norm(w0)
    np.testing.assert_allclose(results[1][0], basis[:j + 1].astype(float) @ w0, rtol=tol, atol=tol)


@settings(deadline=None, max_examples=40)
@given(n=st.integers(5, 150), seed=st.integers(0, 2**32 - 1), spread=st.floats(0.1, 0.8),
       rtol=st.sampled_from([1e-1, 1e-3, 1e-8]), restart=st.sampled_from([5, 20, 60]))
def test_trusted_estimate_saves_the_true_residuals_product(n, seed, spread, rtol, restart):
    """trust_estimate: the same iterates, one product fewer where the first cycle converges (the final true
    residual's), and a true residual that exceeds rtol ‖b‖ by no more than the estimate's rounding (the basis's
    unit round-off × ‖A‖₂ ‖x‖, × the products, a bound of the Arnoldi relation's error, not a fitted number)."""
    a, b = system(n, seed, spread)
    plain, plain_calls = counted(a)
    trusted, trusted_calls = counted(a)
    x0, info0 = gmres(plain, b, rtol, restart, 5)
    x1, info1 = gmres(trusted, b, rtol, restart, 5, trust_estimate=True)
    assert info0 == info1
    np.testing.assert_array_equal(x0, x1)
    if info1 == 0:
        assert trusted_calls[0] == plain_calls[0] - 1
        eps = np.finfo(np.float32 if rtol >= 1e-4 else np.float64).eps
        slack = trusted_calls[0] * eps * np.linalg.norm(a, 2) * np.linalg.norm(x1)
        assert np.linalg.norm(b - a @ x1) <= rtol * np.linalg.norm(b) + slack


@pytest.mark.parametrize("rtol,restart", [(1e-3, 60), (1e-8, 4)])
def test_extras_are_the_solutions_parts(rtol, restart):
    """extras: matvec's linear parts e(v) (here B v and C v), summed with GMRES's coefficients, are e(x) of the
    solution it returns (to round-off: ‖e(x) − B x‖ ≤ products × eps × ‖B‖₂ ‖x‖), with and without restarts, and the
    verdict and x are the plain solve's."""
    a, b = system(90, 11, 0.6)
    rng = np.random.default_rng(5)
    parts = rng.standard_normal((2, 90, 90))
    calls = [0]

    def matvec(v):
        calls[0] += 1
        return a @ v, parts[0] @ v, parts[1] @ v

    x, info, (ex, fx) = gmres(matvec, b, rtol, restart, 50, extras=2)
    x0, info0 = gmres(lambda v: a @ v, b, rtol, restart, 50)
    assert info == info0 == 0
    np.testing.assert_array_equal(x, x0)
    for part, value in zip(parts, (ex, fx)):
        eps = np.finfo(np.float32 if rtol >= 1e-4 else np.float64).eps
        assert np.linalg.norm(value - part @ x) <= calls[0] * eps * np.linalg.norm(part, 2) * np.linalg.norm(x)
    x, info, extras = gmres(matvec, np.zeros(90), rtol, restart, 5, extras=2)
    assert info == 0 and np.all(x == 0) and extras == [0.0, 0.0]
