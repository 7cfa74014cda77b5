"""One fmpy run of the damper FMU against a forcing signal.

This is the public API a user scripting fmpy would use:

    from pidamper import find_fmu, forcing, run
    result = run({"mu": 0.02, "FR": 5.0}, forcing.harmonic(0.0981, 3.132), stop_time=40.0, output_interval=0.01)
    result.data["theta"]        # structured array, one row per communication point

`parameters` may hold `storeys`: N >= 1 runs DampedShearBuilding<N>.fmu (variants.py fits the
values to the model that runs them).
"""
import math
import re
import time
from dataclasses import dataclass, field

import fmpy
import numpy as np
from fmpy.fmi1 import FMICallException

from pidamper_physics import Params

from .fmu import find_fmu
from .unpacked import unpacked
from .variants import for_model, storeys_of
from ..forcing import Forcing, none

OUTPUTS = ("theta", "theta_dot", "alpha", "alpha_dot", "x", "y", "z", "a", "impacts", "contact",
           "contact_force", "energy", "energy_dissipated", "energy_viscous", "work_in")


@dataclass
class RunResult:
    data: np.ndarray  # structured: time, F and a_g (inputs held over the step that ends there), OUTPUTS
    fmu: str
    parameters: dict
    forcing: Forcing
    output_interval: float
    cpu_time: float  # s, process CPU time of the fmpy run
    meta: dict = field(default_factory=dict)

    def write_csv(self, path, outputs=None):
        """The table as CSV: time, the inputs and `outputs` (default: every column)."""
        names = self.data.dtype.names if outputs is None else ("time", "F", "a_g") + tuple(outputs)
        np.savetxt(path, np.column_stack([self.data[n].astype(float) for n in names]), delimiter=",",
                   header=",".join(names), comments="", fmt="%.17g")


class FmuError(RuntimeError):
    """An FMI call failed; the message includes what the model logged, and `partial`
    holds the rows recorded before the failure (a RunResult, or None)."""

    def __init__(self, message, partial=None):
        super().__init__(message)
        self.partial = partial


class FmuMessages:
    """fmpy logger callback that keeps the model's messages: problems (a warning when a run leaves
    its model's validity, the reason of a failure) and, at fmi2OK, which build of the physics
    runs, which text() leaves out."""

    OK, WARNING = 0, 1  # fmi2OK, fmi2Warning

    def __init__(self):
        self.messages = []  # (fmi2Status, text)

    def __call__(self, component, instance, status, category, message):
        text = message.decode(errors="replace") if isinstance(message, bytes) else str(message)
        self.messages.append((status, text.strip()))

    def text(self):
        """The messages; a pythonfmu fatal-error report is reduced to the model's own words."""
        return " | ".join(_model_words(m) for status, m in self.messages if status != self.OK)

    def warnings(self):
        return [text for status, text in self.messages if status == self.WARNING]


def _model_words(message):
    found = re.search(r"\w+Error\(['\"](.*)['\"]\)\s*$", message, flags=re.S)
    return found.group(1) if found else message


def resonance(parameters):
    """Primary natural frequency [rad/s] for the given FMU parameters (the model's defaults for
    those not given): w2 = sqrt(g / L2), or a building's first natural frequency w_1 (storeys >= 1)."""
    return Params.from_variables(parameters).w2


def floor_columns(storeys):
    """The FMU outputs a floor block is made of, in floors_dtype's order."""
    return tuple(f"{kind}[{k}].{field}" for kind, field in (("floor", "x"), ("floor", "a"), ("storey", "drift"))
                 for k in range(1, storeys + 1)) + ("base_shear",)


def peak_columns(storeys):
    """A building's drift ratios and running maxima (exact, located inside the FMU's steps)."""
    return tuple(f"{kind}[{k}].{field}" for kind, field in (
        ("storey", "drift_ratio"), ("storey", "drift_ratio_max"), ("floor", "v_abs_max"), ("floor", "a_abs_max"))
        for k in range(1, storeys + 1))


def yield_columns(storeys):
    """A building's yielding storeys: spring forces, zero-force drifts, hysteretic energy, collapse."""
    return tuple(f"storey[{k}].{field}" for field in ("force", "plastic_drift") for k in range(1, storeys + 1)) + (
        "energy_hysteretic", "collapsed")


#: what the materials add (a run with a contact radius R > 0 records them)
CONTACT_OUTPUTS = ("impact_force_peak", "contact_pressure_peak", "impacts_plastic")


