"""The demands of one assessment run, as FEMA P-58 asks for them and pelicun names them.

A run is one record, scaled, through the building FMU (fmpy), followed by a free-vibration tail of
TAIL_PERIODS first periods with the ground at rest, so that the building settles and its residual
drift can be read.  From the FMU's exact running maxima (located inside its steps, not sampled):

    PID-k   peak inter-storey drift ratio of storey k                      [1]
    PFA-k   peak absolute acceleration of floor k; PFA-0 the ground's      [m/s2]
    PFV-k   peak absolute velocity of floor k (k >= 1)                      [m/s]
and from the tail:
    RID-k   residual drift ratio of storey k: the mean drift over the tail's last first period
            divided by the storey height (the oscillation left is below exp(-2 pi zeta TAIL_PERIODS)
            of its start; nan for a run that collapsed)                     [1]
and of the damper: stroke (largest |z| at the communication points) [m], impacts, v_impact_max
(largest |relative velocity before| of the impacts recorded: the FMU records 16 per step; those
beyond are counted in impacts_unrecorded), impact_force_max (the largest peak contact force of the
run's impacts [N], from the contact law of the stops' materials; nan without materials, R = 0).

Impacts on the damper's floor: the FMU applies each impact as an instantaneous impulse, so its
floor acceleration (a_abs_max) holds the motion between impacts only.  Over a contact the stop
pushes that floor with the contact force F(t), adding F(t) / M to its acceleration (M the floor's
mass).  With materials given, the damper floor's PFA is counted as its a_abs_max plus
impact_force_max / M (impact_accel): a bound, as if the largest contact force met the largest
acceleration between impacts, in the same direction.

A run that collapses stops there (pidamper.running.simulation.run): its demands are those at the
collapse and `collapsed` is 1.  pelicun_columns() turns the names into pelicun's
`event-TYPE-location-direction` (one direction: 1)."""
import math

import numpy as np

#: free-vibration tail after each record, in first periods of the bare building
TAIL_PERIODS = 10
#: the demand types per storey (PID, RID: storeys 1..N) and per floor (PFA: 0..N, PFV: 1..N), units
TYPES = {"PID": "unitless", "RID": "unitless", "PFA": "mps2", "PFV": "mps"}
DAMPER = ("stroke", "impacts", "v_impact_max", "impacts_unrecorded", "impact_force_max", "impact_accel")
SLOTS = 16  # impact records per step (pidamper_fmu.particle_tables.IMPACT_SLOTS)


def names(storeys):
    """The per-storey and per-floor demand columns of an N-storey building, in a fixed order."""
    return ([f"PID-{k}" for k in range(1, storeys + 1)] + [f"RID-{k}" for k in range(1, storeys + 1)]
            + [f"PFA-{k}" for k in range(0, storeys + 1)] + [f"PFV-{k}" for k in range(1, storeys + 1)])


def with_tail(accel, dt, period):
    """The record followed by zeros for TAIL_PERIODS first periods; (times, accel)."""
    tail = int(math.ceil(TAIL_PERIODS * period / dt))
    accel = np.concatenate([np.asarray(accel, dtype=float), np.zeros(tail)])
    return dt * np.arange(accel.size), accel


def run_demands(values, accel, dt, period, step=None, fmu=None, record="record"):
    """Run one scaled record (ground acceleration samples [m/s2] at interval dt [s]) and its tail
    through the building FMU; the demands (module doc) as a dict, with `collapsed` (0/1) and
    `t_end` (the time the run ended [s]).

    The FMU is stepped as pidamper.run has fmpy.simulate_fmu step it (communication points k h, the
    input the record interpolated there (its sample when h = dt) held over the step, the run ended after the step whose `collapsed`
    output turned 1), but only the few outputs the demands need are read at each step: the same
    demands as demands_of(run(...).data) to the last bit (tests/test_demands.py), at a fraction of the
    host's cost.  A refused FMI call raises simulation.FmuError with what the model logged."""
    times, ground = with_tail(accel, dt, period)
    h = step or dt
    n = int(round(times[-1] / h))
    inputs = np.interp(h * np.arange(n + 1), times, ground).tolist()  # as pidamper.run samples a table
    return stepped_building(values, inputs, fmu, lambda instance: _stepped(
        instance, inputs, h, values["storeys"], period, float(np.abs(accel).max()), values))


