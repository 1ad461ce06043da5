"""A user-defined normal interface law: energy, traction and tangent given as Python callables.

The extension point for laws of one's own (the peers': Tamaas' ``Functional``, ContactMechanics' ``Potential``).
The user gives, vectorised over numpy arrays of normal gaps Δn (m; Δ = indenter − body,
`gfmd_contact.core.conventions`):

    energy(Δn)   V(Δn), interface energy per area (J/m²), V(∞) = 0 by convention (not required)
    traction(Δn) T_n(Δn) = dV/dΔn (Pa), > 0 tensile (reference-formulas §0; acts on the body as t_z = T_n)
    tangent(Δn)  dT_n/dΔn (Pa/m)

and one number that cannot be derived from them, the law's length scale `length` (m; δn of seed
Eq. 3): the shortest length over which T_n changes. It sets where the law is sampled (the checks
below, the peak), the FIRE trust region (solver.max_move·length), the resolution check of the
scene (length ≥ 2 l) and the messages. Everything else a solver or an observable asks a law
(`gfmd_contact.core.laws`: peak_traction, reference_traction, contact_gap, in_contact, jump_in_separation,
steepest_softening, initial_stiffness, ...) is derived from the callables on the grid
Δn = s·length, s ∈ [0, SAMPLE_REACH] (SAMPLE_POINTS points, refined by scipy):

* peak_traction: max T_n (Pa), the peak refined by bounded Brent (`minimize_scalar`);
* contact rule "traction-tolerance" (the seed's): Δtol > Δ_peak where T_n falls to
  contact_tolerance · e · peak_traction, which for seed Eq. 3 is contact_tolerance · φn/δn, the
  built-in rule (`gfmd_contact.core.laws.contact_gap_threshold`); `contact_gap` (m) overrides it. Rule "gap":
  Δn ≤ contact_gap · interface.length_normal, as for every law; "compressive": −t_z > 0;
* steepest_softening: max −dT_n/dΔn on the grid; jump_in_separation(k): the flat surface on a spring k
  loses stability at the largest gap Δ* with dT_n/dΔn(Δ*) = −k, where it stands at δ = Δ* + T_n(Δ*)/k
  (the construction of `gfmd_contact.core.laws.jump_in_separation`, by root finding instead of Lambert W);
* initial_stiffness (0, dT_n/dΔn(0)), reference_traction = peak_traction (a flat profile's scale).

Consistency check at construction (`UserLawError` naming the callable, the gap and the numbers):
every value finite and of the input's shape on the check grid s ∈ [CHECK_FROM, CHECK_TO]; T_n equal to
the central difference of V, and dT_n/dΔn to that of T_n, step h = FD_STEP·length, within
CHECK_RTOL of the largest |T_n| (|dT_n/dΔn|) on the grid. Why that tolerance: the central difference
errs by h²|f'''|/6 + ε|f|/h; with f''' ~ max|T_n|/length² that is ≈ 2e-9 + 2e-12 relative at
FD_STEP = 1e-4, so 1e-6 is passed by any smooth law written right and failed by a wrong sign, a wrong
factor or a unit slip (all O(1) errors; tests/test_user_law.py checks each is caught).

Normal-only: T_t ≡ 0 and u_x decouples (u_x ≡ 0 solves the tangential equations). A coupled
(Δn, Δt) user law is not supported: such a law has in general no potential, so neither the NCG nor
the FE's energy line search applies, and its non-symmetric 2×2 tangent and the coupled chain's
stability test (`gfmd.chains`) would need a second set of callables; the scene refuses
solver.unknowns = "coupled" for it.
"""

from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass, field
from typing import Callable, ClassVar

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from .errors import SceneError
from .law_registry import SceneLaw

#: the derived quantities are found on Δn = s·length, s ∈ [0, SAMPLE_REACH], SAMPLE_POINTS points
SAMPLE_REACH = 50.0
SAMPLE_POINTS = 5001
#: the consistency check's grid s ∈ [CHECK_FROM, CHECK_TO] (CHECK_POINTS points), step and tolerance
CHECK_FROM, CHECK_TO, CHECK_POINTS = -1.0, 12.0, 131
FD_STEP = 1e-4
CHECK_RTOL = 1e-6


