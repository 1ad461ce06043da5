"""Static equilibrium of one load step: the names other code imports, from the modules that own them.

The solver is split into the problem (`gfmd.problem`: energy, force, Hessian product,
the hard wall and its dual), one module per algorithm (`gfmd.algorithms`), their shared stopping
test (`gfmd.stopping`), FFT (`gfmd.fft`), steppers (`gfmd.integrators`) and the chain that picks
and falls back between them per law (`gfmd.chains`, whose `relax` this is).
"""

from __future__ import annotations

from .chains import COUPLED_FIRE_BUDGET, relax
from .fft import Fft as _Fft
from .fft import fft_backend
from .problem import InterfaceLaw, Problem
from .settings import Relaxed, Settings

__all__ = ["COUPLED_FIRE_BUDGET", "InterfaceLaw", "Problem", "Relaxed", "Settings", "_Fft", "fft_backend", "relax"]
