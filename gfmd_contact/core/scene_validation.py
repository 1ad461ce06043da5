"""Scene validation: one TOML table → its validated section dataclass; every error names the key.

Units: SI (see `gfmd_contact.core.conventions`). Every error names the key, the value and the allowed
range (`SceneError`). [surface] takes only the keys of its kind (every kind: kind,
length, nodes, seed, realizations, nodes_y, length_y; self-affine: hurst, h_rms, rolloff_wavelength,
rollon_wavelength; sinusoid, egg-box: amplitude; cylinder, sphere: radius; file: path and the preparation
keys of `gfmd_contact.core.topography_keys`); a key of
another kind is an error, not ignored; so is a key of another contact rule in [interface]
(contact_tolerance belongs to contact_rule "traction-tolerance", contact_gap to "gap"). The
law's own parameters are not policed that way: a hard wall takes phi_n_star etc. and ignores
them, so a study can zip interface.law with them. Sizes are bounded (N ≤ 2^24, steps ≤ 10^6,
realizations ≤ 10^5) and positive physical quantities lie in [1e-30, 1e30] (SI).
The 2+1-D keys and refusals are `gfmd_contact.core.scene2d`; the whole scene, `gfmd_contact.core.scene.scene_from_dict`.
"""

from __future__ import annotations

import dataclasses
import math

from . import law_registry, scene2d, topography_keys
from .errors import SceneError
from .scene_sections import Interface, Loading, Material, Method, Output, Solver, Surface


#: the methods a scene can name, and the [method] keys each takes besides name
METHOD_KEYS = {"gfmd": (), "fe": ("order", "linear", "quadrature")}
_FE_LINEAR = ("auto", "dense", "sparse", "sparse-lagged")
_FE_QUADRATURE = ("nodal", "gauss")
_KINDS = ("self-affine", "sinusoid", "cylinder", "flat", "file") + scene2d.KINDS_2D_ONLY
#: [surface] keys of every kind, and the keys that apply to one kind only
_COMMON_KEYS = ("kind", "length", "nodes", "seed", "realizations", "boundary") + scene2d.KEYS_2D
#: surface.boundary: a periodic cell, or the cell's indenter alone on an unbounded (free) body
BOUNDARIES = ("periodic", "free")
_KIND_KEYS = {"self-affine": ("hurst", "h_rms", "rolloff_wavelength", "rollon_wavelength"),
              "sinusoid": ("amplitude",), "cylinder": ("radius",), "flat": (), "file": topography_keys.FILE_KEYS,
              "egg-box": ("amplitude",), "sphere": ("radius",)}
#: largest surface.nodes: a run holds tens of arrays of N values (N = 2^24: several GB)
MAX_NODES = 2**24
#: largest loading.steps, output.field_steps, surface.realizations (arrays and loops of that length)
MAX_STEPS = 10**6
MAX_REALIZATIONS = 10**5
#: positive physical quantities (SI) must lie in [MIN_SCALE, MAX_SCALE]: outside it a value is a unit
#: slip, and products such as φn = φn* δn E or the stiffness E q underflow to 0 or overflow to inf
MIN_SCALE, MAX_SCALE = 1e-30, 1e30
#: TOML integers are 64-bit signed
_MAX_INT = 2**63 - 1
#: interface.contact_rule (which nodes count as contact; `gfmd_contact.core.laws`, docs/guide/laws.rst), and
#: the [interface] keys that apply to one rule only: a key of another rule is an error, not ignored (as
#: surface keys of another kind), and `scene_to_dict` writes only the chosen rule's keys
_RULE_KEYS = {"traction-tolerance": ("contact_tolerance",), "compressive": (), "gap": ("contact_gap",)}
_METHODS = ("fire", "verlet")
_UNKNOWNS = ("auto", "coupled")
_CHECKS = ("warn", "error")


def _fail(key, value, allowed):
    raise SceneError(f"{key} = {value!r}: {allowed}")


