"""The material range both FE references solve: a displacement FE near ν = 1/2 is ill-conditioned.

Shared by `reference.fem` and `reference.fem3d` (each refuses such a scene by name); it reads only the scene's
material.poisson_ratio.
"""

from __future__ import annotations

#: largest λ/μ = 2ν/(1 − 2ν) the FE references accept: the condensed surface stiffness's condition number grows as
#: ≈ 0.05–0.1 λ/μ (measured on P1/P2 cells of 16 nodes, ν = 0.5 − 10^−k, k = 3 … 16), so at 10^9 a solve keeps
#: about 8 significant digits, and from λ/μ ≈ 10^14 on its Cholesky factorisation fails outright
MAX_BULK_TO_SHEAR = 1e9
#: the largest ν accepted: λ/μ = MAX_BULK_TO_SHEAR solved for ν (0.4999999995)
MAX_POISSON_RATIO = MAX_BULK_TO_SHEAR / (2 * (1 + MAX_BULK_TO_SHEAR))


def near_incompressible(scene):
    """Why `scene`'s ν is too close to 1/2 for a displacement FE (a str naming the key), or None."""
    nu = scene.material.poisson_ratio
    if nu <= MAX_POISSON_RATIO:
        return None
    ratio = 2 * nu / (1 - 2 * nu) if nu < 0.5 else float("inf")
    return (f"material.poisson_ratio = {nu!r}: a bulk-to-shear ratio λ/μ = 2ν/(1 − 2ν) = {ratio:.3g} above "
            f"{MAX_BULK_TO_SHEAR:g} leaves the FE's displacement stiffness too ill-conditioned to solve (fewer than "
            f"8 significant digits); use ν ≤ {MAX_POISSON_RATIO:.10g} with the FE, or method.name = \"gfmd\"")
