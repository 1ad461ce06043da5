"""Study files: parse and validate a study (TOML) into its parameter sets and content-addressed tasks.

Units: SI (see `gfmd_contact.core.conventions`). A study file (TOML) names a base scene and axes
over scene keys by their dotted names:

    name = "fig3_small"                 # optional; default: the file's stem
    base = "fig3_base.toml"             # relative to the study file; or an inline [scene] table
    [axes]                              # the grid is the product of the axes (file order)
    "interface.length_normal" = [0.25e-9, 1e-9]
    [zip]                               # optional: keys that vary together (equal lengths)
    "interface.law" = ["hard-wall", "cohesive", "cohesive"]
    "interface.phi_n_star" = [0.15, 0.001, 0.15]

A parameter set ("set", numbered 0, 1, … in product order, the zip index innermost) is
the base scene with one value of every axis (and one zip entry); each (set,
realization) is one task: the set's scene with surface.seed = seed + realization and
surface.realizations = 1, run as realization 0 (the profile depends on the realization
only through its seed, so this is the same realization as in `gfmd run`). Every set is
validated with `Scene.replace` and the run's checks before any compute; a bad axis (an
unknown key, a value out of range, zip lengths that differ, a key given twice) is refused
naming the key.

A task's address (its directory DIR/tasks/<key>/) is the first 16 hex digits of the SHA-256
of the task scene's values that differ from the scene defaults (`task_key_text`): a newer
version that adds a scene key with a default keeps every address. Running a study is
`gfmd_contact.app.study`; one task on a worker `gfmd_contact.app.study_task`; its tables `gfmd_contact.app.study_tables`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import itertools
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from gfmd_contact.core.errors import SceneError
from gfmd_contact.core.scene import Scene, load_scene, scene_from_dict, scene_to_dict

from .methods import solve_key

STUDY_KEYS = ("name", "description", "base", "scene", "axes", "zip")

#: the most tasks a study runs without being told to (`gfmd study run --yes`, `yes=True` in Python): loading
#: (validating) 10^4 tasks takes about 13 s and each task writes a directory; more is refused, naming the count
MAX_TASKS = 10_000

TASK_NAME = "task"


class StudyError(SceneError):
    """A study file that cannot run: the message names the file and the key."""


@dataclass(frozen=True)
class Task:
    key: str
    set: int
    realization: int
    seed: int
    scene: object  # gfmd_contact.core.scene.Scene, realization 0 of it is run


@dataclass
class Study:
    name: str
    path: Path | None
    text: str
    base: object  # the base Scene
    axes: dict  # key -> list of values (the grid)
    zipped: dict  # key -> list of values (vary together)
    sets: list = field(default_factory=list)  # [{key: value}] for every parameter set
    scenes: list = field(default_factory=list)  # the Scene of every set
    index: list = field(default_factory=list)  # per set: (axis indices..., zip index or None)

    @property
    def keys(self):
        """Every varied key: the axes, then the zipped keys."""
        return list(self.axes) + list(self.zipped)

    @property
    def tasks(self):
        out = []
        for s, scene in enumerate(self.scenes):
            for r in range(scene.surface.realizations):
                task = task_scene(scene, r)
                out.append(Task(task_key(task), s, r, scene.surface.seed + r, task))
        return out


def task_scene(scene, realization):
    """The one-realization scene of (scene, realization): seed + realization, 1 realization, run as 0."""
    task = scene.replace(**{"surface.seed": scene.surface.seed + realization, "surface.realizations": 1,
                            "output.workers": 1})
    return dataclasses.replace(task, name=TASK_NAME)


_MISSING = object()
_DEFAULTS = {section: dataclasses.asdict(getattr(Scene(), section)) for section in scene_to_dict(Scene())}
_DEFAULTS["material"]["thickness"] = "inf"


def task_key_text(task):
    """What a task's address hashes: its resolved values that differ from `gfmd_contact.core.scene`'s defaults.

    One "section.key = value" line each, sorted. A key that a later version adds with a default
    equal to the old behaviour leaves every address unchanged, so upgrading the code loses no
    finished task; a reused task's stored scene.toml is compared key by key with the current
    resolved scene (`run_task`), so a changed default is caught instead of reused.
    """
    d = scene_to_dict(task)
    return "".join(f"{section}.{k} = {v!r}\n" for section, values in sorted(d.items())
                   for k, v in sorted(values.items()) if _DEFAULTS.get(section, {}).get(k, _MISSING) != v)


def task_key(task):
    """Content address of a task: the first 16 hex digits of sha256(`task_key_text`(task))."""
    return hashlib.sha256(task_key_text(task).encode()).hexdigest()[:16]


#: relative cost factors of `task_cost`, from the seed's full-scale task times (N = 2^17, 200 steps, one
#: core each; studies/results/seed_full/README.md): a cohesive task 9 s (1 + 50 φn*) (measured 9, 11, 13,
#: 31, 76 s at φn* = 0.001 … 0.15), the hard wall 27 s, a coupled law (tangential_ratio > 0) 240–720 s
#: against 40 s for its normal law (fig8)
COST_HARD_WALL, COST_PER_PHI, COST_COUPLED = 3.0, 50.0, 10.0


def task_cost(scene):
    """A task scene's relative cost (arbitrary units), only to order tasks longest first (`longest_first`).

    steps × N log₂N (N nodes, N_x N_y in 2+1-D) × the law's factor (`COST_HARD_WALL`; cohesive laws
    1 + `COST_PER_PHI` φn*; × `COST_COUPLED` with tangential_ratio > 0) × the contact the loading reaches,
    final_penetration / (2 h_rms) within [0.1, 1] (1 where h_rms is 0): at δ = 20 nm the seed's tasks
    at h_rms = 10, 15, 30 nm took 1 : 0.5 : 0.25 of the time, hard wall and cohesive alike.
    """
    import math

    surface, interface = scene.surface, scene.interface
    n = surface.nodes * max(surface.nodes_y, 1)
    law = COST_HARD_WALL if interface.law == "hard-wall" else 1.0 + COST_PER_PHI * interface.phi_n_star
    if interface.tangential_ratio > 0:
        law *= COST_COUPLED
    contact = (min(1.0, max(0.1, scene.loading.final_penetration / (2 * surface.h_rms)))
               if surface.h_rms > 0 else 1.0)
    return scene.loading.steps * n * math.log2(max(n, 2)) * law * contact


def solve_address(scene):
    """The address of the solve a task scene runs: `task_key` of its `gfmd_contact.app.methods.solve_key`, the
    same for tasks that differ only in `gfmd_contact.core.observation.OBSERVATION_KEYS`; its own key where it shares
    no solve (None solve key)."""
    shared = solve_key(scene)
    return "solve-" + task_key(shared) if shared is not None else task_key(scene)


def solve_groups(jobs):
    """`jobs` [(key, task scene, ...)] grouped by `solve_address` (a group: one solve, `run_shared`), in
    the order of each group's first job: jobs ordered `longest_first` give the groups longest first,
    each counted once (its members cost one solve)."""
    groups = {}
    for job in jobs:
        groups.setdefault(solve_address(job[1]), []).append(job)
    return list(groups.values())


def longest_first(tasks):
    """`tasks` ordered by decreasing `task_cost` (ties keep their order): the classic longest-processing-
    time-first order, which on a few workers shortens the tail where one long task runs alone."""
    return sorted(tasks, key=lambda t: -task_cost(t.scene))


def _values(where, key, values, unique=True):
    if not isinstance(values, list) or not values:
        raise StudyError(f"{where} {key!r} = {values!r}: must be a non-empty list of values")
    seen = []
    for v in values:
        if isinstance(v, (dict, list)):
            raise StudyError(f"{where} {key!r}: value {v!r} must be a number, string or boolean")
        if unique and (type(v), v) in seen:
            raise StudyError(f"{where} {key!r}: value {v!r} appears twice")
        seen.append((type(v), v))
    return values


def _check_key(where, key):
    section, _, name = key.partition(".")
    if not name or not section:
        raise StudyError(f"{where} key {key!r}: must be a dotted scene key like \"interface.phi_n_star\"")


def study_from_dict(d, *, path=None, text="", name=None, yes=False, note=None):
    """Parse and validate a study (dict of the TOML); every parameter set is built and checked.

    Before that, the task count and estimated cost (`study_size`) go to note(line), and a study of more than
    MAX_TASKS tasks is refused unless `yes`."""
    label = f"study {str(path)!r}" if path else "study"
    if not isinstance(d, dict):
        raise StudyError(f"{label}: must be a TOML table")
    for key in d:
        if key not in STUDY_KEYS:
            raise StudyError(f"{label}: unknown key {key!r}; valid keys: {', '.join(STUDY_KEYS)}")
    if ("base" in d) == ("scene" in d):
        raise StudyError(f"{label}: give exactly one of base = \"SCENE.toml\" (relative to the study file) "
                         "or an inline [scene] table")
    if "base" in d:
        if not isinstance(d["base"], str):
            raise StudyError(f"{label}: base = {d['base']!r}: must be a path to a scene TOML file")
        p = Path(d["base"])
        if not p.is_absolute() and path is not None:
            p = Path(path).parent / p
        try:
            base = load_scene(p)
        except SceneError as exc:
            raise StudyError(f"{label}: base scene: {exc}") from None
    else:
        try:
            base = scene_from_dict(d["scene"], name="scene")
        except SceneError as exc:
            raise StudyError(f"{label}: [scene]: {exc}") from None
    study_name = d.get("name", name or (Path(path).stem if path else "study"))
    if not isinstance(study_name, str) or not study_name:
        raise StudyError(f"{label}: name = {study_name!r}: must be a non-empty string")
    import dataclasses

    base = dataclasses.replace(base, name=study_name)
    axes, zipped = d.get("axes", {}), d.get("zip", {})
    for section, table in (("[axes]", axes), ("[zip]", zipped)):
        if not isinstance(table, dict):
            raise StudyError(f"{label}: {section} must be a table of \"section.key\" = [values]")
        for key, values in table.items():
            _check_key(f"{label}: {section}", key)
            _values(f"{label}: {section}", key, values, unique=section == "[axes]")  # zip: entries repeat
    both = [k for k in axes if k in zipped]
    if both:
        raise StudyError(f"{label}: {both[0]!r} is both in [axes] and in [zip]: give it once")
    if zipped and len({len(v) for v in zipped.values()}) > 1:
        lengths = ", ".join(f"{k!r}: {len(v)}" for k, v in zipped.items())
        raise StudyError(f"{label}: [zip] lists must have equal lengths (they vary together); got {lengths}")
    _check_size(label, study_name, base, axes, zipped, yes, note)
    entries = list(zip(*([(type(x), x) for x in v] for v in zipped.values())))
    if len(set(entries)) != len(entries):
        raise StudyError(f"{label}: [zip] keys {', '.join(map(repr, zipped))}: an entry appears twice")
    # every value alone, so that the message names the key and the value
    for section, table in (("[axes]", axes), ("[zip]", zipped)):
        for key, values in table.items():
            for v in values:
                try:
                    base.replace(**{key: v})
                except SceneError as exc:
                    raise StudyError(f"{label}: {section} {key!r} = {v!r}: {exc}") from None
    study = Study(name=study_name, path=Path(path) if path else None, text=text, base=base, axes=axes,
                  zipped=zipped)
    zip_len = len(next(iter(zipped.values()))) if zipped else 0
    for combo in itertools.product(*(range(len(v)) for v in axes.values())):
        for z in (range(zip_len) if zipped else [None]):
            params = {k: axes[k][i] for k, i in zip(axes, combo)}
            if z is not None:
                params.update({k: v[z] for k, v in zipped.items()})
            try:
                scene = base.replace(**params)
                _run_checks(scene)
            except SceneError as exc:
                raise StudyError(f"{label}: parameter set {len(study.sets)} ({_describe(params)}): {exc}") from None
            study.sets.append(params)
            study.scenes.append(scene)
            study.index.append(combo + ((z,) if zipped else ()))
    keys = [t.key for t in study.tasks]
    if len(set(keys)) != len(keys):
        raise StudyError(f"{label}: two parameter sets give the same scene (check the axes for values that "
                         "change nothing)")
    return study


def study_size(base, axes, zipped):
    """(sets, tasks, node-steps, peak memory of one task (bytes), compute time (s) or None) of a study, from its axes'
    lengths and the base scene (the realizations, nodes and steps the axes give at most), without building a set; the
    time: the base task's `estimate_seconds` scaled by the study's node-steps over the base task's."""
    import math

    from gfmd_contact.core.cost import estimate_peak_memory, estimate_seconds

    sets = math.prod(len(v) for v in axes.values()) * (len(next(iter(zipped.values()))) if zipped else 1)

    def most(key, default):
        values = [v for table in (axes, zipped) for v in table.get(key, []) if isinstance(v, (int, float))]
        return max([default] + values)

    realizations = int(most("surface.realizations", base.surface.realizations))
    s = base.surface
    nodes = int(most("surface.nodes", s.nodes)) * max(int(most("surface.nodes_y", s.nodes_y)), 1)
    steps = int(most("loading.steps", base.loading.steps)) if not base.loading.path else base.loading.steps
    task = task_scene(base, 0)
    memory, one = estimate_peak_memory(task), estimate_seconds(task, workers=1)
    work = sets * realizations * nodes * (steps + 1)
    seconds = None if one is None else one * work / (s.nodes * max(s.nodes_y, 1) * (base.loading.steps + 1))
    return sets, sets * realizations, work, memory, seconds


