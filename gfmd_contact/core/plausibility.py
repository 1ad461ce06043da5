"""Plausibility warnings: SI magnitudes that are almost certainly a unit slip (µm or nm written as m, MPa as
Pa, ...). Each names the key; they are warnings only, never a refusal (an unusual scene may mean them).

* a cell over CELL_LIMIT (1 mm) with nanometre-scale roughness (below ROUGH_LIMIT, 1 µm): a length given in m
  where nm or µm was meant;
* E under MODULUS_LIMIT (1 MPa): softer than any rubber, a modulus in MPa or GPa given as Pa;
* a roughness (h_rms or amplitude) over a tenth of the cell: slopes of order one, outside the small-slope
  contact the methods solve, often a height in the wrong unit.
"""

from __future__ import annotations

CELL_LIMIT = 1e-3
ROUGH_LIMIT = 1e-6
MODULUS_LIMIT = 1e6
ROUGHNESS_PER_CELL = 0.1


def _roughness(surface):
    """(key, value (m)) of the surface's height scale, or None for kinds without one (flat, cylinder, file)."""
    if surface.kind == "self-affine":
        return "surface.h_rms", surface.h_rms
    if surface.kind in ("sinusoid", "egg-box"):
        return "surface.amplitude", surface.amplitude
    return None


def unit_slip_warnings(scene):
    """The scene's plausibility warnings (list of str, module docstring)."""
    s, found = scene.surface, []
    rough = _roughness(s)
    if s.length > CELL_LIMIT and rough and 0 < rough[1] < ROUGH_LIMIT:
        found.append(f"surface.length = {s.length:g} m is over {CELL_LIMIT:g} m with {rough[0]} = {rough[1]:g} m of "
                     "nanometre scale: is the length in m (not µm or nm)?")
    if scene.material.youngs_modulus < MODULUS_LIMIT:
        found.append(f"material.youngs_modulus = {scene.material.youngs_modulus:g} Pa is under {MODULUS_LIMIT:g} Pa, "
                     "softer than any rubber: is it in Pa (not MPa or GPa)?")
    cell = min(s.length, s.length_y) if s.two_d else s.length
    if rough and rough[1] > ROUGHNESS_PER_CELL * cell:
        found.append(f"{rough[0]} = {rough[1]:g} m is over {ROUGHNESS_PER_CELL:g} of the cell "
                     f"(surface.length{'/length_y' if s.two_d else ''} = {cell:g} m): slopes of order one, beyond "
                     "small-slope contact; is the height in m?")
    return found
