"""Sparse FE path (`reference.fem.sparse`) against the dense condensed path it replaces at large N.

Both paths solve the same equations with the same Newton / trust-region / pseudo-transient
continuation code (`SurfaceProblem.newton`, `.descend`, `.ptc`); only the linear algebra
differs (dense Schur complement S and dense LU vs SuperLU on the full reduced
system). So the Newton iterates agree to round-off, the iteration counts and
fallback steps must be identical, and the converged states agree far below the
solver tolerance.

Measured (this module's scenes, max relative difference over p, a_rel, g, g_r, δ and
every recorded field u_z, u_x, gap, t_n, t_t, dense vs sparse / sparse-lagged):

    scene                               N    dense–sparse   dense–lagged   fallback steps   its
    normal CZ, φn* = 0.01, 10 steps     16   2.8e-14        2.8e-14        none             61
    coupled CZ, c = 0.5, ν = 0.3        16   7.0e-14        1.0e-13        none             39
    jump-in, φn* = 0.15, 5 steps         8   (not run)      1.8e-14        [3] (PTC)        1029

Bound: RELATIVE = 1e-8, the FE reference's acceptance level ("to solver
tolerance", 1e-10 in max |R/W|/p_ref, times a margin of 100 for the tangent's
conditioning: cond(S + B) = 46 (normal) and 230 (coupled) at a random state of
these scenes, measured); the measured differences are 10⁵× below it. A wrong
scatter index, a dropped law term or a wrong PTC shift gives O(1) differences.
The jump-in case runs only the lagged variant: the direct one needs a SuperLU
factorization per PTC iteration (~1000 of them, 11 s at N = 16).

Operator level (2048 reduced DOFs, random vector / state; measured relative
difference to the dense result): S·v 5.6e-16 / 7.9e-16, tangent solves
7.0e-15–2.3e-14 (with and without the PTC shift), interior reconstruction
8.0e-16 / 6.6e-16 (normal / coupled). Bound OPERATOR = 1e-11: cond(S + B) ≤ 230
times 1e-14 (round-off of a 2048-DOF solve) is ≤ 3e-12, ×3.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp

from gfmd_contact.core import surfaces
from reference import fem
from reference.fem import sparse
from reference.fem.solver import SurfaceProblem
from verification.scenes import cohesive_sinusoid as normal_scene
from verification.scenes import coupled_sinusoid as coupled_scene

RELATIVE = 1e-8  # converged fields, see docstring
OPERATOR = 1e-11  # S·v and tangent solves, see docstring


def _relative(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(a)), 1e-300))


def _worst_difference(dense, other):
    curve = max(_relative(dense.curve[k], other.curve[k]) for k in ("p", "a_rel", "g", "g_r", "delta"))
    fields = max(_relative(dense.fields[k][f], other.fields[k][f]) for k in dense.fields for f in dense.fields[k])
    return max(curve, fields)


def _assert_same_run(dense, other):
    assert dense.all_converged and other.all_converged, (dense.messages, other.messages)
    assert list(dense.fields) == list(other.fields)
    assert list(dense.diagnostics["fallback_steps"]) == list(other.diagnostics["fallback_steps"])
    assert dense.messages == other.messages
    worst = _worst_difference(dense, other)
    assert worst < RELATIVE, f"dense and sparse runs differ by {worst:.3g} (relative), bound {RELATIVE}"


SCENES = {
    "normal": lambda: normal_scene(16).replace(**{"loading.steps": 10}),
    "coupled": lambda: coupled_scene(16, 0.3),
}


@pytest.mark.parametrize("name", sorted(SCENES))
def test_sparse_run_reproduces_dense(name):
    sc = SCENES[name]()
    dense = fem.run_realization(sc, linear="dense")
    for linear in ("sparse", "sparse-lagged"):
        other = fem.run_realization(sc, linear=linear)
        assert isinstance(other.diagnostics["problem"], sparse.SparseSurfaceProblem)
        _assert_same_run(dense, other)
        if linear == "sparse":  # exact linear solves: the same Newton iterates
            assert np.array_equal(dense.curve["iterations"], other.curve["iterations"])
    assert other.diagnostics["problem"].stats["gmres_solves"] > 0, "lagged mode never used GMRES"


def test_sparse_reproduces_dense_pseudo_transient_fallback():
    """Jump into contact (φn* = 0.15): Newton fails at step 3 and both paths fall back to PTC."""
    sc = normal_scene(8).replace(**{"interface.phi_n_star": 0.15, "loading.initial_separation": 10e-9,
                                    "loading.final_penetration": 0.0, "loading.steps": 5})
    dense = fem.run_realization(sc, linear="dense")
    assert dense.diagnostics["fallback_steps"] == [3], dense.messages  # the scene must exercise the fallback
    other = fem.run_realization(sc, linear="sparse-lagged")
    _assert_same_run(dense, other)


def _problems(sc, order=2):
    h = surfaces.profile(sc.surface, 0)
    return SurfaceProblem(sc, h, order=order), sparse.SparseSurfaceProblem(sc, h, order=order)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_schur_operator_and_tangent_solves_match_dense(name):
    sc = SCENES[name]()
    dense, sparse_problem = _problems(sc)
    rng = np.random.default_rng(1)
    n = dense.S.shape[0]
    v = rng.standard_normal(n)
    assert _relative(dense.S @ v, sparse_problem.S @ v) < OPERATOR
    # a state in the interaction zone: gaps of order δn
    z_ind = sparse_problem.h_surface - sparse_problem.h_surface.min() + 1e-9
    u = 0.3e-9 * rng.standard_normal(n)
    for shift in (None, 1e9 * dense.wt):
        jd = dense.jacobian(u, z_ind, shift=shift)
        js = sparse_problem.jacobian(u, z_ind, shift=shift)
        assert _relative(dense.solve_linear(jd, v), sparse_problem.solve_linear(js, v)) < OPERATOR
    # interior reconstruction (used by the export and for u_x of the normal law)
    assert _relative(dense.solve_interior(v), sparse_problem.solve_interior(v)) < OPERATOR


def _stability_states(problem):
    """Surface states from unstable (gaps in the soft zone) to stable: (u, z_ind) pairs."""
    z_ind = problem.h_surface - problem.h_surface.min() + 1e-9
    n = problem.S.shape[0]
    x = 2 * np.pi * problem.cell.surface_x / problem.cell.length
    for stretch in np.linspace(0.0, 1e-9, 6):  # u_z up: the gap closes from 1 δn towards 0
        for slip in ((0.0, 0.5e-9, 1.5e-9) if problem.tangential else (0.0,)):
            u = np.zeros(n)
            u[-problem.ns:] = stretch
            if problem.tangential:
                u[:problem.ns] = slip * np.sin(x)  # tangential gap: skew tangent, complex eigenvalues
            yield u, z_ind


@pytest.mark.parametrize("name", sorted(SCENES))
def test_stability_check_matches_dense(name):
    """φn* = 0.05: stretched states are unstable, closer ones stable; sparse and dense verdicts agree.

    Coupled law: the sparse eigenvalue test (Bendixson box + shift-invert ARPACK) is also
    compared with the sign of min Re λ of all dense eigenvalues of W^-½JW^-½ directly, since
    at these states sym(J) is often indefinite.
    """
    sc = SCENES[name]().replace(**{"interface.phi_n_star": 0.05})
    dense, sparse_problem = _problems(sc)
    verdicts = set()
    for u, z_ind in _stability_states(sparse_problem):
        verdict = dense.stable(u, z_ind)
        assert sparse_problem.stable(u, z_ind) == verdict
        verdicts.add(verdict)
        if dense.tangential:
            J = dense.jacobian(u, z_ind)
            eig = scipy.linalg.eigvals(J / np.sqrt(np.outer(dense.wt, dense.wt)))
            assert sparse_problem._eigenvalues_positive(u, z_ind) == bool(np.min(eig.real) > 0)
    assert verdicts == {True, False}, "the states must include stable and unstable ones"


def test_positive_definite_counts_inertia():
    rng = np.random.default_rng(0)
    a = sp.random(60, 60, density=0.1, random_state=1)
    spd = (a @ a.T + 0.5 * sp.eye(60)).tocsc()
    assert sparse.positive_definite(spd)
    eig = np.linalg.eigvalsh(spd.toarray())
    for shift in (0.9 * eig[0], 1.1 * eig[0], 0.5 * (eig[3] + eig[4])):
        m = (spd - shift * sp.eye(60)).tocsc()
        assert sparse.positive_definite(m) == bool(np.all(np.linalg.eigvalsh(m.toarray()) > 0)), shift
    assert not sparse.positive_definite(sp.csc_matrix(np.diag(rng.random(5) * [1, 1, 0, 1, 1])))


def test_singular_tangent_raises_linalg_error():
    with pytest.raises(scipy.linalg.LinAlgError, match="singular"):
        sparse._factor(sp.csc_matrix(np.diag([1.0, 0.0, 2.0])))


def test_choose_linear():
    assert sparse.choose_linear("auto", sparse.DENSE_MAX_NODES) == "dense"
    assert sparse.choose_linear("auto", 2 * sparse.DENSE_MAX_NODES) == "sparse"
    assert sparse.choose_linear("auto", sparse.DENSE_MAX_NODES, components=2) == "sparse"  # coupled: 2N unknowns
    assert sparse.choose_linear("sparse", 16) == "sparse"
    with pytest.raises(ValueError, match="linear = 'lu'"):
        sparse.choose_linear("lu", 16)
