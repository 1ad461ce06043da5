"""Closed-form contact solutions: plane-strain line contacts (shared/reference-formulas.md §2–§4)
and 2+1-D references (docs/analytic_2d.rst).

Plain numpy functions, SI units per unit length, p > 0 compressive
(see gfmd_contact.core.conventions). One module per classical solution:

* hertz           – rigid cylinder on a half-plane (§2)
* westergaard     – periodic sinusoid, no adhesion (§3)
* jkr_cylinder    – JKR line contact (§4.1)
* maugis_dugdale  – Baney & Hui (1997) Maugis–Dugdale cylinder (§4.2)
* jkr_sinusoid    – Johnson (1995) adhesive sinusoid (§4.3)

2+1-D (half-space, SI units in N, m, Pa):

* hertz_sphere           – Hertz sphere, periodic array of spheres
* jkr_sphere             – JKR sphere, both pull-offs, Tabor parameter
* maugis_dugdale_sphere  – Maugis (1992) sphere, JKR–DMT transition
* jgh_wavy               – Johnson, Greenwood & Higginson (1985) egg-box asymptotes
* embedded_sinusoid      – the 1-D sinusoid embedded in 2-D (1+1-D results as 2-D means)
"""

from . import (embedded_sinusoid, hertz, hertz_sphere, jgh_wavy, jkr_cylinder, jkr_sinusoid, jkr_sphere,
               maugis_dugdale, maugis_dugdale_sphere, westergaard)

__all__ = ["hertz", "westergaard", "jkr_cylinder", "maugis_dugdale", "jkr_sinusoid",
           "hertz_sphere", "jkr_sphere", "maugis_dugdale_sphere", "jgh_wavy", "embedded_sinusoid"]
