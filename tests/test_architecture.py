"""The layering holds: core (gfmd_contact.core) ← methods (gfmd, reference.fem, reference.analytic) ← app
(gfmd_contact.app, and gfmd_contact: the Python API over it and the CLI over that).

Read from the source with `ast` (every import, top-level or inside a function):
the core imports no method and no app module; a method imports the core and
itself only, never another method or the app; nothing below the app imports it;
and no package has an import circle between its modules.
"""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LAYER = {"gfmd_contact.core": "core", "gfmd": "gfmd", "reference.fem": "fem", "reference.fem3d": "fem3d",
         "reference.analytic": "analytic", "reference._blas": "plumbing", "reference._material": "plumbing",
         "gfmd_contact.app": "app", "gfmd_contact": "app"}
#: which groups each group may import (besides itself). "plumbing": reference._blas, the single-threaded
#: OpenBLAS context both FE references run their dense surface solves in, and reference._material, the ν range a
#: displacement FE can solve; numerics, not the physics either FE checks, so sharing them keeps the FE references
#: independent of each other (they import no project module)
ALLOWED = {"core": set(), "gfmd": {"core"}, "fem": {"core", "plumbing"}, "fem3d": {"core", "plumbing"},
           "analytic": set(), "plumbing": set(), "app": {"core", "gfmd", "fem", "fem3d", "analytic", "plumbing"}}


def group(module):
    for prefix, name in sorted(LAYER.items(), key=lambda kv: -len(kv[0])):
        if module == prefix or module.startswith(prefix + "."):
            return name
    return None


def module_name(path):
    rel = path.relative_to(ROOT).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


