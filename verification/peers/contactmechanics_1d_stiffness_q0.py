"""ContactMechanics 1.8.3: a 1D periodic half-space with stiffness_q0 = 0.0 raises IndexError.

stiffness_q0 = 0.0 is the documented way to clamp the mean displacement (zero q = 0 compliance); it works in 2D,
but the 1D branch of `PeriodicFFTElasticHalfSpace._compute_greens_function` indexes `greens_function[0, 0]` on a
1D array. stiffness_q0 = inf gives the same Green's function in 1D (1/inf = 0); with it the CG reproduces
Westergaard's sinusoid (mean gap ⟨g⟩ = h0(1 − P + P ln P), P = p̄/p*, p* = πE*h0/λ, at zero mean displacement).

    python verification/peers/contactmechanics_1d_stiffness_q0.py
"""

import numpy as np
from ContactMechanics import PeriodicFFTElasticHalfSpace
from ContactMechanics.Optimization import constrained_conjugate_gradients
from SurfaceTopography import UniformLineScan

N, L, E_STAR, H0 = 256, 1.0, 1.0, 0.01

try:
    PeriodicFFTElasticHalfSpace((N,), E_STAR, physical_sizes=(L,), stiffness_q0=0.0)
    print("1D, stiffness_q0 = 0.0: constructed (fixed)")
except IndexError as exc:
    print(f"1D, stiffness_q0 = 0.0: IndexError: {exc}")
PeriodicFFTElasticHalfSpace((N, N), E_STAR, physical_sizes=(L, L), stiffness_q0=0.0)
print("2D, stiffness_q0 = 0.0: constructed")

# the workaround: stiffness_q0 = inf, checked against Westergaard at P = 0.3
substrate = PeriodicFFTElasticHalfSpace((N,), E_STAR, physical_sizes=(L,), stiffness_q0=np.inf)
x = np.arange(N) * L / N
heights = H0 * np.cos(2 * np.pi * x / L)  # the rigid sinusoid, summits up
P = 0.3
delta = H0 * (P - P * np.log(P))  # penetration past first touch: h0 − ⟨g⟩
result = constrained_conjugate_gradients(substrate, UniformLineScan(heights, L, periodic=True),
                                         offset=delta - heights.max(), pentol=1e-12, forcetol=1e-12)
p_star = np.pi * E_STAR * H0 / L
print(f"1D, stiffness_q0 = inf: success {result.success}, mean displacement {result.x.mean():.2e}, "
      f"p̄/p* = {result.jac.sum() / L / p_star:.6f} (Westergaard {P}, N = {N})")