def _check_size(label, name, base, axes, zipped, yes, note):
    """Say the study's size before validating its sets; refuse above MAX_TASKS unless `yes`."""
    from gfmd_contact.core.cost import TIME_FACTOR

    sets, tasks, work, memory, seconds = study_size(base, axes, zipped)
    size = (f"{sets} parameter set(s), {tasks} task(s), estimated cost {work:.3g} node-steps (nodes × load steps, "
            f"summed), peak memory about {memory / 2**20:.0f} MiB per worker"
            + ("" if seconds is None else f", compute time about {seconds / 3600:.3g} CPU-h (within ×{TIME_FACTOR} "
               "either way; divide by the workers)"))
    if tasks > MAX_TASKS and not yes:
        raise StudyError(f"{label}: [axes] / [zip] give {size}: more than MAX_TASKS = {MAX_TASKS} "
                         "(gfmd_contact.app.study_file); shorten the axes or surface.realizations, or confirm with "
                         "`gfmd study run --yes` (Python: yes=True)")
    if note is not None:
        note(f"study {name!r}: {size}; validating every set before any compute")


def _run_checks(scene):
    """The refusals `gfmd run` makes before compute (the method's, gfmd_contact.core.loading.preflight)."""
    from gfmd_contact.core.loading import preflight

    from .methods import method_of

    method_of(scene).refuse(scene)
    preflight(scene)


def _describe(params):
    return ", ".join(f"{k} = {v!r}" for k, v in params.items()) or "the base scene"


def load_study(path, *, yes=False, note=None):
    """Read and validate a study file (module docstring); yes, note: `study_from_dict`'s."""
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise StudyError(f"study file {str(path)!r} not found") from None
    if path.is_dir():
        raise StudyError(f"study file {str(path)!r} is a directory")
    try:
        d = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise StudyError(f"study file {str(path)!r} is not valid TOML: {exc}") from None
    return study_from_dict(d, path=path, text=text, name=path.stem, yes=yes, note=note)
