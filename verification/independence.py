"""What the FE reference shares with GFMD on purpose, read from the code (the report's "Independence" section).

The allowed list is `FE_MAY_IMPORT` of tests/test_architecture.py (read with `ast`, not copied: that test
fails on any other core import of `reference.fem`); the FE's actual core imports are read from
reference/fem/*.py the same way.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: what each shared core module provides to the FE (a module missing here is shown as "not described")
PURPOSE = {
    "gfmd_contact.core": "the package itself (its __init__)",
    "gfmd_contact.core.scene": "the scene: the one input both methods read (geometry, material, law parameters, load steps)",
    "gfmd_contact.core.scene_sections": "the scene's sections and their defaults (gfmd_contact.core.scene's dataclasses, split out)",
    "gfmd_contact.core.scene_validation": "the scene's TOML checks and refusals (gfmd_contact.core.scene's reader, split out)",
    "gfmd_contact.core.scene_toml": "the scene written back as TOML (gfmd_contact.core.scene's writer, split out)",
    "gfmd_contact.core.surfaces": "the profile heights h(x) built from the scene (same nodes, same realization)",
    "gfmd_contact.core.model": "the model choice and its checks (which law/layer the scene asks for)",
    "gfmd_contact.core.ramp": "the load steps (the one δ ramp, its continuation and checkpoints)",
    "gfmd_contact.core.result": "the result type the FE returns (curves, fields)",
    "gfmd_contact.core.errors": "the error types",
    "gfmd_contact.core.user_law": "a user-defined law (interface.law = \"user\") only: the user's own functions, an input with "
                        "nothing to be independent from; the built-in laws stay reference.fem.law's",
    "gfmd_contact.core.law_registry": "a law the FE has no implementation of (the user law, a newly added law such as "
                                      "the LJ 9-3 wall) only: built there and evaluated through the law protocol "
                                      "(reference.fem.law.LawZone); the built-in laws stay reference.fem.law's",
}

#: what the FE computes with its own code (module of reference.fem), not shared
INDEPENDENT = {
    "elasticity (no gfmd_contact.core.kernels: the half-plane/layer kernels are what the FE checks)": "reference.fem.assembly",
    "cohesive-zone law (seed Eqs. 2-3)": "reference.fem.law",
    "observables p, a_rel, g_r, ḡ_r, contact set": "reference.fem.observables",
    "indenter geometry and position z_ind": "reference.fem.geometry",
    "hard-wall contact": "reference.fem.hardwall",
    "solver (Newton, fallback)": "reference.fem.solver",
}


def allowed_imports(path=None):
    """The set FE_MAY_IMPORT of tests/test_architecture.py, read with ast."""
    path = Path(path or ROOT / "tests" / "test_architecture.py")
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "FE_MAY_IMPORT" for t in node.targets):
            return set(ast.literal_eval(node.value))
    raise LookupError(f"no FE_MAY_IMPORT in {path}")


def fe_core_imports(root=None):
    """{core module: [reference.fem modules importing it]} (imports anywhere in the file)."""
    root = Path(root or ROOT)
    core = {".".join(p.relative_to(root).with_suffix("").parts) for p in (root / "gfmd_contact" / "core").glob("*.py")}
    core = {c.removesuffix(".__init__") for c in core}
    found = {}
    for path in sorted((root / "reference" / "fem").glob("*.py")):
        mod = "reference.fem." + path.stem
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
                names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
            for n in names:
                if n == "gfmd_contact.core" or n.startswith("gfmd_contact.core."):
                    while n not in core and "." in n:
                        n = n.rpartition(".")[0]
                    found.setdefault(n, set()).add(mod)
    return {k: sorted(v) for k, v in found.items()}


def fe_shared_inputs(root=None):
    """{"shared": [(module, what, [FE users])] for every allowed module, "independent": INDEPENDENT,
    "not_allowed": {module: [FE users]} (core imports outside the list; empty when the architecture test passes)}."""
    allowed = allowed_imports(Path(root) / "tests" / "test_architecture.py" if root else None)
    used = fe_core_imports(root)
    shared = [(m, PURPOSE.get(m, "not described"), used.get(m, [])) for m in sorted(allowed)]
    return {"shared": shared, "independent": INDEPENDENT,
            "not_allowed": {m: u for m, u in used.items() if m not in allowed}}