def _number(d, section, key, default, *, integer=False):
    full = f"{section}.{key}"
    value = d.get(key, default)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        _fail(full, value, "must be a number" + (" (integer)" if integer else ""))
    if integer:
        if not math.isfinite(value) or int(value) != value:
            _fail(full, value, "must be an integer")
        if abs(int(value)) > _MAX_INT:
            _fail(full, value, f"must be an integer of at most {_MAX_INT} in size (TOML's 64-bit integers)")
        return int(value)
    value = float(value)
    if math.isnan(value):
        _fail(full, value, "must not be NaN")
    return value


def _check_keys(d, section, cls, also=(), omit=()):
    valid = [f.name for f in dataclasses.fields(cls) if f.name not in omit] + list(also)
    if not isinstance(d, dict):
        _fail(section, d, f"must be a table with keys {valid}")
    for key in d:
        if key not in valid:
            raise SceneError(f"unknown key {section}.{key!r}; valid keys of [{section}]: {', '.join(valid)}")


def _positive(key, value):
    if not value > 0 or math.isinf(value):
        _fail(key, value, "must be a finite number > 0")
    if not MIN_SCALE <= value <= MAX_SCALE:
        _fail(key, value, f"must lie in [{MIN_SCALE:g}, {MAX_SCALE:g}] (SI units): a value outside is no "
              "physical scale (a unit slip?) and under- or overflows in the model")


def _surface(d):
    _check_keys(d, "surface", Surface)
    s = Surface()
    kind = d.get("kind", s.kind)
    if not isinstance(kind, str) or kind not in _KINDS:
        _fail("surface.kind", kind, f"must be one of {list(_KINDS)}")
    allowed = _COMMON_KEYS + _KIND_KEYS[kind]
    for key in d:
        if key not in allowed:
            others = [k for k, keys in _KIND_KEYS.items() if key in keys]
            _fail(f"surface.{key}", d[key],
                  f"does not apply to surface.kind = {kind!r} (it belongs to kind {' / '.join(map(repr, others))}); "
                  f"the keys of a {kind!r} surface are: {', '.join(allowed)}")
    length = _number(d, "surface", "length", s.length)
    _positive("surface.length", length)
    boundary = d.get("boundary", s.boundary)
    if not isinstance(boundary, str) or boundary not in BOUNDARIES:
        _fail("surface.boundary", boundary, f"must be one of {list(BOUNDARIES)} (periodic: the cell repeats; free: "
              "the cell's indenter alone on an unbounded body, its elastic images removed)")
    nodes = _number(d, "surface", "nodes", s.nodes, integer=True)
    if not 8 <= nodes <= MAX_NODES:
        _fail("surface.nodes", nodes, f"must be an integer in [8, {MAX_NODES}] (2^24: a run holds tens of arrays "
              "of N values)")
    nodes_y = _number(d, "surface", "nodes_y", 0, integer=True)
    length_y = _number(d, "surface", "length_y", length) if "length_y" in d else (length if nodes_y else 0.0)
    scene2d.check_dimensions(kind, nodes, length, nodes_y, length_y, "length_y" in d, MAX_NODES)
    if nodes_y:
        _positive("surface.length_y", length_y)
    if kind == "file":  # the prepared file gives the cell's size where the scene does not
        file_kw, sizes = topography_keys.resolve(d, nodes, nodes_y, (length if "length" in d else None,
                                                                    length_y if "length_y" in d else None))
        length, length_y = sizes[0], (sizes[1] if nodes_y else 0.0)
    spacing = max(length / nodes, length_y / nodes_y) if nodes_y else length / nodes  # the coarser one
    kw = dict(kind=kind, length=length, nodes=nodes, nodes_y=nodes_y, length_y=length_y, boundary=boundary)
    seed = _number(d, "surface", "seed", s.seed, integer=True)
    if seed < 0:
        _fail("surface.seed", seed, "must be an integer ≥ 0")
    realizations = _number(d, "surface", "realizations", 1 if kind != "self-affine" else s.realizations,
                           integer=True)
    if not 1 <= realizations <= MAX_REALIZATIONS:
        _fail("surface.realizations", realizations, f"must be an integer in [1, {MAX_REALIZATIONS}]")
    if kind != "self-affine" and realizations != 1:
        _fail("surface.realizations", realizations, f"must be 1 for the deterministic kind {kind!r}")
    kw.update(seed=seed, realizations=realizations)
    if kind == "self-affine":
        hurst = _number(d, "surface", "hurst", s.hurst)
        if not 0 < hurst < 1:
            _fail("surface.hurst", hurst, "must lie in (0, 1)")
        h_rms = _number(d, "surface", "h_rms", s.h_rms)
        _positive("surface.h_rms", h_rms)
        lr = _number(d, "surface", "rolloff_wavelength", s.rolloff_wavelength)
        ls = _number(d, "surface", "rollon_wavelength", s.rollon_wavelength)
        longest = max(length, length_y)  # 2+1-D: the longest wave of the cell, 2π/min|q| (q ≠ 0)
        if not longest >= lr > ls > spacing:
            raise SceneError(
                "wavelengths out of order: need length ≥ rolloff_wavelength > rollon_wavelength > spacing "
                f"L/N; got L = {longest:g}, surface.rolloff_wavelength = {lr:g}, "
                f"surface.rollon_wavelength = {ls:g}, L/N = {spacing:g} (m)"
                + (" (2+1-D: L = max(length, length_y), L/N = the coarser of Lx/Nx, Ly/Ny)" if nodes_y else ""))
        kw.update(hurst=hurst, h_rms=h_rms, rolloff_wavelength=lr, rollon_wavelength=ls)
    elif kind in ("sinusoid", "egg-box"):
        amp = _number(d, "surface", "amplitude", 0.0)
        _positive("surface.amplitude", amp)
        kw.update(amplitude=amp)
    elif kind in ("cylinder", "sphere"):
        radius = _number(d, "surface", "radius", 0.0)
        _positive("surface.radius", radius)
        kw.update(radius=radius)
    elif kind == "file":
        kw.update(file_kw)
    return Surface(**kw)