class UserLawError(ValueError):
    """A user law whose callables are inconsistent, not finite or not vectorised (the message says which)."""


@dataclass(frozen=True)
class UserLaw:
    """A normal-only interface law from the user's V(Δn), T_n(Δn), dT_n/dΔn (module docstring); `user_law` builds it.

    energy, traction, tangent: callables of the gap array Δn (m) returning J/m², Pa, Pa/m; length (m);
    name, description: what meta.json and the model description say ran; contact_tolerance, contact_rule,
    rule_gap: the scene's contact rule (`gfmd_contact.core.laws`; set from the scene by `for_scene`); contact_gap (m):
    optional Δtol of the traction-tolerance rule instead of the derived one.
    """

    energy: Callable
    traction: Callable
    tangent_fn: Callable
    length: float
    name: str = "user law"
    description: str = ""
    contact_gap_given: float | None = None
    contact_tolerance: float = 1e-3
    contact_rule: str = "traction-tolerance"
    rule_gap: float | None = None
    peak_gap: float = field(init=False, repr=False, compare=False)
    peak_traction: float = field(init=False, repr=False, compare=False)
    steepest_softening: float = field(init=False, repr=False, compare=False)
    tolerance_gap: float | None = field(init=False, repr=False, compare=False)
    work_normal: float = field(init=False, repr=False, compare=False)

    constraint: ClassVar[bool] = False
    tangential: ClassVar[bool] = False
    has_potential: ClassVar[bool] = True
    nodal_form: ClassVar[None] = None  # the NCG evaluates the callables on its near set
    #: not derived: the two-level preconditioner was measured on seed Eq. 3 only, so the NCG keeps K⁻¹
    curvature_scale: ClassVar[None] = None

    def __post_init__(self):
        for key in ("energy", "traction", "tangent_fn"):
            if not callable(getattr(self, key)):
                raise UserLawError(f"user law {self.name!r}: {_ARG[key]} must be a callable of the gap array Δn (m), "
                                   f"got {getattr(self, key)!r}")
        if not (isinstance(self.length, (int, float)) and np.isfinite(self.length) and self.length > 0):
            raise UserLawError(f"user law {self.name!r}: length = {self.length!r} must be a positive length scale (m)")
        check_consistency(self)
        s = np.linspace(0.0, SAMPLE_REACH, SAMPLE_POINTS) * self.length
        t = self._call("traction", s)
        i = int(np.argmax(t))
        lo, hi = s[max(i - 1, 0)], s[min(i + 1, s.size - 1)]
        best = minimize_scalar(lambda x: -float(self._call("traction", np.array([x]))[0]), bounds=(lo, hi),
                               method="bounded", options={"xatol": 1e-12 * self.length})
        peak_gap = float(best.x) if -best.fun >= t[i] else float(s[i])
        peak = max(float(-best.fun), float(t[i]))
        set_ = object.__setattr__
        set_(self, "peak_gap", peak_gap)
        set_(self, "peak_traction", peak)
        set_(self, "steepest_softening", max(0.0, float(np.max(-self._call("tangent_fn", s)))))
        set_(self, "tolerance_gap", self._tolerance_gap(s, t, i))
        # work of separation w (J/m²): V far out minus its minimum (the unloaded equilibrium gap; Δn = 0 for Eq. 3,
        # where V(0) = −φn and w = φn), both over the checked range CHECK_FROM … SAMPLE_REACH lengths
        g = np.linspace(CHECK_FROM, SAMPLE_REACH, SAMPLE_POINTS) * self.length
        v = self._call("energy", g)
        j = int(np.argmin(v))
        low = minimize_scalar(lambda x: float(self._call("energy", np.array([x]))[0]),
                              bounds=(g[max(j - 1, 0)], g[min(j + 1, g.size - 1)]), method="bounded",
                              options={"xatol": 1e-12 * self.length})
        set_(self, "work_normal", float(v[-1] - min(float(low.fun), float(v[j]))))

    # -- calling the user's functions -----------------------------------------------------------------------
    def _call(self, key, gap):
        try:
            out = np.asarray(getattr(self, key)(gap), dtype=float)
        except Exception as exc:  # noqa: BLE001 - the user's code: say which law, callable and gaps
            g = np.asarray(gap, dtype=float)
            raise UserLawError(f"user law {self.name!r}: {_ARG[key]}(Δn) raised {type(exc).__name__}: {exc} on "
                               f"{g.size} gap(s) Δn in [{np.min(g):.4g}, {np.max(g):.4g}] m") from exc
        return np.broadcast_to(out, np.shape(gap)) if out.ndim == 0 else out

    def _tolerance_gap(self, s, t, i):
        """Δtol (m) of the traction-tolerance rule (module docstring), or contact_gap_given."""
        if self.contact_gap_given is not None:
            return float(self.contact_gap_given)
        if self.peak_traction <= 0:
            return None  # a purely repulsive law: the tolerance rule is the compressive one
        if not 0.0 < self.contact_tolerance < np.exp(-1.0):
            raise UserLawError(f"contact_tolerance = {self.contact_tolerance!r} must lie in (0, 1/e): a fraction of "
                               "e·peak_traction below the peak")
        target = self.contact_tolerance * np.e * self.peak_traction
        below = np.flatnonzero(t[i:] < target)
        if below.size == 0:
            raise UserLawError(f"user law {self.name!r}: T_n does not fall to contact_tolerance·e·peak_traction = "
                               f"{target:.4g} Pa within {SAMPLE_REACH:g} length beyond its peak: give contact_gap (m)")
        j = i + int(below[0])
        return float(brentq(lambda x: float(self._call("traction", np.array([x]))[0]) - target, s[j - 1], s[j],
                            xtol=1e-15 * self.length, rtol=4 * np.finfo(float).eps))

    # -- the law-object interface of gfmd_contact.core.laws ------------------------------------------------------------
    @property
    def adhesive(self):
        """True if the law carries tension (peak_traction > 0)."""
        return self.peak_traction > 0

    @property
    def length_normal(self):
        """The law's length (m), in the role of δn (resolution check)."""
        return self.length

    @property
    def length_scale(self):
        """The law's length (m)."""
        return self.length

    @property
    def work_of_adhesion(self):
        """w (J/m²), the derived work of separation (`work_normal`)."""
        return self.work_normal

    def far_reach(self, traction):
        """s_c = far_gap(traction)/length: |T_n| ≤ traction beyond s_c lengths (inf: not within the sample grid)."""
        return self.far_gap(traction) / float(self.length)

    def check_gaps(self, delta_n):
        """Nothing to check: the callables were checked finite at construction, the user owns their range."""

    def normal_only(self):
        return self

    @property
    def initial_stiffness(self):
        """(k_t, k_n) = (0, dT_n/dΔn(0)) (Pa/m)."""
        return 0.0, float(self._call("tangent_fn", np.zeros(1))[0])

    def reference_traction(self, contact_modulus):
        """peak_traction (Pa): a flat profile's residual scale."""
        return self.peak_traction

    @property
    def contact_gap(self):
        """The rule's gap threshold (m): Δtol (traction-tolerance), rule_gap ("gap"), None ("compressive")."""
        if self.contact_rule == "gap":
            return self.rule_gap
        if self.contact_rule == "compressive":
            return None
        return self.tolerance_gap

    def in_contact(self, gap, traction_z):
        """Nodes with Δn ≤ contact_gap, or −t_z > 0 where contact_gap is None (as `gfmd_contact.core.laws`' laws)."""
        threshold = self.contact_gap
        if threshold is None:
            return -np.asarray(traction_z) > 0.0
        return np.asarray(gap) <= threshold

    def jump_in_separation(self, stiffness):
        """δ_jump (m) of a flat surface on a spring k (Pa/m): Δ* + T_n(Δ*)/k at the largest Δ* > Δ_peak with
        dT_n/dΔn(Δ*) = −k; 0 if k ≥ steepest_softening."""
        if stiffness >= self.steepest_softening or stiffness <= 0:
            return 0.0
        s = np.linspace(0.0, SAMPLE_REACH, SAMPLE_POINTS) * self.length
        unstable = np.flatnonzero(self._call("tangent_fn", s) + stiffness < 0)
        j = int(unstable[-1])
        if j + 1 >= s.size:
            return float(s[-1] + self._call("traction", s[-1:])[0] / stiffness)
        g = brentq(lambda x: float(self._call("tangent_fn", np.array([x]))[0]) + stiffness, s[j], s[j + 1],
                   xtol=1e-14 * self.length)
        return float(g + self._call("traction", np.array([g]))[0] / stiffness)

    def far_gap(self, traction):
        """Δ_far (m): beyond it |T_n| ≤ traction (Pa) on the whole sample grid (up to SAMPLE_REACH·length), inf if
        |T_n| exceeds it at the grid's end. The NCG leaves nodes beyond it out of its nodal work and checks a
        converged state with every node (`gfmd.algorithms.ncg`), so this is a saving, not an assumption."""
        s = np.linspace(0.0, SAMPLE_REACH, SAMPLE_POINTS) * self.length
        above = np.flatnonzero(np.abs(self._call("traction", s)) > traction)
        if above.size == 0:
            return 0.0
        j = int(above[-1])
        return np.inf if j + 1 >= s.size else float(s[j + 1])

    def potential(self, delta_n):
        """V(Δn) (J/m²), the user's energy."""
        return self._call("energy", np.asarray(delta_n, dtype=float))

    def tractions(self, delta_n, delta_t=None):
        """(T_n, T_t) in Pa: the user's traction, and 0."""
        return self._call("traction", np.asarray(delta_n, dtype=float)), 0.0

    def tangent(self, delta_n, delta_t=None):
        """(∂Tn/∂Δn, 0, 0, 0) in Pa/m: the user's tangent."""
        return self._call("tangent_fn", np.asarray(delta_n, dtype=float)), 0.0, 0.0, 0.0

    def needs_tangential(self, material):
        return False

    def tangential_reason(self, material):
        return f"user law {self.name!r}: normal-only (T_t ≡ 0), u_x decouples"

    def forced_tangential_reason(self):
        return None  # the scene refuses solver.unknowns = "coupled" for it

    def for_scene(self, interface):
        """This law with the contact rule of a scene's `Interface` (rule "gap": contact_gap·interface.length_normal)."""
        i = interface
        return _with_rule(self, i.contact_rule, i.contact_tolerance,
                          i.contact_gap * i.length_normal if i.contact_rule == "gap" else None)

    def summary(self):
        """What meta.json records: name, description, length and the derived numbers (SI)."""
        return {"name": self.name, "description": self.description, "length": self.length,
                "peak_traction": self.peak_traction, "peak_gap": self.peak_gap,
                "contact_gap": self.contact_gap, "steepest_softening": self.steepest_softening,
                "work_normal": self.work_normal,
                "reproducible_from_scene_toml": False}