def imports(path):
    """Absolute names of the project modules `path` imports (relative imports resolved)."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module
            found.add(mod)
            found.update(f"{mod}.{a.name}" for a in node.names)  # `from pkg import module`
    return {m for m in found if group(m) is not None}


def sources():
    for top in ("gfmd", "gfmd_contact", "reference"):
        yield from sorted((ROOT / top).rglob("*.py"))


def known_modules():
    return {module_name(p) for p in sources()}


def test_layers_import_downward_only():
    wrong = []
    for path in sources():
        mine = group(module_name(path))
        if mine is None or path.name == "__main__.py":  # `python -m gfmd` starts the app: an entry point
            continue
        for target in imports(path):
            theirs = group(target)
            if theirs != mine and theirs not in ALLOWED[mine]:
                wrong.append(f"{module_name(path)} ({mine}) imports {target} ({theirs})")
    assert not wrong, "\n".join(wrong)


@pytest.mark.parametrize("package", ["gfmd_contact.core", "gfmd", "reference.fem", "reference.fem3d",
                                     "gfmd_contact.app", "gfmd_contact"])
def test_no_import_circles(package):
    modules = known_modules()
    graph = {}
    for path in sources():
        name = module_name(path)
        if (name + ".").startswith(package + ".") and path.name != "__init__.py":  # gfmd_contact is not gfmd
            graph[name] = {t for t in imports(path) if t in modules and (t + ".").startswith(package + ".")
                           and not (ROOT / Path(*t.split(".")) / "__init__.py").is_file()} - {name}
    seen, stack = {}, []

    def visit(node):
        seen[node] = "active"
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if seen.get(nxt) == "active":
                raise AssertionError("import circle: " + " → ".join(stack[stack.index(nxt):] + [nxt]))
            if nxt not in seen:
                visit(nxt)
        stack.pop()
        seen[node] = "done"

    for node in sorted(graph):
        if node not in seen:
            visit(node)
    assert graph, f"no modules found for {package}"


def test_the_check_sees_a_violation(tmp_path, monkeypatch):
    """The import reader resolves relative and in-function imports (else the tests above prove nothing)."""
    fake = ROOT / "gfmd_contact" / "core" / "_probe_for_test.py"
    fake.write_text("def f():\n    from gfmd import solver\n\nfrom .scene import Scene\n")
    try:
        found = imports(fake)
        assert "gfmd.solver" in found and "gfmd_contact.core.scene" in found
        with pytest.raises(AssertionError, match="gfmd_contact.core._probe_for_test"):
            test_layers_import_downward_only()
    finally:
        fake.unlink()


#: what reference.fem may import from the core. The FE is an independent cross-check of GFMD:
#: it shares the inputs (the scene; the profile heights of gfmd_contact.core.surfaces), the
#: model choice and its checks (gfmd_contact.core.model), the one load ramp (gfmd_contact.core.ramp) and the result
#: and error types, and nothing it checks. Not gfmd_contact.core.laws nor gfmd_contact.core.law_equations (the FE has reference.fem.law),
#: gfmd_contact.core.observables (reference.fem.observables, through Cell.observe), gfmd_contact.core.loading
#: (z_ind: reference.fem.geometry), nor gfmd_contact.core.kernels: the elastic kernels are what
#: verification/test_fe_linear checks against the FE, so the FE solver must not use them (the
#: verification tests may). gfmd_contact.core.user_law: a user-defined law is an input (the user's callables), with
#: nothing to be independent from; the FE's built-in laws stay its own. gfmd_contact.core.law_registry: a law the FE has
#: no implementation of (the user law, a newly added law) is built there and consumed through the law protocol
#: (reference.fem.law.LawZone), as the user law is. The scene is gfmd_contact.core.scene and
#: the modules it is split into (scene_sections, scene_validation, scene_toml): input, as it.
FE_MAY_IMPORT = {"gfmd_contact.core", "gfmd_contact.core.scene", "gfmd_contact.core.scene_sections", "gfmd_contact.core.scene_validation", "gfmd_contact.core.scene_toml",
                 "gfmd_contact.core.surfaces", "gfmd_contact.core.model", "gfmd_contact.core.ramp", "gfmd_contact.core.result", "gfmd_contact.core.errors",
                 "gfmd_contact.core.user_law", "gfmd_contact.core.law_registry"}


def fe_core_imports(root=ROOT, package="fem"):
    """{FE module: core modules it imports that FE_MAY_IMPORT does not list} for reference/<package>."""
    modules = known_modules() | {"gfmd_contact.core"}

    def owner(name):  # gfmd_contact.core.ramp.StepSolution → gfmd_contact.core.ramp
        while name not in modules and "." in name:
            name = name.rpartition(".")[0]
        return name

    wrong = {}
    for path in sorted((root / "reference" / package).rglob("*.py")):
        bad = {owner(t) for t in imports(path) if group(t) == "core"} - FE_MAY_IMPORT
        if bad:
            wrong[module_name(path)] = sorted(bad)
    return wrong


@pytest.mark.parametrize("package", ["fem", "fem3d"])
def test_fe_reference_shares_only_its_inputs_with_gfmd(package):
    """Both FE references (1+1-D reference.fem, 3-D reference.fem3d) import from the core only FE_MAY_IMPORT."""
    wrong = fe_core_imports(package=package)
    assert not wrong, "reference.fem imports code it checks: " + "; ".join(f"{m}: {', '.join(t)}"
                                                                         for m, t in wrong.items())


@pytest.mark.parametrize("source", ["from gfmd_contact.core import laws\n", "from gfmd_contact.core.observables import rms_gradient\n",
                                    "def f():\n    from gfmd_contact.core.loading import indenter_surface\n",
                                    "import gfmd_contact.core.kernels\n"])
@pytest.mark.parametrize("package", ["fem", "fem3d"])
def test_the_fe_check_sees_a_violation(source, package):
    fake = ROOT / "reference" / package / "_probe_for_test.py"
    fake.write_text(source)
    try:
        assert f"reference.{package}._probe_for_test" in fe_core_imports(package=package)
    finally:
        fake.unlink()


#: one module per GFMD algorithm: each is `solve(problem, start, settings) -> Relaxed` over the
#: problem of gfmd.problem, and none imports another: a fallback is a link of its law's chain (gfmd.chains)
ALGORITHMS = ROOT / "gfmd" / "algorithms"


def algorithm_cross_imports(folder=ALGORITHMS):
    """{algorithm module: the other algorithm modules it imports}."""
    paths = sorted(p for p in folder.glob("*.py") if p.name != "__init__.py")
    names = {module_name(p) for p in paths}
    wrong = {}
    for path in paths:
        me = module_name(path)
        bad = {a for t in imports(path) for a in names - {me} if t == a or t.startswith(a + ".")}
        if bad:
            wrong[me] = sorted(bad)
    return wrong


def test_no_algorithm_imports_another():
    wrong = algorithm_cross_imports()
    assert not wrong, "; ".join(f"{m} imports {', '.join(t)}" for m, t in wrong.items())


@pytest.mark.parametrize("source", ["from .ncg import solve\n", "from . import dynamics\n",
                                    "def f():\n    from gfmd.algorithms import coupled_newton\n",
                                    "import gfmd.algorithms.hard_wall_primal_cg\n"])
def test_the_algorithm_check_sees_a_violation(source):
    fake = ALGORITHMS / "_probe_for_test.py"
    fake.write_text(source)
    try:
        assert "gfmd.algorithms._probe_for_test" in algorithm_cross_imports()
    finally:
        fake.unlink()


#: the non-algorithm gfmd modules the algorithms import (plumbing such as gfmd.fft, gfmd.stopping, and the
#: shared loop gfmd.dual_cg: the projected dual CG both dual hard-wall algorithms run, each with its own
#: preconditioner) import no algorithm, or the ban above would be side-stepped through them
def shared_modules_importing_algorithms(folder=ALGORITHMS):
    """{gfmd module an algorithm imports: the algorithm modules it imports}."""
    shared = {t for p in folder.glob("*.py") for t in imports(p)
              if t.startswith("gfmd.") and not t.startswith("gfmd.algorithms")}
    paths = [path for t in sorted(shared) if (path := ROOT / (t.replace(".", "/") + ".py")).exists()]
    wrong = {}
    for path in paths:
        bad = sorted(t for t in imports(path) if t == "gfmd.algorithms" or t.startswith("gfmd.algorithms."))
        if bad:
            wrong[module_name(path)] = bad
    return wrong


def test_shared_algorithm_modules_import_no_algorithm():
    wrong = shared_modules_importing_algorithms()
    assert not wrong, "; ".join(f"{m} imports {', '.join(t)}" for m, t in wrong.items())


def test_the_shared_module_check_sees_a_violation():
    shared, fake = ROOT / "gfmd" / "_probe_shared_for_test.py", ALGORITHMS / "_probe_for_test.py"
    shared.write_text("from .algorithms import ncg\n")
    fake.write_text("from .._probe_shared_for_test import ncg\n")
    try:
        assert "gfmd._probe_shared_for_test" in shared_modules_importing_algorithms()
    finally:
        fake.unlink()
        shared.unlink()


def test_every_algorithm_solves_the_problem():
    """Each algorithm module has solve(problem, start, settings), and the chains name only those modules."""
    import importlib
    import inspect

    from gfmd import chains

    modules = {p.stem for p in ALGORITHMS.glob("*.py") if p.name != "__init__.py"}
    for name in modules:  # a module with options of its own (`Options`, as scipy's per-method options) names them so
        module = importlib.import_module(f"gfmd.algorithms.{name}")
        third = "options" if hasattr(module, "Options") else "settings"
        assert list(inspect.signature(module.solve).parameters) == ["problem", "start", third], name
    assert set(chains.ALGORITHMS) == modules
    assert {link.algorithm for chain in chains.CHAINS.values() for link in chain} <= modules


#: the most lines a module of the methods may have (the developers' guide: "rarely over ~500")
METHOD_MODULE_LINES = 500


def test_method_modules_stay_small():
    """Every module of the methods (GFMD, both FE references, the analytic solutions)."""
    paths = [p for top in ("gfmd", "reference") for p in (ROOT / top).rglob("*.py") if not p.name.startswith("_probe")]
    long = {module_name(p): n for p in paths if (n := len(p.read_text().splitlines())) > METHOD_MODULE_LINES}
    assert not long, f"method modules over {METHOD_MODULE_LINES} lines: {long}"


def test_ramp_records_check_uses_its_own_code():
    """verification/ramp_records.py recomputes what the shared ramp records: it imports no
    project package (gfmd, reference, gfmd_contact), only the standard library and numpy."""
    tree = ast.parse((ROOT / "verification" / "ramp_records.py").read_text(encoding="utf-8"))
    names = {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    names |= {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module and not n.level}
    assert not any(isinstance(n, ast.ImportFrom) and n.level for n in ast.walk(tree))
    assert {m.split(".")[0] for m in names} <= {"__future__", "csv", "json", "tomllib", "pathlib", "numpy"}, names


#: the top-level import names an install may add (the architecture's "one namespace")
TOP_LEVEL_NAMES = {"gfmd", "gfmd_contact", "reference", "verification"}


def test_install_adds_only_the_design_top_level_names():
    """pyproject's package patterns, matched against the source tree as setuptools matches them, install no generic
    top-level name (a `contact` or `workbench` of ours would shadow, or be shadowed by, another package's)."""
    import fnmatch
    import tomllib

    patterns = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]["find"]["include"]
    packages = {".".join(p.parent.relative_to(ROOT).parts) for p in ROOT.rglob("__init__.py") if ".git" not in p.parts}
    installed = {p for p in packages if any(fnmatch.fnmatchcase(p, pat) for pat in patterns)}
    assert {"gfmd", "gfmd_contact", "gfmd_contact.core", "gfmd_contact.app", "reference", "verification"} <= installed
    assert {p.split(".")[0] for p in installed} <= TOP_LEVEL_NAMES, sorted(installed)
