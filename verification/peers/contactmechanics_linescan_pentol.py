"""ContactMechanics 1.8.3: constrained_conjugate_gradients on a line scan fails without an explicit pentol.

Its default penetration tolerance calls `topography.rms_height_from_area()`, which SurfaceTopography refuses for
a UniformLineScan ("Areal rms height can only be computed for topographies, not line scans"); the profile's
rms height (`rms_height_from_profile`) would serve. With pentol given the same call solves the contact.

    python verification/peers/contactmechanics_linescan_pentol.py
"""

import numpy as np
from ContactMechanics import PeriodicFFTElasticHalfSpace
from ContactMechanics.Optimization import constrained_conjugate_gradients
from SurfaceTopography import UniformLineScan

N, L, E_STAR, H0 = 64, 1.0, 1.0, 0.01
substrate = PeriodicFFTElasticHalfSpace((N,), E_STAR, physical_sizes=(L,))
profile = UniformLineScan(H0 * np.cos(2 * np.pi * np.arange(N) / N), L, periodic=True)
try:
    constrained_conjugate_gradients(substrate, profile, offset=-0.5 * H0)
    print("default pentol on a line scan: solved (fixed)")
except ValueError as exc:
    print(f"default pentol on a line scan: ValueError: {exc}")
result = constrained_conjugate_gradients(substrate, profile, offset=-0.5 * H0, pentol=1e-10)
print(f"pentol = 1e-10: success {result.success} after {result.nit} iterations, mean pressure "
      f"{result.jac.sum() / L:.4e} E*")