@functools.lru_cache(maxsize=64)
def _with_rule(law, rule, tolerance, rule_gap):
    """`UserLaw.for_scene`, built (and checked) once per law and rule: every load step asks for it."""
    if (law.contact_rule, law.contact_tolerance, law.rule_gap) == (rule, tolerance, rule_gap):
        return law
    return dataclasses.replace(law, contact_rule=rule, contact_tolerance=tolerance, rule_gap=rule_gap)


_ARG = {"energy": "energy", "traction": "traction", "tangent_fn": "tangent"}
_UNITS = {"energy": "J/m²", "traction": "Pa", "tangent_fn": "Pa/m"}


def check_consistency(law):
    """Raise `UserLawError` unless the callables are finite, vectorised and T_n = dV/dΔn, tangent = dT_n/dΔn
    (central differences, module docstring) on Δn = s·length, s ∈ [CHECK_FROM, CHECK_TO]."""
    L = law.length
    gaps = np.linspace(CHECK_FROM, CHECK_TO, CHECK_POINTS) * L
    h = FD_STEP * L
    values = {}
    for key in ("energy", "traction", "tangent_fn"):
        try:
            out = np.asarray(getattr(law, key)(gaps), dtype=float)
        except Exception as exc:  # noqa: BLE001 - the user's code: say which callable failed and how
            raise UserLawError(f"user law {law.name!r}: {_ARG[key]}(Δn) failed on an array of {gaps.size} gaps: "
                               f"{type(exc).__name__}: {exc} (the callables must be vectorised over numpy arrays)") from exc
        if out.shape not in ((), gaps.shape):
            raise UserLawError(f"user law {law.name!r}: {_ARG[key]}(Δn) returned shape {out.shape} for {gaps.size} "
                               "gaps: it must be vectorised (one value per gap)")
        bad = ~np.isfinite(np.broadcast_to(out, gaps.shape))
        if bad.any():
            raise UserLawError(f"user law {law.name!r}: {_ARG[key]}(Δn) is not finite at Δn = "
                               f"{gaps[bad][0] / L:.3g} length ({gaps[bad][0]:.3g} m); it must be finite for "
                               f"Δn/length in [{CHECK_FROM:g}, {CHECK_TO:g}]")
        values[key] = np.broadcast_to(out, gaps.shape)
    for key, of in (("traction", "energy"), ("tangent_fn", "traction")):
        fd = (law._call(of, gaps + h) - law._call(of, gaps - h)) / (2 * h)
        scale = float(np.max(np.abs(values[key])))
        err = np.abs(values[key] - fd)
        j = int(np.argmax(err))
        if not err[j] <= CHECK_RTOL * max(scale, float(np.max(np.abs(fd)))):
            raise UserLawError(
                f"user law {law.name!r}: {_ARG[key]} is not d{_ARG[of]}/dΔn: at Δn = {gaps[j] / L:.3g} length "
                f"({gaps[j]:.3g} m) {_ARG[key]} = {values[key][j]:.6g} {_UNITS[key]} but the central difference of "
                f"{_ARG[of]} gives {fd[j]:.6g} {_UNITS[key]} (error {err[j]:.3g} > {CHECK_RTOL:g} × the largest value "
                f"on Δn/length in [{CHECK_FROM:g}, {CHECK_TO:g}]); check the sign (T_n = +dV/dΔn, > 0 tensile) and "
                "the units (V in J/m², T_n in Pa, tangent in Pa/m)")