def building_outputs(parameters):
    """The building's outputs a run records beside OUTPUTS (none with storeys = 0), and the
    materials' (CONTACT_OUTPUTS) when the parameters give a contact radius R > 0."""
    n = storeys_of(parameters)
    contact = CONTACT_OUTPUTS if float(parameters.get("R", 0.0)) > 0.0 else ()
    return (floor_columns(n) + peak_columns(n) + yield_columns(n) if n else ()) + contact


def run(parameters=None, forcing=None, stop_time=20.0, output_interval=0.01, fmu=None, start_time=0.0,
        step_finished=None, extra_outputs=(), on_warning=None, after_collapse=False):
    """Simulate the FMU with fmpy.simulate_fmu; parameters are FMU start values, extra_outputs
    further FMU variables to record beside OUTPUTS.  The model's warnings end up in
    result.meta["warnings"]; on_warning(t, text) also hears each one at the step it came in.  A
    building that collapses (its `collapsed` output turns 1) ends the run at that step, its time in
    result.meta["collapsed"], unless after_collapse is true (the FMU then holds every output)."""
    forcing = forcing or none()
    _check_interval(start_time, stop_time, output_interval)
    start_values = dict(parameters or {})
    start_values.update(forcing.start_values)
    extra_outputs = tuple(extra_outputs) + tuple(o for o in building_outputs(start_values) if o not in extra_outputs)
    path = str(find_fmu(fmu, storeys=storeys_of(start_values)))
    folder, md = unpacked(path)  # once per process and FMU file: a study's runs share it
    model_values = for_model(md.modelName, start_values)
    n = int(round((stop_time - start_time) / output_interval))
    grid = start_time + output_interval * np.arange(n + 1)
    signal = forcing.input_array(grid)
    messages = FmuMessages()
    seen = {}

    def tell(t):  # hand on_warning the warnings that came in since the last call
        if on_warning is not None and len(messages.messages) != seen.get("heard", 0):
            for status, text in messages.messages[seen.get("heard", 0):]:
                if status == FmuMessages.WARNING:
                    on_warning(t, text)
            seen["heard"] = len(messages.messages)

    def watch(t, recorder):  # keeps the recorder, so a failed run still returns its rows
        seen["recorder"] = recorder
        tell(t)
        go_on = step_finished(t, recorder) if step_finished is not None else True
        if "collapsed" in extra_outputs and recorder.rows:
            column = seen.setdefault("collapsed", [c[0] for c in recorder.cols].index("collapsed"))
            if recorder.rows[-1][column] and "collapse" not in seen:
                seen["collapse"] = float(recorder.rows[-1][0])
                go_on = go_on and after_collapse
        return go_on

    cpu = time.process_time()
    try:
        data = fmpy.simulate_fmu(folder, model_description=md, start_time=start_time, stop_time=stop_time, output_interval=output_interval,
                                 start_values=model_values, input=signal, output=list(OUTPUTS) + list(extra_outputs),
                                 step_finished=watch, debug_logging=True, logger=messages)
    except FMICallException as err:
        partial = None
        if "recorder" in seen:
            partial = RunResult(_with_force(seen["recorder"].result(), forcing), path, start_values, forcing,
                                output_interval, time.process_time() - cpu)
        raise FmuError(f"{messages.text() or '(the model logged nothing)'} [{err}]", partial) from err
    cpu = time.process_time() - cpu
    tell(float(data["time"][-1]))  # what the model said at fmi2Terminate
    data = _with_force(data, forcing)
    meta = {"warnings": messages.warnings()}
    if "collapse" in seen:
        meta["collapsed"] = seen["collapse"]
    return RunResult(data, path, start_values, forcing, output_interval, cpu, meta)


def _with_force(data, forcing):
    """Add columns F and a_g: the inputs held over the step ending at each row (first row: at t0)."""
    out = np.zeros(len(data), dtype=[("time", np.float64), ("F", np.float64), ("a_g", np.float64)] +
                   [(n, data.dtype[n]) for n in data.dtype.names if n != "time"])
    for name in data.dtype.names:
        out[name] = data[name]
    t = data["time"]
    out[forcing.target] = forcing.value(np.concatenate([t[:1], t[:-1]]))
    return out


def _check_interval(start_time, stop_time, output_interval):
    for name, value in (("start_time", start_time), ("stop_time", stop_time), ("output_interval", output_interval)):
        if not math.isfinite(value):
            raise ValueError(f"{name} = {value!r} is not allowed: it must be finite")
    if output_interval <= 0:
        raise ValueError(f"output_interval = {output_interval!r} is not allowed: it must be > 0 s")
    if stop_time <= start_time:
        raise ValueError(f"stop_time = {stop_time!r} is not allowed: it must exceed start_time = {start_time!r}")
