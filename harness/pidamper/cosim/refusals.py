"""Refusal checks of the component FMUs (run in a child process through pidamper.running.isolated)."""
from .components import component_instance


def refusal(fmu, values=None, inputs=None, steps=2, h=0.01):
    """Instantiate `fmu` with the start `values`, set `inputs` after initialization and take
    `steps` steps of h: the FMU's messages (str) if a call was refused, else None.  Run it through
    pidamper.running.isolated (a child process), as the other refusal checks."""
    from fmpy.fmi1 import FMICallException

    messages = []
    try:
        slave = component_instance(fmu, "checked", values or {}, messages)
    except FMICallException as err:
        return "\n".join(messages) + f"\nstatus {err.status}"
    try:
        for name, value in (inputs or {}).items():
            slave.fmu.setReal(slave.vr(name), [value])
        for k in range(steps):
            slave.fmu.doStep(k * h, h)
    except FMICallException as err:
        return "\n".join(messages) + f"\nstatus {err.status}"
    finally:
        slave.close()
    return None


def refusals(cases):
    """[refusal(fmu, values, inputs) for each case]: for pidamper.running.isolated (JSON in and out)."""
    return [refusal(fmu, values, inputs) for fmu, values, inputs in cases]
