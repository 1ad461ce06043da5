"""2+1-D surfaces in a scene: the keys [surface] nodes_y, length_y and what a 2+1-D scene refuses.

Units: SI (see `gfmd_contact.core.conventions`). nodes_y = 0 (the default, omitted from the TOML) is a
1+1-D profile; nodes_y ≥ 2 is a surface of Nx × Ny = nodes × nodes_y nodes on a
periodic Lx × Ly = length × length_y cell (length_y defaults to length). Axis 0 of every 2-D array
is x, axis 1 is y (the 2+1-D contract).

Refused, each naming its key and saying why:

* nodes_y = 1 or < 0 (a surface needs ≥ 2 nodes along y; 0 is the profile), Nx·Ny > MAX_NODES;
* length_y without nodes_y (a profile has no Ly);
* a 2-D-only kind ("egg-box", "sphere") on a profile, a 1-D-only kind ("cylinder") on a surface
  (its 2+1-D counterpart is "sphere");
* a law that needs u_x (interface.tangential_ratio > 0, solver.unknowns = "coupled"): 2+1-D is
  normal-only; the 3 × 3 coupled kernel (two tangential components) is not built, and the seed finds
  friction and compressibility negligible for the area–load relation.

The methods refuse what they do not solve in 2+1-D themselves (`gfmd_contact.app.methods`).
"""

from __future__ import annotations

from .errors import SceneError

#: [surface] keys of a 2+1-D surface (written only when nodes_y ≥ 2)
KEYS_2D = ("nodes_y", "length_y")
#: kinds that exist only as 2+1-D surfaces, and kinds that exist only as 1+1-D profiles (their 2-D kin)
KINDS_2D_ONLY = ("egg-box", "sphere")
KINDS_1D_ONLY = {"cylinder": "sphere"}
#: smallest nodes_y of a surface
MIN_NODES_Y = 2


def check_dimensions(kind, nodes, length, nodes_y, length_y, length_y_given, max_nodes):
    """Raise SceneError for a bad nodes_y / length_y or a kind of the other dimension (module docstring)."""
    if nodes_y != 0 and nodes_y < MIN_NODES_Y:
        raise SceneError(f"surface.nodes_y = {nodes_y!r}: must be 0 (a 1+1-D profile, the default) or an integer "
                         f"≥ {MIN_NODES_Y} (a 2+1-D surface of surface.nodes × surface.nodes_y nodes)")
    if nodes_y == 0 and length_y_given:
        raise SceneError(f"surface.length_y = {length_y!r}: applies to a 2+1-D surface only; give surface.nodes_y ≥ "
                         f"{MIN_NODES_Y} with it, or leave it out (a profile has no Ly)")
    if nodes_y and nodes * nodes_y > max_nodes:
        raise SceneError(f"surface.nodes_y = {nodes_y}: surface.nodes × surface.nodes_y = {nodes * nodes_y} nodes "
                         f"> {max_nodes} (a run holds tens of arrays of that size)")
    if nodes_y == 0 and kind in KINDS_2D_ONLY:
        raise SceneError(f"surface.kind = {kind!r}: a 2+1-D surface kind; give surface.nodes_y ≥ {MIN_NODES_Y} "
                         f"(a surface of surface.nodes × surface.nodes_y nodes), or a profile kind "
                         f"({'cylinder' if kind == 'sphere' else 'sinusoid'})")
    if nodes_y and kind in KINDS_1D_ONLY:
        raise SceneError(f"surface.kind = {kind!r}: a 1+1-D profile kind, not defined on a 2+1-D surface "
                         f"(surface.nodes_y = {nodes_y}); use surface.kind = {KINDS_1D_ONLY[kind]!r} or "
                         "surface.nodes_y = 0")


def check_scene(scene):
    """Raise SceneError for what a 2+1-D scene cannot be (module docstring); a profile passes unchanged."""
    if not scene.surface.two_d:
        return
    why = ("2+1-D surfaces are normal-only: the coupled law needs two tangential displacement components and "
           "its 3 × 3 kernel, which is not built (the seed finds friction and compressibility negligible)")
    c = scene.interface.tangential_ratio
    if c != 0:
        raise SceneError(f"interface.tangential_ratio = {c!r}: must be 0 on a 2+1-D surface (surface.nodes_y = "
                         f"{scene.surface.nodes_y}): {why}")
    if scene.solver.unknowns == "coupled":
        raise SceneError(f"solver.unknowns = \"coupled\": not available on a 2+1-D surface (surface.nodes_y = "
                         f"{scene.surface.nodes_y}): {why}; use \"auto\"")
