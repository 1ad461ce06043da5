"""Find solver adapters by name: ours built in, a third party's through the entry-point group
``gfmd_contact.solvers`` (``name = "package.module:factory"``; the factory returns a `Solver`).

A built-in whose package is not installed is reported by `get` with the install hint, not a traceback.
"""

from __future__ import annotations

import importlib
from importlib.metadata import entry_points

GROUP = "gfmd_contact.solvers"

#: built-in adapters: name → (module, factory, the pip extra that brings the peer package)
BUILTINS = {"gfmd": ("verification.solvers.gfmd", "GFMDSolver", None),
            "fe": ("verification.solvers.fe", "FESolver", None),
            "tamaas": ("verification.solvers.tamaas", "TamaasSolver", "gfmd-contact[tamaas]"),
            "contactmechanics": ("verification.solvers.contactmechanics", "ContactMechanicsSolver",
                                 "gfmd-contact[contactmechanics]")}


class SolverUnavailable(LookupError):
    """An adapter that is unknown, or whose code is not installed (the message says how to install it)."""


def _builtin_loader(name):
    module, factory, extra = BUILTINS[name]

    def load():
        try:
            return getattr(importlib.import_module(module), factory)()
        except ImportError as exc:
            if exc.name == module:  # the adapter itself, not the code it wraps
                raise SolverUnavailable(f"solver {name!r}: its adapter module {module} is missing") from exc
            hint = f": pip install '{extra}'" if extra else ""
            raise SolverUnavailable(f"solver {name!r} is not installed ({exc}){hint}") from exc
    return load


def _entry_point_loader(ep):
    def load():
        try:
            return ep.load()()
        except ImportError as exc:
            raise SolverUnavailable(f"solver {ep.name!r} (entry point {ep.value}) cannot be imported: {exc}") from exc
    return load


def solvers() -> dict:
    """{name: factory} — the built-ins, then the entry points (which may not shadow a built-in name)."""
    found = {name: _builtin_loader(name) for name in BUILTINS}
    for ep in entry_points(group=GROUP):
        if ep.name not in found:
            found[ep.name] = _entry_point_loader(ep)
    return found


def get(name: str):
    """The adapter called `name`; `SolverUnavailable` naming the known solvers, or the install hint."""
    known = solvers()
    if name not in known:
        raise SolverUnavailable(f"unknown solver {name!r}; known: {', '.join(sorted(known))} (register another "
                                f"through the entry-point group {GROUP!r})")
    return known[name]()
