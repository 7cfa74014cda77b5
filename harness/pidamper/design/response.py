"""What one design run gives: the building FMU (fmpy) stepped through one ground motion, its samples
held over each communication step of the motion's own interval, reading only what the design's
metrics need at each step.

    peak_drift       max over storeys of storey[k].drift_ratio_max (exact running maxima)       [1]
    peak_accel       max over floors of floor[k].a_abs_max (exact; the damper floor's raised by
                     the largest contact force over its mass, as assessment.demands counts it)  [m/s2]
    rms_drift        max over storeys of the RMS of storey[k].drift_ratio at the communication
                     points                                                                       [1]
    rms_accel        max over floors of the RMS of floor[k].a (absolute)                          [m/s2]
    peak_base_shear  max |base_shear| at the communication points                                 [N]
    rms_base_shear   the RMS of base_shear at the communication points                            [N]
    roof_disp        max |floor[N].x| (the top floor, relative to the ground) at the
                     communication points                                                         [m]
    damper_force     the largest force of the damper on its floor: m g alpha + c_p L1 alpha' -
                     contact_force at the communication points (the wire, the dashpot c_p =
                     2 zeta_p m w1 and a stop it rides), or at an impact its peak contact force
                     plus the wire's m w1^2 d at the stop (0 without a damper)                    [N]
    ductility        max over storeys of the peak drift over the yield drift storey[k].Fy /
                     storey[k].k (exact running maxima; nan when the storeys do not yield)         [1]
    rms_ductility    max over storeys of the RMS drift over the yield drift (nan likewise)         [1]
    yielded          the storeys whose peak drift passed their yield drift (nan likewise)
    energy_hysteretic  the energy the storeys' yielding dissipated over the run                    [J]
    stroke           max |z| = |x - y| of the particle at the communication points                [m]
    impact_force     the largest peak contact force of the impacts (0 without materials)          [N]
    contact_pressure the largest peak contact pressure (0 without materials)                      [Pa]
    impacts, impacts_plastic, collapsed (0/1; a run that collapses stops there)
"""
import math

from pidamper_physics import Params
from pidamper_physics.params import STOREY_HEIGHT, STOREY_STIFFNESS

from ..assessment.demands import damper_floor, stepped_building

METRICS = ("peak_drift", "peak_accel", "rms_drift", "rms_accel", "peak_base_shear", "rms_base_shear", "roof_disp",
           "damper_force", "ductility", "rms_ductility", "yielded", "energy_hysteretic")
DAMPER = ("stroke", "impact_force", "contact_pressure", "impacts", "impacts_plastic", "collapsed")
COLUMNS = METRICS + DAMPER


def run(values, accel, dt, fmu=None):
    """The module doc's quantities of one run (a dict): `values` the building FMU's start values,
    `accel` the ground acceleration samples [m/s2] at interval dt [s] (the last sample ends the run)."""
    inputs = list(accel)
    return stepped_building(values, inputs, fmu, lambda instance: _stepped(instance, inputs, dt, values))


def _yield_drifts(values):
    """Each storey's yield drift storey[k].Fy / storey[k].k [m], or None when a storey does not yield."""
    n = values["storeys"]
    fy = [values.get(f"storey[{k}].Fy", 0.0) for k in range(1, n + 1)]
    if not all(f > 0 for f in fy):
        return None
    return [f / values.get(f"storey[{k}].k", STOREY_STIFFNESS) for k, f in enumerate(fy, 1)]


def _stepped(fmu, inputs, h, values):
    slave = fmu.fmu
    set_real, do_step, get_real, get_integer = slave.setReal, slave.doStep, slave.getReal, slave.getInteger
    n = values["storeys"]
    ag = fmu.vr("a_g")
    reals = fmu.vr(*[f"storey[{k}].drift_ratio" for k in range(1, n + 1)], *[f"floor[{k}].a" for k in range(1, n + 1)],
                   "base_shear", "z", "impact_force_peak", "contact_pressure_peak", f"floor[{n}].x", "alpha",
                   "alpha_dot", "contact_force")
    wire, dashpot, stop = _damper_constants(values)
    flag = fmu.vr("collapsed")
    squares = [0.0] * (2 * n + 1)
    shear = stroke = force = pressure = roof = pull = 0.0
    collapsed = False
    t, steps = 0.0, len(inputs) - 1
    for k in range(steps):
        nxt = (k + 1) * h
        set_real(ag, [inputs[k]])
        do_step(currentCommunicationPoint=t, communicationStepSize=nxt - t)
        t = nxt
        got = get_real(reals)
        for i in range(2 * n + 1):
            squares[i] += got[i] * got[i]
        shear, stroke = max(shear, abs(got[2 * n])), max(stroke, abs(got[2 * n + 1]))
        force, pressure = max(force, got[2 * n + 2]), max(pressure, got[2 * n + 3])
        roof = max(roof, abs(got[2 * n + 4]))
        pull = max(pull, abs(wire * got[2 * n + 5] + dashpot * got[2 * n + 6] - got[2 * n + 7]))
        if get_integer(flag)[0]:
            collapsed = True
            break
    done = k + 1 if steps else 1
    peaks = get_real(fmu.vr(*[f"storey[{k}].drift_ratio_max" for k in range(1, n + 1)],
                            *[f"floor[{k}].a_abs_max" for k in range(1, n + 1)], "energy_hysteretic"))
    (floor, mass), contact = damper_floor(values)
    accel = list(peaks[n:2 * n])
    if contact:
        accel[floor - 1] += force / mass
    impacts, plastic = get_integer(fmu.vr("impacts", "impacts_plastic"))
    rms = [math.sqrt(s / done) for s in squares]
    return {"peak_drift": max(peaks[:n]), "peak_accel": max(accel), "rms_drift": max(rms[:n]),
            "rms_accel": max(rms[n:2 * n]), "peak_base_shear": shear, "rms_base_shear": rms[2 * n], "roof_disp": roof,
            "damper_force": max(pull, force + stop if force > 0 else 0.0),
            **_yielding(values, peaks[:n], rms[:n]), "energy_hysteretic": peaks[2 * n],
            "stroke": stroke, "impact_force": force, "contact_pressure": pressure,
            "impacts": int(impacts), "impacts_plastic": int(plastic), "collapsed": int(collapsed)}


def _damper_constants(values):
    """(m g, c_p L1, m w1^2 d) of the damper on the building of start values `values` [N, N s, N]:
    its force on the floor is m g alpha + c_p L1 alpha' - contact_force (alpha = (y - x_j) / L1)."""
    p = Params.from_variables(values)
    if p.m <= 0.0:
        return 0.0, 0.0, 0.0
    damping = 2.0 * p.zeta_p * p.m * p.w1 if p.fidelity >= 1 else 0.0
    return p.m * p.g, damping * p.L1, p.m * p.w1 * p.w1 * p.d


def _yielding(values, peak, rms):
    """ductility, rms_ductility and yielded from the storeys' peak and RMS drift ratios."""
    yields = _yield_drifts(values)
    if yields is None:
        return {"ductility": math.nan, "rms_ductility": math.nan, "yielded": math.nan}
    heights = [values.get(f"storey[{k}].h", STOREY_HEIGHT) for k in range(1, len(yields) + 1)]
    peak = [p * h / y for p, h, y in zip(peak, heights, yields)]
    return {"ductility": max(peak), "rms_ductility": max(r * h / y for r, h, y in zip(rms, heights, yields)),
            "yielded": sum(1 for p in peak if p > 1.0)}
