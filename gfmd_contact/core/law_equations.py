"""Interface traction–separation equations as functions (seed Eqs. 2–3; reference-formulas §4.0).

Units: SI (see `gfmd_contact.core.conventions`): gaps Δn, Δt and lengths δn, δt in m, works of
separation φn, φt in J/m², tractions in Pa. T_n > 0 is tension; the law acts on
the body as t_z = T_n, t_x = T_t, with Δ = indenter − body.

The coupled law (seed Eq. 2) is *not* derivable from a potential
(∂T_n/∂Δt ≠ ∂T_t/∂Δn): solvers must work on forces, not on an energy.

The repulsive branch (Δn < 0) grows like |Δn| e^{|Δn|/δn}. Every function is
finite for Δn/δn ≥ −MAX_COMPRESSION; beyond that the exponential would leave
double precision and a `CompressionOverflowError` is raised instead of
returning inf/NaN.

The laws as objects built from a scene (what solvers and checks ask) are `gfmd_contact.core.laws`,
which re-exports these names.
"""

from __future__ import annotations

import numpy as np
from scipy.special import lambertw

#: largest compression Δn/δn (negative gap) the laws evaluate; e^{600} ≈ 4e260
MAX_COMPRESSION = 600.0


class CompressionOverflowError(FloatingPointError):
    """A gap so negative that the exponential repulsive branch would overflow."""


def _check_compression(delta_n, length_normal):
    worst = np.min(delta_n) / length_normal if np.size(delta_n) else 0.0
    if not np.isfinite(worst):
        raise CompressionOverflowError("non-finite normal gap passed to the cohesive law")
    if np.size(delta_n) and np.min(delta_n) < -MAX_COMPRESSION * length_normal:  # the product, as a caller forms Δn
        raise CompressionOverflowError(
            f"normal gap Δn = {worst:.3g} δn is beyond the law's range (Δn ≥ −{MAX_COMPRESSION:g} δn): "
            "the repulsive branch would overflow. The solver diverged or the load step is far too large."
        )


def traction_normal(delta_n, work_normal, length_normal):
    """Normal CZ traction T_n(Δn) = (φn/δn)(Δn/δn) e^{−Δn/δn} (seed Eq. 3), Pa.

    delta_n: gap Δn (m, array); work_normal: φn (J/m²); length_normal: δn (m).
    """
    delta_n = np.asarray(delta_n, dtype=float)
    _check_compression(delta_n, length_normal)
    s = delta_n / length_normal
    return (work_normal / length_normal) * s * np.exp(-s)


def stiffness_normal(delta_n, work_normal, length_normal):
    """dT_n/dΔn = (φn/δn²)(1 − Δn/δn) e^{−Δn/δn} (Pa/m) of `traction_normal`."""
    delta_n = np.asarray(delta_n, dtype=float)
    _check_compression(delta_n, length_normal)
    s = delta_n / length_normal
    return (work_normal / length_normal**2) * (1.0 - s) * np.exp(-s)


def potential_normal(delta_n, work_normal, length_normal):
    """V(Δn) = −φn (1 + Δn/δn) e^{−Δn/δn} (J/m²), with T_n = dV/dΔn and V(∞) = 0."""
    delta_n = np.asarray(delta_n, dtype=float)
    _check_compression(delta_n, length_normal)
    s = delta_n / length_normal
    return -work_normal * (1.0 + s) * np.exp(-s)


def traction_coupled(delta_n, delta_t, work_normal, length_normal, work_tangential, length_tangential):
    """Coupled CZ law (seed Eq. 2), returns (T_n, T_t) in Pa.

    T_n = (φn/δn)(Δn/δn) e^{−Δn/δn} e^{−Δt²/δt²}
    T_t = 2(φt/δt)(Δt/δt) e^{−Δn/δn} e^{−Δt²/δt²}
    Gaps Δn, Δt in m; φn, φt in J/m²; δn, δt in m. Δt = 0 reduces T_n to Eq. 3.
    """
    delta_n = np.asarray(delta_n, dtype=float)
    delta_t = np.asarray(delta_t, dtype=float)
    _check_compression(delta_n, length_normal)
    sn = delta_n / length_normal
    st = delta_t / length_tangential
    common = np.exp(-sn - st * st)
    t_n = (work_normal / length_normal) * sn * common
    t_t = 2.0 * (work_tangential / length_tangential) * st * common
    return t_n, t_t