def _material(d):
    _check_keys(d, "material", Material)
    m = Material()
    e = _number(d, "material", "youngs_modulus", m.youngs_modulus)
    _positive("material.youngs_modulus", e)
    nu = _number(d, "material", "poisson_ratio", m.poisson_ratio)
    if not -1 < nu <= 0.5:
        _fail("material.poisson_ratio", nu, "must lie in (−1, 0.5]")
    thickness = d.get("thickness", "inf")
    if isinstance(thickness, str):
        if thickness.strip().lower() not in ("inf", "infinite", "half-plane"):
            _fail("material.thickness", thickness, 'must be "inf" (half-plane) or a depth > 0 (m)')
        thickness = math.inf
    else:
        thickness = _number(d, "material", "thickness", thickness)
        if thickness != math.inf:  # TOML's inf is the half-plane too
            _positive("material.thickness", thickness)
        if nu == 0.5 and thickness != math.inf:
            _fail("material.poisson_ratio", nu,
                  f"an incompressible layer (material.thickness = {thickness!r}) bonded to a rigid base has "
                  'no uniform mode (M = ∞): use ν < 0.5 or thickness = "inf"')
    return Material(youngs_modulus=e, poisson_ratio=nu, thickness=thickness)


def _interface(d, material):
    i = Interface()
    law = d.get("law", i.law) if isinstance(d, dict) else i.law
    if not isinstance(law, str) or law not in law_registry.names():
        _fail("interface.law", law, f"must be one of {list(law_registry.names())}")
    entry = law_registry.entry(law)
    own = [k.name for k in entry.keys]  # the law's own keys (`gfmd_contact.core.law_registry`), in Interface.parameters
    _check_keys(d, "interface", Interface, also=("work_normal", *own), omit=("parameters",))  # work_normal: stored as φn*
    parameters = []
    for key in entry.keys:
        if key.name not in d:
            raise SceneError(f"interface.{key.name} is missing: interface.law = {law!r} needs it ({key.meaning}, "
                             f"{key.unit})")
        value = _number(d, "interface", key.name, 0.0)
        _positive(f"interface.{key.name}", value)
        parameters.append((key.name, value))
    dn = _number(d, "interface", "length_normal", i.length_normal)
    _positive("interface.length_normal", dn)
    if "phi_n_star" in d and "work_normal" in d:
        raise SceneError("give either interface.phi_n_star or interface.work_normal, not both "
                         f"(got phi_n_star = {d['phi_n_star']!r}, work_normal = {d['work_normal']!r})")
    if "work_normal" in d:  # φn given: stored as φn* = φn/(δn E) (module docstring: last bits)
        w = _number(d, "interface", "work_normal", 0.0)
        _positive("interface.work_normal", w)
        phi = w / (dn * material.youngs_modulus)
        if not MIN_SCALE <= phi <= MAX_SCALE:  # else the φn* written back would be refused on reading
            _fail("interface.work_normal", w, f"gives φn* = φn/(δn E) = {phi:g} (δn = {dn:g} m, E = "
                  f"{material.youngs_modulus:g} Pa), which must lie in [{MIN_SCALE:g}, {MAX_SCALE:g}]")
    else:
        phi = _number(d, "interface", "phi_n_star", i.phi_n_star)
        _positive("interface.phi_n_star", phi)
    c = _number(d, "interface", "tangential_ratio", i.tangential_ratio)
    if c < 0 or math.isinf(c):
        _fail("interface.tangential_ratio", c, "must be a finite number ≥ 0 (0 = frictionless)")
    dt = _number(d, "interface", "length_tangential", i.length_tangential)
    _positive("interface.length_tangential", dt)
    if entry.normal_only and not entry.unused_friction and c != 0:
        _fail("interface.tangential_ratio", c, f"must be 0 for interface.law = {law!r}: the law is normal-only "
              "(frictionless, no tangential traction)")
    rule = d.get("contact_rule", i.contact_rule)
    if not isinstance(rule, str) or rule not in _RULE_KEYS:
        _fail("interface.contact_rule", rule, f"must be one of {list(_RULE_KEYS)}")
    for key in d:
        others = [r for r, keys in _RULE_KEYS.items() if key in keys and r != rule]
        if others and key not in _RULE_KEYS[rule]:
            _fail(f"interface.{key}", d[key], f"does not apply to interface.contact_rule = {rule!r} (it belongs to "
                  f"rule {' / '.join(map(repr, others))}); leave it out or choose that rule")
    tol = _number(d, "interface", "contact_tolerance", i.contact_tolerance)
    if not 0 < tol < math.exp(-1):
        _fail("interface.contact_tolerance", tol, "must lie in (0, 1/e): a fraction of φn/δn")
    gap = _number(d, "interface", "contact_gap", i.contact_gap)
    if not 0 < gap < math.inf:
        _fail("interface.contact_gap", gap, "must be a finite number > 0 (units of δn = interface.length_normal: "
              "rule \"gap\" counts the nodes with Δn ≤ contact_gap·δn)")
    return Interface(law=law, phi_n_star=phi, length_normal=dn, tangential_ratio=c, length_tangential=dt,
                     contact_tolerance=tol, contact_rule=rule, contact_gap=gap, parameters=tuple(parameters))


