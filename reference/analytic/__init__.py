"""Closed-form plane-strain line-contact solutions (shared/reference-formulas.md §2–§4).

Plain numpy functions, SI units per unit length, p > 0 compressive
(see contact.conventions). One module per classical solution:

* hertz           – rigid cylinder on a half-plane (§2)
* westergaard     – periodic sinusoid, no adhesion (§3)
* jkr_cylinder    – JKR line contact (§4.1)
* maugis_dugdale  – Baney & Hui (1997) Maugis–Dugdale cylinder (§4.2)
* jkr_sinusoid    – Johnson (1995) adhesive sinusoid (§4.3)
"""

from . import hertz, jkr_cylinder, jkr_sinusoid, maugis_dugdale, westergaard

__all__ = ["hertz", "westergaard", "jkr_cylinder", "maugis_dugdale", "jkr_sinusoid"]
