"""The sections of a scene ([surface], [material], [interface], [loading], [solver], [output], [method]).

Frozen dataclasses, one per TOML table, whose field defaults are the scene defaults (SI units,
see `gfmd_contact.core.conventions`), with the few quantities derived from one section alone (node
spacing, E*, half-plane). Reading and checking a table is `gfmd_contact.core.scene_validation`; the whole
scene, `gfmd_contact.core.scene.Scene`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from . import kernels


@dataclass(frozen=True)
class Surface:
    kind: str = "self-affine"
    length: float = 10.24e-6
    nodes: int = 131072
    hurst: float = 0.8
    h_rms: float = 10e-9
    rolloff_wavelength: float = 1.28e-6
    rollon_wavelength: float = 2.5e-9
    seed: int = 1
    realizations: int = 10
    amplitude: float = 0.0
    radius: float = 0.0
    path: str = ""
    nodes_y: int = 0  # 0: a 1+1-D profile; ≥ 2: a 2+1-D surface of nodes × nodes_y (gfmd_contact.core.scene2d)
    length_y: float = 0.0  # Ly (m) of a 2+1-D surface (default: length); 0 for a profile
    boundary: str = "periodic"  # "periodic": the cell repeats; "free": one indenter on an unbounded body
    # a measured height file (kind "file"), prepared in this order (gfmd_contact.core.topography_prep)
    facing: str = "summits"  # "summits": the measured surface's highest points touch first; "valleys": h as read
    channel: object = ""  # a channel's name or index; "": the file's first height channel
    region: tuple = ()  # (x0, x1[, y0, y1]) m from the file's origin; (): the whole file
    undefined: str = "refuse"  # "refuse" | "harmonic" | "mean"
    line: str = "none"  # "x:K" | "y:K": one line of a map for a profile
    height_unit: str = ""  # "": the file's unit (m for .npy and text)
    height_scale: float = 1.0
    line_levelling: str = "none"  # "none" | "height" | "slope": each scan line of a map levelled on its own
    scan_axis: str = "x"  # "x" | "y": the axis the scan lines run along (the fast-scan axis)
    levelling: str = "none"  # "none" | "height" | "slope" | "curvature"
    resample: str = "none"  # "none" | "linear" | "cubic" | "fourier"

    @property
    def spacing(self):
        """Node spacing l = L/N (m); along x for a 2+1-D surface (`spacings`)."""
        return self.length / self.nodes

    @property
    def two_d(self):
        """A 2+1-D surface (nodes_y ≥ 2)?"""
        return self.nodes_y > 0

    @property
    def shape(self):
        """Shape of the height array: (N,) or (Nx, Ny) (axis 0 is x, axis 1 is y)."""
        return (self.nodes, self.nodes_y) if self.two_d else (self.nodes,)

    @property
    def spacings(self):
        """(l,) or (lx, ly) = (Lx/Nx, Ly/Ny) (m)."""
        return (self.spacing, self.length_y / self.nodes_y) if self.two_d else (self.spacing,)


@dataclass(frozen=True)
class Material:
    youngs_modulus: float = 70e9
    poisson_ratio: float = 0.45
    thickness: float = math.inf  # "inf" in TOML = half-plane

    @property
    def contact_modulus(self):
        """E* = E/(1 − ν²) (Pa), `gfmd_contact.core.kernels.contact_modulus`."""
        return kernels.contact_modulus(self.youngs_modulus, self.poisson_ratio)

    @property
    def half_plane(self):
        return math.isinf(self.thickness)


@dataclass(frozen=True)
class Interface:
    law: str = "cohesive"
    phi_n_star: float = 0.15
    length_normal: float = 1e-9
    tangential_ratio: float = 0.0
    length_tangential: float = 1e-9
    contact_tolerance: float = 1e-3
    contact_rule: str = "traction-tolerance"
    contact_gap: float = 1.0  # rule "gap": Δn ≤ contact_gap·δn (units of δn)
    #: a law's own keys ((key, value) pairs, SI), those its module declares (`gfmd_contact.core.law_registry`);
    #: written to and read from [interface] as keys of their own
    parameters: tuple = ()
    # φn = φn* δn E (J/m²) needs E: `Scene.work_normal`; the law objects: `gfmd_contact.core.laws.law_from_scene`


@dataclass(frozen=True)
class Loading:
    """The load: under displacement control the seed's ramp (δ from −initial_separation to final_penetration in `steps`
    equal increments), or, with `path`, a piecewise-linear path in δ = U − δ0 (m) through the corners
    path[0], path[1], ... with segment_steps[s] increments on segment s (`gfmd_contact.core.loading`). For a path,
    initial_separation = −path[0], final_penetration = max(path) and steps = sum(segment_steps) (derived).
    Under force control (control = "force") path holds corners of the mean pressure p̄ (Pa, from 0), the indenter
    starting out of contact at δ = −initial_separation."""

    initial_separation: float = 2e-9
    final_penetration: float = 40e-9
    steps: int = 200
    path: tuple = ()  # corners of δ (m); () = the ramp
    segment_steps: tuple = ()  # increments per segment of the path (TOML: loading.steps, an int or a list)
    control: str = "displacement"  # "displacement" or "force" (path in p̄, Pa)


@dataclass(frozen=True)
class Solver:
    """Solver settings.

    unknowns: "auto" (only what the scene requires, `gfmd_contact.core.model`) or "coupled" (always
    u_x and u_z, to compare the reduced model with the full one; cohesive law only).
    checks: "warn" (resolution/stability findings of `gfmd_contact.core.model.scene_warnings` are
    recorded in the model's reasons and the run goes on) or "error" (such a scene is
    refused before any work).
    """

    method: str = "fire"
    tolerance: float = 1e-8
    max_iterations: int = 200_000
    unknowns: str = "auto"
    checks: str = "warn"


@dataclass(frozen=True)
class Output:
    field_steps: int = 5  # steps (evenly spaced, last included) whose fields are saved
    workers: int = 0  # processes for realizations; 0 = number of CPU cores


@dataclass(frozen=True)
class Method:
    """Which method solves the scene, and its options.

    name: "gfmd" (the production solver; its algorithms: solver.method) or "fe" (the
    finite-element reference, a finite layer only). FE options (fe only): order 1 or 2
    (P1/P2 elements), linear "auto" | "dense" | "sparse" | "sparse-lagged" (reference.fem),
    quadrature "nodal" | "gauss" (the cohesive boundary term; gauss needs linear dense).
    """

    name: str = "gfmd"
    order: int = 2
    linear: str = "auto"
    quadrature: str = "nodal"


_SECTIONS = {"surface": Surface, "material": Material, "interface": Interface,
             "loading": Loading, "solver": Solver, "output": Output, "method": Method}