_CONTROLS = ("displacement", "force")


def _path_loading(d):
    """A loading with `path` (Loading docstring): corners of δ (m) and the steps of each segment."""
    for key in ("initial_separation", "final_penetration"):
        if key in d:
            _fail(f"loading.{key}", d[key], "does not apply with loading.path (the path gives δ0 = −path[0] and its "
                  "deepest point); leave it out or leave out loading.path")
    path = d["path"]
    if not isinstance(path, (list, tuple)) or len(path) < 2:
        _fail("loading.path", path, "must be a list of at least two displacements δ (m): the corners of the path")
    corners = []
    for i, v in enumerate(path):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            _fail(f"loading.path[{i}]", v, "must be a finite number (m)")
        corners.append(float(v))
    if corners[0] > 0:
        _fail("loading.path[0]", corners[0], "must be ≤ 0: the path starts out of contact, δ0 = −path[0] ≥ 0 (m) "
              "above the undeformed surface")
    for i in range(1, len(corners)):
        if corners[i] == corners[i - 1]:
            _fail(f"loading.path[{i}]", corners[i], f"equals loading.path[{i - 1}]: a segment of zero length "
                  "(consecutive corners must differ)")
    segments = len(corners) - 1
    steps = d.get("steps", Loading().steps)
    if isinstance(steps, (list, tuple)):
        if len(steps) != segments:
            _fail("loading.steps", steps, f"must give one step count per segment of loading.path ({segments}), "
                  "or one integer for all")
        counts = tuple(_number({"steps": v}, "loading", "steps", 0, integer=True) for v in steps)
    else:
        counts = (_number(d, "loading", "steps", 0, integer=True),) * segments
    for i, n in enumerate(counts):
        if n < 1:
            _fail("loading.steps", list(steps) if isinstance(steps, (list, tuple)) else steps,
                  f"segment {i} (loading.path[{i}] → loading.path[{i + 1}]) has {n} steps: every segment needs ≥ 1")
    if sum(counts) > MAX_STEPS:
        _fail("loading.steps", steps, f"the path's steps add up to {sum(counts)} > {MAX_STEPS}")
    return Loading(initial_separation=-corners[0] + 0.0, final_penetration=max(corners), steps=sum(counts),
                   path=tuple(corners), segment_steps=counts, control=d.get("control", "displacement"))


