"""Physics core of the pendulum-type particle impact damper (plain Python + math).

Knows nothing of FMI.  The FMU (pidamper_fmu) is a thin adapter over `Damper`.
This package uses relative imports only, so the FMU can ship it under another
name (see build_fmu).  The same sources also run compiled (Cython, build_fmu.compile),
bit for bit; BUILD says which build runs (_build.py chooses, before any other module loads).
"""
from ._build import BUILD
from .damper import FREE, OUTSIDE, STICK, Damper
from .impact import collide, impact_loss
from .oscillator import Oscillator
from .params import ANGLE, DEFAULTS, DISPLACEMENT, INITIAL_DEFAULTS, ParameterError, Params
from .stepping import same_bits
from .validity import DriftMonitor, SmallAngleMonitor, frequency_error

__all__ = ["BUILD", "ANGLE", "DEFAULTS", "DISPLACEMENT", "INITIAL_DEFAULTS", "FREE", "OUTSIDE", "STICK", "Damper", "Oscillator",
           "ParameterError", "Params", "DriftMonitor", "SmallAngleMonitor", "collide", "frequency_error", "impact_loss",
           "same_bits"]