def stepped_building(values, inputs, fmu, stepping):
    """stepping(instance) on an initialised FmuInstance of the building FMU of start values `values`
    (its input a_g set to inputs[0]), for hosts that read only what they need at each step; a
    refused FMI call raises simulation.FmuError with what the model logged."""
    from fmpy.fmi1 import FMICallException

    from ..running.fmu import find_fmu
    from ..running.instance import FmuInstance
    from ..running.simulation import FmuError, FmuMessages
    from ..running.unpacked import unpacked
    from ..running.variants import for_model, storeys_of

    path = str(find_fmu(fmu, storeys=storeys_of(values)))
    model_values = for_model(unpacked(path)[1].modelName, dict(values))
    messages = FmuMessages()
    logger = lambda status, text: messages(None, None, status, None, text)  # noqa: E731
    try:
        with FmuInstance(path, {**model_values, "a_g": inputs[0]}, logger=logger) as instance:
            return stepping(instance)
    except FMICallException as err:
        raise FmuError(f"{messages.text() or '(the model logged nothing)'} [{err}]", None) from err


def _stepped(fmu, inputs, h, storeys, period, pga, values):
    """Step `fmu` (an initialised FmuInstance) through `inputs` (a_g at the communication points);
    the demands (see run_demands)."""
    slave = fmu.fmu
    set_real, do_step, get_real, get_integer = slave.setReal, slave.doStep, slave.getReal, slave.getInteger
    ag, z_vr = fmu.vr("a_g"), fmu.vr("z")
    watch = fmu.vr("collapsed", "impacts_in_step")
    slots = fmu.vr(*(f"impact[{k}].v_rel_before" for k in range(1, SLOTS + 1)))
    floor, contact = damper_floor(values)
    force_vr = fmu.vr("impact_force_peak") if contact else None
    force = 0.0
    drifts = fmu.vr(*(f"storey[{k}].drift" for k in range(1, storeys + 1)))
    n = len(inputs) - 1
    last = n * h
    tail_from = last - period - 0.5 * h  # the rows of the tail's last period (as demands_of takes them)
    collapsed, stroke, speed = False, abs(fmu.get("z")), 0.0
    tail = [get_real(drifts)] if 0.0 >= tail_from else []
    t = 0.0
    for k in range(n):
        nxt = (k + 1) * h
        set_real(ag, [inputs[k]])
        do_step(currentCommunicationPoint=t, communicationStepSize=nxt - t)
        t = nxt
        flag, in_step = get_integer(watch)
        stroke = max(stroke, abs(get_real(z_vr)[0]))
        if in_step:
            speed = max([speed] + [abs(v) for v in get_real(slots[:min(in_step, SLOTS)])])
            if contact:
                force = max(force, get_real(force_vr)[0])
        if t >= tail_from:
            tail.append(get_real(drifts))
        if flag:
            collapsed = True
            break
    names = ([f"storey[{k}].{q}" for q in ("drift_ratio_max", "drift", "drift_ratio") for k in range(1, storeys + 1)]
             + [f"floor[{k}].{q}" for q in ("a_abs_max", "v_abs_max") for k in range(1, storeys + 1)])
    end = dict(zip(names, get_real(fmu.vr(*names))))
    impacts, unrecorded = get_integer(fmu.vr("impacts", "impacts_unrecorded"))
    out = {"collapsed": int(collapsed), "t_end": t}
    columns = list(zip(*tail)) if tail else [[] for _ in range(storeys)]
    for k in range(1, storeys + 1):
        out[f"PID-{k}"] = end[f"storey[{k}].drift_ratio_max"]
        height = values.get(f"storey[{k}].h") or (end[f"storey[{k}].drift"] / end[f"storey[{k}].drift_ratio"]
                                                   if end[f"storey[{k}].drift_ratio"] else math.nan)
        out[f"RID-{k}"] = math.nan if collapsed else abs(float(np.mean(np.array(columns[k - 1])))) / height
    out["PFA-0"] = pga
    for k in range(1, storeys + 1):
        out[f"PFA-{k}"] = end[f"floor[{k}].a_abs_max"]
    for k in range(1, storeys + 1):
        out[f"PFV-{k}"] = end[f"floor[{k}].v_abs_max"]
    out.update(stroke=float(stroke), impacts=int(impacts), v_impact_max=float(speed),
               impacts_unrecorded=int(unrecorded))
    return _with_impact_force(out, floor, force if contact else math.nan)