def _force_loading(d):
    """Force control: loading.path holds corners of p̄ (Pa, > 0 compressive), starting unloaded at 0 with the
    indenter out of contact at δ = −initial_separation."""
    if "final_penetration" in d:
        _fail("loading.final_penetration", d["final_penetration"], "does not apply with loading.control = \"force\" "
              "(the path gives the loads; δ follows from them)")
    d0 = _number(d, "loading", "initial_separation", Loading().initial_separation)
    if not 0 < d0 < math.inf:
        _fail("loading.initial_separation", d0, "must be a finite number > 0 (m): under force control the indenter "
              "starts out of contact, δ = −initial_separation")
    path = d["path"]
    if isinstance(path, (list, tuple)) and path and path[0] != 0:
        _fail("loading.path[0]", path[0], "must be 0 under loading.control = \"force\": the path starts out of "
              "contact, unloaded (p̄ = 0 Pa), at δ = −initial_separation")
    lo = _path_loading({k: v for k, v in d.items() if k not in ("initial_separation", "control")})
    return dataclasses.replace(lo, initial_separation=d0, final_penetration=0.0, control="force")


def _loading(d):
    _check_keys(d, "loading", Loading)
    if "segment_steps" in d:
        _fail("loading.segment_steps", d["segment_steps"], "is derived: give loading.steps (an int or a list per "
              "segment of loading.path)")
    control = d.get("control", "displacement")
    if not isinstance(control, str) or control not in _CONTROLS:
        _fail("loading.control", control, f"must be one of {list(_CONTROLS)}")
    if control == "force" and "path" not in d:
        _fail("loading.control", control, "\"force\" needs loading.path: the corners of the mean pressure p̄ (Pa)")
    if control == "force":
        return _force_loading(d)
    if "path" in d:
        return _path_loading(d)
    lo = Loading()
    d0 = _number(d, "loading", "initial_separation", lo.initial_separation)
    if d0 < 0 or math.isinf(d0):
        _fail("loading.initial_separation", d0, "must be a finite number ≥ 0 (m)")
    final = _number(d, "loading", "final_penetration", lo.final_penetration)
    if math.isinf(final) or final <= -d0:
        _fail("loading.final_penetration", final, f"must be finite and > −initial_separation = {-d0:g} (m)")
    steps = _number(d, "loading", "steps", lo.steps, integer=True)
    if not 1 <= steps <= MAX_STEPS:
        _fail("loading.steps", steps, f"must be an integer in [1, {MAX_STEPS}]")
    return Loading(initial_separation=d0, final_penetration=final, steps=steps)


