"""The coupled Newton's forcing rule (`gfmd.coupled_krylov.forcing`, `eisenstat_walker`): GMRES's relative
tolerance min(FORCING, max(η, FORCING_MIN, 0.3 tolerance / residual)), η by Eisenstat & Walker's choice 2."""

import pytest

from gfmd.coupled_krylov import EW_ALPHA, EW_GAMMA, FORCING, FORCING_MIN, eisenstat_walker, forcing


def test_the_first_solve_is_loose():
    assert eisenstat_walker(0.3) == FORCING
    assert forcing(1e-8, 0.3, eisenstat_walker(0.3)) == FORCING


@pytest.mark.parametrize("ratio", [0.5, 0.1, 0.03, 1e-3])
def test_eta_follows_the_residual_ratio(ratio):
    """η = γ ratio^α, capped at FORCING: linear convergence (ratio 0.5) keeps the loosest solve, quadratic
    convergence (ratio 1e-3) tightens it down to the floor."""
    eta = eisenstat_walker(ratio * 1e-2, 1e-2)
    assert eta == pytest.approx(min(FORCING, EW_GAMMA * ratio**EW_ALPHA))
    assert forcing(1e-8, ratio * 1e-2, eta) == pytest.approx(max(eta, FORCING_MIN))


def test_no_accuracy_beyond_the_stop():
    """Near the tolerance the solve needs only 0.3 tolerance / residual, whatever η says."""
    tolerance, residual = 1e-8, 2e-8
    assert forcing(tolerance, residual, 0.0) == FORCING  # 0.3 · 1e-8 / 2e-8 = 0.15, capped
    assert forcing(tolerance, 1e-6, 1e-5) == pytest.approx(max(FORCING_MIN, 0.3 * tolerance / 1e-6))
