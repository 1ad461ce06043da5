"""The interface-law protocol: what every GFMD algorithm, preconditioner and diagnostic may ask a law.

A law object (built from the scene by `gfmd_contact.core.laws.law_from_scene`, through
`gfmd_contact.core.law_registry`) answers the members below and nothing else is asked of it: no caller
tests which law it is or reads one law's own parameters. Units SI, signs of
`gfmd_contact.core.conventions` (Δn = indenter − body gap, T_n > 0 tensile, acting on the body as t_z = T_n).

Equations (not for a pure constraint, ``constraint`` with no attraction: the hard wall)
    potential(Δn)            energy per area V(Δn) (J/m²), T_n = dV/dΔn, where ``has_potential``
    tractions(Δn, Δt)        (T_n, T_t) (Pa)
    tangent(Δn, Δt)          (∂Tn/∂Δn, ∂Tn/∂Δt, ∂Tt/∂Δn, ∂Tt/∂Δt) (Pa/m)
What the algorithms choose by
    constraint               Δn ≥ 0 is kept by projection (a wall); tractions are the attraction only
    has_potential            T = ∇V: the energy methods (NCG, the FE's line search) apply
    tangential               coupled in normal and tangential gaps, T_t(Δn, Δt) (no potential in general)
    adhesive                 the law carries tension (the start and resolution checks apply)
    nodal_form               None, or a (family, parameters) tuple naming a closed form for which a method
                             has a fused kernel ("exponential": seed Eq. 3, "coupled exponential": Eq. 2);
                             a method falls back to tractions/tangent for any other law
    normal_only()            the law at Δt ≡ 0 as a normal-only law (the frictionless reduction)
Scalars (SI)
    length_scale             the shortest length over which the tractions change (m)
    length_normal            the normal law's length (m): resolution and start checks, the gap rule's unit
    initial_stiffness        (k_t, k_n) at Δ = 0 (Pa/m): the interface stiffness in the dynamics' mass
    curvature_scale          a node's stiffness in contact (Pa/m) the two-level preconditioner measures stiff
                             nodes against; None where the law vouches for none (the NCG keeps K⁻¹)
    far_reach(t)             s_c: |T_n| ≤ t (Pa) for Δn ≥ s_c·length_scale (inf: never)
    check_gaps(Δn)           raise `gfmd_contact.core.law_equations.CompressionOverflowError` for gaps out of range
    peak_traction            largest tensile T_n (Pa)
    work_of_adhesion         w (J/m²): the work to separate from the unloaded equilibrium (stickiness inputs)
    steepest_softening       max −∂T_n/∂Δn (Pa/m), 0 if the law never softens
    reference_traction(E*)   a flat profile's residual scale (Pa)
    jump_in_separation(k)    δ_jump (m) of a surface of normal stiffness k (Pa/m)
Contact rule and tangential unknowns
    contact_rule, contact_gap, in_contact(gap, t_z), needs_tangential(material),
    tangential_reason(material), forced_tangential_reason()
Naming
    name, description
"""

from __future__ import annotations

#: the members every law answers
MEMBERS = ("name", "description", "constraint", "has_potential", "tangential", "adhesive", "nodal_form",
           "normal_only", "peak_traction", "work_of_adhesion", "steepest_softening", "curvature_scale",
           "reference_traction", "jump_in_separation", "contact_rule", "contact_gap", "in_contact",
           "needs_tangential", "tangential_reason")
#: what a law with tractions (every law but a pure constraint) answers besides
TRACTION_MEMBERS = ("potential", "tractions", "tangent", "length_scale", "length_normal", "initial_stiffness",
                    "far_reach", "check_gaps", "forced_tangential_reason")


def missing(law):
    """The protocol members `law` does not answer (empty: it implements the protocol). The implementations:
    `gfmd_contact.core.laws`, `gfmd_contact.core.user_law`, `gfmd_contact.core.law_lj93`."""
    need = MEMBERS + (() if law.constraint and not law.adhesive else TRACTION_MEMBERS)
    return [m for m in need if not hasattr(law, m)]