def damper_floor(values):
    """(floor: the damper's floor (1..N) and its mass [kg], contact: whether the stops' materials
    give contact forces) of FMU start values."""
    from pidamper_physics import Params

    params = Params.from_variables(values)
    return (params.floor + 1, params.M), params.materials is not None and params.mu > 0.0


def _with_impact_force(out, floor, force):
    """The demands with impact_force_max [N] and impact_accel = it over the damper floor's mass
    [m/s2] (nan without materials), the damper floor's PFA raised by impact_accel (module doc)."""
    k, mass = floor
    accel = force / mass
    out.update(impact_force_max=float(force), impact_accel=float(accel))
    if accel > 0.0:
        out[f"PFA-{k}"] += accel
    return out


def demands_of(data, storeys, heights, pga, period, h, collapsed, floor=(0, 1.0)):
    """The demands of a finished run's table (a RunResult's data; see run_demands); floor: the
    damper's floor and its mass (damper_floor), whose PFA takes the table's impact_force_peak."""
    last = {name: float(data[name][-1]) for name in data.dtype.names}
    out = {"collapsed": int(collapsed), "t_end": last["time"]}
    tail = data["time"] >= data["time"][-1] - period - 0.5 * h
    for k in range(1, storeys + 1):
        out[f"PID-{k}"] = last[f"storey[{k}].drift_ratio_max"]
        height = heights[k - 1] or (last[f"storey[{k}].drift"] / last[f"storey[{k}].drift_ratio"]
                                    if last[f"storey[{k}].drift_ratio"] else math.nan)
        out[f"RID-{k}"] = math.nan if collapsed else abs(float(np.mean(data[f"storey[{k}].drift"][tail]))) / height
    out["PFA-0"] = pga
    for k in range(1, storeys + 1):
        out[f"PFA-{k}"] = last[f"floor[{k}].a_abs_max"]
    for k in range(1, storeys + 1):
        out[f"PFV-{k}"] = last[f"floor[{k}].v_abs_max"]
    out.update(stroke=float(np.abs(data["z"]).max()), impacts=int(last["impacts"]), **_impact_speed(data))
    force = float(data["impact_force_peak"].max()) if "impact_force_peak" in data.dtype.names else math.nan
    return _with_impact_force(out, floor, force)


def _impact_speed(data):
    """The largest |v_rel_before| of the impacts the run recorded (nan when the table has no impact
    records: run_demands asks for them) and the impacts past the FMU's records."""
    if "impacts_in_step" not in data.dtype.names:
        return {"v_impact_max": math.nan, "impacts_unrecorded": math.nan}
    counts = np.minimum(data["impacts_in_step"], SLOTS)
    speeds = np.stack([np.abs(data[f"impact[{k}].v_rel_before"]) * (counts >= k) for k in range(1, SLOTS + 1)])
    return {"v_impact_max": float(speeds.max()), "impacts_unrecorded": int(data["impacts_unrecorded"][-1])}


def largest(found, storeys):
    """The run's largest storey drift ratio, its storey (1..N) and the largest floor acceleration."""
    ratio = np.array([found[f"PID-{k}"] for k in range(1, storeys + 1)])
    return {"drift_ratio": float(ratio.max()), "drift_storey": int(ratio.argmax()) + 1,
            "floor_accel": float(max(found[f"PFA-{k}"] for k in range(1, storeys + 1)))}


def pelicun_columns(row, storeys, event=1, direction=1):
    """One run's demands as pelicun's demand sample columns {event-TYPE-location-direction: value}."""
    return {f"{event}-{name}-{direction}": row[name] for name in names(storeys)}
