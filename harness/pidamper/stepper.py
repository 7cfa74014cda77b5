"""Step-by-step drivers with save/restore, for measures that need the continuous solution.

Both steppers share one protocol (t, advance, read, save, restore, discard,
close) so the measures run unchanged on the FMU (through fmpy's FMU2Slave) or
on the physics core directly.  The external force, if any, is sampled at the
start of each advance and held (as a co-simulation host does).
"""
import re
import shutil
from ctypes import byref

import fmpy
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (FMU2Slave, calloc, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, fmi2Fatal, free)
from fmpy.logging import addLoggerProxy

from pidamper_physics import INITIAL_DEFAULTS, Damper, Params


def fmi2_callbacks(logger):
    """FMI 2 callbacks as fmpy.simulate_fmu builds them (its C proxy formats the model's text),
    calling logger(status, text)."""
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(
        lambda component, instance, status, category, message: logger(status, message.decode(errors="replace")))
    callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    addLoggerProxy(byref(callbacks))
    return callbacks


class FmuStepper:
    """The damper FMU driven by fmpy's FMU2Slave."""

    def __init__(self, fmu_path, start_values=None, forcing=None, start_time=0.0, instance_name="pidamper",
                 logger=None):
        """logger(status, text): hears the model's messages (debug logging on), else they are dropped."""
        self._md = md = fmpy.read_model_description(str(fmu_path))
        self._dir = fmpy.extract(str(fmu_path))
        self._vars = {v.name: v for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=self._dir,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance_name)
        self.forcing = forcing
        self.t = float(start_time)
        self.fatal = False  # after fmi2Fatal the FMI standard forbids any further call
        self._closed = False
        fmu = self.fmu
        if logger is None:
            fmu.instantiate()
        else:
            self._callbacks = fmi2_callbacks(logger)  # kept alive as long as the instance
            fmu.instantiate(callbacks=self._callbacks, loggingOn=True)
        try:
            self._call(fmu.setupExperiment, startTime=self.t)
            self._call(fmu.enterInitializationMode)
            for name, value in (start_values or {}).items():
                self.set(name, value)
            self._call(fmu.exitInitializationMode)
        except Exception:
            self.close()
            raise
        self._vr_read = [self._vars[n].valueReference for n in ("theta", "theta_dot")]

    def set(self, name, value):
        var = self._vars.get(name)
        if var is None:
            raise KeyError(f"{name!r} is not a variable of the FMU")
        if var.type == "Integer":
            self._call(self.fmu.setInteger, [var.valueReference], [int(value)])
        else:
            self._call(self.fmu.setReal, [var.valueReference], [float(value)])

    def get(self, name):
        var = self._vars[name]
        if var.type == "Integer":
            return self.fmu.getInteger([var.valueReference])[0]
        return self.fmu.getReal([var.valueReference])[0]

    def advance(self, t_end):
        if self.forcing is not None:
            self.set(self.forcing.target, float(self.forcing.value(self.t)))
        self.do_step(self.t, t_end - self.t)

    def do_step(self, current_time, step_size):
        """fmi2DoStep as a host would call it (the times are not checked here)."""
        self._call(self.fmu.doStep, currentCommunicationPoint=current_time, communicationStepSize=step_size)
        self.t = current_time + step_size

    def _call(self, function, *args, **kwargs):
        try:
            return function(*args, **kwargs)
        except FMICallException as err:
            self.fatal = self.fatal or err.status == fmi2Fatal
            raise

    def read(self):
        """(theta, theta_dot) now."""
        theta, theta_dot = self.fmu.getReal(self._vr_read)
        return theta, theta_dot

    def save(self):
        return self.t, self.fmu.getFMUstate()

    def restore(self, saved):
        self.t, state = saved
        self.fmu.setFMUstate(state)

    def discard(self, saved):
        self.fmu.freeFMUstate(saved[1])

    def close(self):
        """Terminate and free the instance; after fmi2Fatal only the files are removed (the
        standard forbids further calls, and pythonfmu 0.7 has already released its objects:
        freeing the instance again would free them twice)."""
        if self._closed:
            return
        self._closed = True
        if not self.fatal:
            try:
                self.fmu.terminate()
            except FMICallException:
                pass
            self.fmu.freeInstance()
        shutil.rmtree(self._dir, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class CoreStepper:
    """The physics core (pidamper_physics.Damper) behind the same protocol; start values
    default as in the FMU."""

    def __init__(self, start_values=None, forcing=None, start_time=0.0):
        values = dict(start_values or {})
        initial = [float(values.pop(k, default)) for k, default in INITIAL_DEFAULTS.items()]
        known = [k for k in values if k in Params.NAMES or re.fullmatch(r"(floor\[\d+\]\.m|storey\[\d+\]\.k)", k)]
        params = {k: values.pop(k) for k in known}
        if values:
            raise KeyError(f"unknown parameters {sorted(values)!r}")
        self.core = Damper(Params.from_variables(params), *initial, t0=start_time)
        self.core.bound_work()  # as the FMU: a step's work is capped
        self.forcing = forcing

    @property
    def t(self):
        return self.core.t

    def _input(self, target):
        """The input `target` (F or a_g) held over the last step: the forcing's value at its start."""
        if self.forcing is None or self.forcing.target != target:
            return 0.0
        return float(self.forcing.value(self._held_from))

    _held_from = 0.0

    def advance(self, t_end):
        self._held_from = self.core.t
        value = 0.0 if self.forcing is None else float(self.forcing.value(self.core.t))
        if self.forcing is not None and self.forcing.target == "a_g":
            self.core.advance(t_end, 0.0, value)
        else:
            self.core.advance(t_end, value)

    def read(self):
        return self.core.angles()[:2]

    def get(self, name):
        c = self.core
        found = re.fullmatch(r"(floor|storey)\[(\d+)\]\.(x|a|drift)", name)
        if found or name == "base_shear":
            ground = self._input("a_g")
            xs, acc, drifts, shear = c.building_outputs(self._input("F"), ground)
            if not found:
                return shear
            return {"x": xs, "a": acc, "drift": drifts}[found.group(3)][int(found.group(2)) - 1]
        return {"impacts": c.impacts, "energy": c.energy, "energy_dissipated": c.dissipated,
                "energy_viscous": c.viscous, "work_in": c.work_in, "theta": c.angles()[0]}[name]

    def save(self):
        return self.core.get_state()

    def restore(self, saved):
        self.core.set_state(saved)

    def discard(self, saved):
        pass

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
