"""pidamper: fmpy harness for the PendulumImpactDamper FMU.

Public API: find_fmu, run, RunResult, forcing (signal generators), measures,
FmuStepper / CoreStepper (step-by-step drivers with save/restore).
"""
from . import forcing, measures
from .running.fmu import find_fmu
from .running.simulation import OUTPUTS, FmuError, RunResult, resonance, run
from .running.stepper import CoreStepper, FmuStepper

__all__ = ["OUTPUTS", "CoreStepper", "FmuError", "FmuStepper", "RunResult", "find_fmu", "forcing", "measures",
           "resonance", "run"]
