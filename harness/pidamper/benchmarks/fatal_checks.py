"""Checks that make the FMU refuse a call on purpose (fmi2Error through the native layer, fmi2Fatal
without it); run them through pidamper.running.isolated (a child process each)."""
import numpy as np
from fmpy.fmi1 import FMICallException

from ..forcing import Forcing
from ..running.simulation import FmuError, run
from ..running.stepper import FmuStepper

FREE = {"theta_dot_0": 2.1924643668712155}


def bad_parameter(fmu, name, value):
    """Run with one invalid parameter: the error text, or None if it was accepted."""
    return bad_values(fmu, {name: value})


def bad_values(fmu, values):
    """Run with the start values `values`: the error text, or None if they were accepted."""
    try:
        run(values, stop_time=0.1, output_interval=0.01, fmu=fmu)
    except FmuError as err:
        return str(err)
    return None


def bad_input(fmu, value, t_bad=1.0):
    """A force that becomes `value` at t_bad: (error text, rows kept, last kept time)."""
    sig = Forcing("csv", {}, table=(np.array([0.0, t_bad - 1e-3, t_bad, t_bad + 9.0]),
                                    np.array([0.0, 0.0, value, value])))
    try:
        run({}, sig, stop_time=t_bad + 1.0, output_interval=0.05, fmu=fmu)
    except FmuError as err:
        data = err.partial.data if err.partial is not None else None
        return {"error": str(err), "rows": 0 if data is None else len(data),
                "last_time": None if data is None else float(data["time"][-1]),
                "finite": None if data is None else bool(np.isfinite(data["theta"]).all())}
    return {"error": None}


def host_misuse(fmu, action):
    """'back' (a step back in time), 'mismatch' (a step from the wrong time) or 'fixed' (a fixed
    parameter set after initialization): True when the FMU refused it with an FMI error."""
    with FmuStepper(fmu, FREE) as s:
        s.advance(1.0)
        try:
            if action == "back":
                s.do_step(1.0, -0.1)
            elif action == "mismatch":
                s.do_step(0.5, 0.1)
            elif action == "fixed":
                s.set("M", 2.0)
            elif action == "tunable-range":
                s.set("e", 1.5)
        except FMICallException:
            return True
    return False


def logged_failure(fmu, out_dir):
    """A logged run whose input turns infinite at t = 1 s: the error text (the logs stay in out_dir)."""
    from ..runlog.logged_run import run_logged

    sig = Forcing("csv", {"file": "x"}, table=(np.array([0.0, 0.999, 1.0, 9.0]), np.array([0.0, 0.0, np.inf, np.inf])))
    try:
        run_logged({}, sig, stop_time=3.0, output_interval=0.05, out_dir=out_dir, fmu=fmu)
    except FmuError as err:
        return str(err)
    return None


def percent_in_instance_name(fmu, instance="damper%s%n%d"):
    """A refused parameter in an instance whose name holds printf conversions: the host's
    logger takes the model's text as a format, so the FMU must escape them (a bare %n or %s
    crashes fmpy).  Returns the logged text of the error, or None if nothing was refused."""
    from ..running.instance import FmuInstance

    texts = []
    try:
        FmuInstance(fmu, {"mu": -1.0}, instance_name=instance, logger=lambda status, text: texts.append(text)).close()
    except Exception:  # noqa: BLE001 - the refusal is the point
        return " | ".join(texts)
    return None