def _solver(d):
    _check_keys(d, "solver", Solver)
    so = Solver()
    method = d.get("method", so.method)
    if method not in _METHODS:
        _fail("solver.method", method, f"must be one of {list(_METHODS)}")
    tol = _number(d, "solver", "tolerance", so.tolerance)
    if not 1e-15 <= tol < 1:
        _fail("solver.tolerance", tol, "must lie in [1e-15, 1) (relative force residual)")
    iters = _number(d, "solver", "max_iterations", so.max_iterations, integer=True)
    if iters < 1:
        _fail("solver.max_iterations", iters, "must be an integer ≥ 1")
    unknowns = d.get("unknowns", so.unknowns)
    if unknowns not in _UNKNOWNS:
        _fail("solver.unknowns", unknowns, f"must be one of {list(_UNKNOWNS)} (auto: only what the scene requires)")
    checks = d.get("checks", so.checks)
    if checks not in _CHECKS:
        _fail("solver.checks", checks, f"must be one of {list(_CHECKS)}")
    return Solver(method=method, tolerance=tol, max_iterations=iters, unknowns=unknowns, checks=checks)


def _output(d):
    _check_keys(d, "output", Output)
    o = Output()
    fs = _number(d, "output", "field_steps", o.field_steps, integer=True)
    if not 0 <= fs <= MAX_STEPS:
        _fail("output.field_steps", fs, f"must be an integer in [0, {MAX_STEPS}]")
    workers = _number(d, "output", "workers", o.workers, integer=True)
    if workers < 0:
        _fail("output.workers", workers, "must be an integer ≥ 0 (0 = all cores)")
    return Output(field_steps=fs, workers=workers)


def _method(d):
    _check_keys(d, "method", Method)
    m = Method()
    name = d.get("name", m.name)
    if name not in METHOD_KEYS:
        _fail("method.name", name, f"must be one of {list(METHOD_KEYS)} (gfmd: the production solver; fe: the "
              "finite-element reference)")
    for key in d:
        if key != "name" and key not in METHOD_KEYS[name]:
            _fail(f"method.{key}", d[key], f"does not apply to method.name = {name!r} (its keys: "
                  f"{', '.join(('name',) + METHOD_KEYS[name])})")
    order = _number(d, "method", "order", m.order, integer=True)
    if order not in (1, 2):
        _fail("method.order", order, "must be 1 (P1) or 2 (P2)")
    linear = d.get("linear", m.linear)
    if linear not in _FE_LINEAR:
        _fail("method.linear", linear, f"must be one of {list(_FE_LINEAR)}")
    quadrature = d.get("quadrature", m.quadrature)
    if quadrature not in _FE_QUADRATURE:
        _fail("method.quadrature", quadrature, f"must be one of {list(_FE_QUADRATURE)}")
    if quadrature == "gauss" and linear not in ("dense", "auto"):
        _fail("method.quadrature", quadrature, f"needs method.linear = \"dense\" (got {linear!r})")
    return Method(name=name, order=order, linear=linear, quadrature=quadrature)