def jacobian_coupled(delta_n, delta_t, work_normal, length_normal, work_tangential, length_tangential):
    """Tangent of the coupled law: (∂Tn/∂Δn, ∂Tn/∂Δt, ∂Tt/∂Δn, ∂Tt/∂Δt), Pa/m.

    Non-symmetric (∂Tn/∂Δt ≠ ∂Tt/∂Δn): the law has no potential.
    """
    delta_n = np.asarray(delta_n, dtype=float)
    delta_t = np.asarray(delta_t, dtype=float)
    _check_compression(delta_n, length_normal)
    dn, dt = length_normal, length_tangential
    sn, st = delta_n / dn, delta_t / dt
    common = np.exp(-sn - st * st)
    a = work_normal / dn**2
    b = 2.0 * work_tangential / dt**2
    dtn_dn = a * (1.0 - sn) * common
    dtn_dt = a * dn / dt * sn * (-2.0 * st) * common
    dtt_dn = -b * dt / dn * st * common
    dtt_dt = b * (1.0 - 2.0 * st * st) * common
    return dtn_dn, dtn_dt, dtt_dn, dtt_dt


def contact_gap_threshold(contact_tolerance, length_normal):
    """Gap Δtol (m) beyond which a cohesive node no longer counts as in contact.

    Δtol > δn solves T_n(Δtol) = contact_tolerance · φn/δn on the decaying branch,
    i.e. s e^{−s} = tol with s = Δtol/δn, s = −W₋₁(−tol) (Lambert W, branch −1).
    Requires 0 < contact_tolerance < 1/e (the peak of s e^{−s}).
    """
    if not 0.0 < contact_tolerance < np.exp(-1.0):
        raise ValueError(
            f"contact_tolerance = {contact_tolerance!r} must lie in (0, 1/e ≈ 0.368): "
            "it is a fraction of φn/δn below the law's peak traction φn/(e δn)"
        )
    s = -lambertw(-contact_tolerance, k=-1).real
    return s * length_normal


def jump_in_separation(stiffness, work_normal, length_normal):
    """Largest indenter separation δ_jump (m) at which a surface of normal stiffness k jumps into contact.

    stiffness k in Pa/m, work_normal φn in J/m², length_normal δn in m. The energy's
    Hessian is K + diag(∂T_n/∂Δn), and the law's slope ∂T_n/∂Δn = (φn/δn²)(1 − s)e^{−s}
    (s = Δn/δn) has its steepest softening −e^{−2}φn/δn² at s = 2. If
    k ≥ e^{−2}φn/δn² every state is stable, nothing jumps, and 0 is returned. Otherwise
    a flat surface on a spring k (the worst case: any other shape is stiffer) loses
    stability at the gap s*·δn where k = −∂T_n/∂Δn, i.e. (s* − 1)e^{−s*} = k δn²/φn,
    s* = 1 − W₋₁(−e k δn²/φn) > 2 (Lambert W, branch −1); its displacement there is
    u = T_n/k = δn s*/(s* − 1), so the indenter stands at δ_jump = δn s*²/(s* − 1).
    A run that starts closer (δ0 < δ_jump) may jump during its first step.
    """
    ratio = stiffness * length_normal**2 / work_normal
    if ratio >= np.exp(-2.0):
        return 0.0
    s = float(1.0 - lambertw(-np.e * ratio, k=-1).real)
    return s * s / (s - 1.0) * length_normal


#: e^{−s} is exactly 0 in double precision beyond this s
EXP_UNDERFLOW = 746.0


def attraction_cut(x):
    """s_c ≥ 1 with s_c e^{−s_c} = x: beyond Δn = s_c δn, |T_n| < x φn/δn (Eq. 3; s e^{−s} falls for s > 1).

    inf for x ≤ 0 (every node counts); 1 for x ≥ 1/e; at most EXP_UNDERFLOW, where T_n is exactly 0.
    Newton on s − ln s = ln(1/x), convex and rising for s > 1, from s = 2 ln(1/x) + 1 above the root:
    the iterates fall monotonically onto it.
    """
    if not x > 0:
        return np.inf
    if x >= np.exp(-1.0):
        return 1.0
    rhs = -np.log(x)
    s = 2.0 * rhs + 1.0
    for _ in range(200):
        step = (s - np.log(s) - rhs) / (1.0 - 1.0 / s)
        s -= step
        if step <= 1e-13 * s:
            break
    return float(min(max(s, 1.0), EXP_UNDERFLOW))