def user_law(energy, traction, tangent, length, *, name="user law", description="", contact_gap=None):
    """A normal-only interface law from the user's callables (`UserLaw`; module docstring for what is derived).

    Parameters
    ----------
    energy : callable
        V(Δn): interface energy per area (J/m²) of the normal gap array Δn (m).
    traction : callable
        T_n(Δn) = dV/dΔn (Pa), > 0 tensile.
    tangent : callable
        dT_n/dΔn (Pa/m).
    length : float
        The law's length scale (m): the shortest length over which T_n changes (δn of seed Eq. 3).
    name, description : str
        What meta.json and the model description say ran.
    contact_gap : float, optional
        Δtol (m) of the seed's contact rule; default: where T_n falls to contact_tolerance·e·peak_traction.

    Raises
    ------
    UserLawError
        A callable not vectorised or not finite, or traction ≠ dV/dΔn, tangent ≠ dT_n/dΔn (the message names
        which, where and by how much).
    """
    return UserLaw(energy=energy, traction=traction, tangent_fn=tangent, length=float(length), name=name,
                   description=description or name, contact_gap_given=contact_gap)


def scene_law(scene):
    """The user law a scene carries (`gfmd_contact.core.scene.Scene.user_law`) with the scene's contact rule; SceneError if none."""
    law = getattr(scene, "user_law", None)
    if law is None:
        raise SceneError("interface.law = \"user\": the law's Python callables are not in the scene file, so this "
                         "scene cannot run from scene.toml alone (nor with the gfmd command); run it from Python with "
                         "gfmd_contact.run(scene, law=gfmd_contact.user_law(...))")
    return law.for_scene(scene.interface)


def _from_scene(interface, work_normal, work_tangential, tangential, scene=None):
    """The registry's builder (`gfmd_contact.core.law_registry`): the user law the scene carries."""
    if scene is None:
        raise ValueError("interface.law = \"user\": the law object is not in the Interface; use law_from_scene(scene)")
    if tangential:
        raise ValueError("a user law is normal-only: no tangential unknowns (gfmd_contact.core.user_law)")
    return scene_law(scene)


#: the law of this module as the scene names it (`gfmd_contact.core.law_registry`)
SCENE_LAWS = {"user": SceneLaw(_from_scene, in_file=False)}
