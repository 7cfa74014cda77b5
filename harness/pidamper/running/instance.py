"""One FMU instance through fmpy's FMU2Slave: instantiated from the FMU unpacked once per process
(unpacked.py), initialised with start values, set and read by variable name, stepped, and freed as
the FMI standard allows (after fmi2Fatal nothing more is called).  Every harness driver of an FMU
builds on it (stepper.FmuStepper, the co-simulation masters, the benchmarks and the refusal checks)."""
from ctypes import byref

from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (FMU2Slave, calloc, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, fmi2Fatal, free)
from fmpy.logging import addLoggerProxy

from .unpacked import unpacked
from .variants import for_model


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


class FmuInstance:
    """An initialised instance of the FMU at `fmu_path` (start values set in initialization mode);
    `fmu` is fmpy's FMU2Slave, `vars` the model variables by name, `t` [s] the time after the last
    do_step.  logger(status, text) hears the model's messages (debug logging on), else they are
    dropped.  Start values are fitted to the model (variants.for_model).  A refused call raises
    fmpy's FMICallException; a failed initialization frees the instance before it raises."""

    def __init__(self, fmu_path, start_values=None, start_time=0.0, instance_name="pidamper", logger=None):
        self.dir, md = unpacked(fmu_path)
        self.vars = {v.name: v for v in md.modelVariables}
        if "storeys" not in self.vars:  # (a build before the split into one FMU per model takes them as given)
            start_values = for_model(md.modelName, start_values or {})
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=self.dir,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance_name)
        self.t = float(start_time)
        self.fatal = False  # after fmi2Fatal the FMI standard forbids any further call
        self._closed = False
        if logger is None:
            self.fmu.instantiate()
        else:
            self._callbacks = fmi2_callbacks(logger)  # kept alive as long as the instance
            self.fmu.instantiate(callbacks=self._callbacks, loggingOn=True)
        try:
            self._call(self.fmu.setupExperiment, startTime=self.t)
            self._call(self.fmu.enterInitializationMode)
            for name, value in (start_values or {}).items():
                self.set(name, value)
            self._call(self.fmu.exitInitializationMode)
        except Exception:
            self.close()
            raise

    def vr(self, *names):
        """Value references of the named variables."""
        return [self.vars[n].valueReference for n in names]

    def set(self, name, value):
        var = self.vars.get(name)
        if var is None:
            raise KeyError(f"{name!r} is not a variable of the FMU")
        if var.type == "Integer":
            self._call(self.fmu.setInteger, [var.valueReference], [int(value)])
        else:
            self._call(self.fmu.setReal, [var.valueReference], [float(value)])

    def get(self, name):
        var = self.vars[name]
        if var.type == "Integer":
            return self.fmu.getInteger([var.valueReference])[0]
        return self.fmu.getReal([var.valueReference])[0]

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

    def close(self):
        """Terminate and free the instance; after fmi2Fatal nothing is called (the standard forbids
        further calls, and pythonfmu 0.7 has already released its objects: freeing the instance
        again would free them twice).  The unpacked files stay for the process's next instance."""
        if self._closed:
            return
        self._closed = True
        if not self.fatal:
            try:
                self.fmu.terminate()
            except FMICallException:
                pass
            self.fmu.freeInstance()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
