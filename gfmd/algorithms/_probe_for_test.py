from . import dynamics
