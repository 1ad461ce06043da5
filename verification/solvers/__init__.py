"""Solver adapters: any contact code answers the verification's cross-code cases through one protocol.

`protocol` fixes what a case gives a code (`Problem`) and what the code returns (`Answer`); `registry`
finds the adapters by name (ours built in, a third party's through the entry-point group
``gfmd_contact.solvers``). `gfmd` is the adapter a third party copies.
"""

from verification.solvers.protocol import (
    Answer,
    Capabilities,
    Cost,
    Interface,
    Problem,
    Solver,
    State,
    not_applicable,
)
from verification.solvers.registry import SolverUnavailable, get, solvers

__all__ = ["Answer", "Capabilities", "Cost", "Interface", "Problem", "Solver", "SolverUnavailable", "State", "get",
           "not_applicable", "solvers"]
