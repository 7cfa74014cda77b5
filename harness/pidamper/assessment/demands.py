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
beyond are counted in impacts_unrecorded).

A run that collapses stops there (pidamper.running.simulation.run): its demands are those at the
collapse and `collapsed` is 1.  pelicun_columns() turns the names into pelicun's
`event-TYPE-location-direction` (one direction: 1)."""
import math

import numpy as np

#: free-vibration tail after each record, in first periods of the bare building
TAIL_PERIODS = 10
#: the demand types per storey (PID, RID: storeys 1..N) and per floor (PFA: 0..N, PFV: 1..N), units
TYPES = {"PID": "unitless", "RID": "unitless", "PFA": "mps2", "PFV": "mps"}
DAMPER = ("stroke", "impacts", "v_impact_max", "impacts_unrecorded")
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
    `t_end` (the time the run ended [s])."""
    from ..forcing import Forcing
    from ..running.simulation import run

    storeys = values["storeys"]
    times, ground = with_tail(accel, dt, period)
    signal = Forcing("record", {"record": record}, table=(times, ground), target="a_g")
    h = step or dt
    stop = int(round(times[-1] / h)) * h
    slots = [f"impact[{k}].v_rel_before" for k in range(1, SLOTS + 1)] + ["impacts_in_step", "impacts_unrecorded"]
    result = run(values, signal, stop_time=stop, output_interval=h, fmu=fmu, extra_outputs=slots)
    return demands_of(result.data, storeys, [values.get(f"storey[{k}].h") for k in range(1, storeys + 1)],
                      float(np.abs(accel).max()), period, h, "collapsed" in result.meta)


def demands_of(data, storeys, heights, pga, period, h, collapsed):
    """The demands of a finished run's table (a RunResult's data; see run_demands)."""
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
    return out


def _impact_speed(data):
    """The largest |v_rel_before| of the impacts the run recorded (nan when the table has no impact
    records: run_demands asks for them) and the impacts past the FMU's records."""
    if "impacts_in_step" not in data.dtype.names:
        return {"v_impact_max": math.nan, "impacts_unrecorded": math.nan}
    counts = np.minimum(data["impacts_in_step"], SLOTS)
    speeds = np.stack([np.abs(data[f"impact[{k}].v_rel_before"]) * (counts >= k) for k in range(1, SLOTS + 1)])
    return {"v_impact_max": float(speeds.max()), "impacts_unrecorded": int(data["impacts_unrecorded"][-1])}


def pelicun_columns(row, storeys, event=1, direction=1):
    """One run's demands as pelicun's demand sample columns {event-TYPE-location-direction: value}."""
    return {f"{event}-{name}-{direction}": row[name] for name in names(storeys)}
