"""Performance measures from the continuous solution: peaks, damping ratio, amplitude ratio; a
building run's exact peaks (building_peaks).

Every extremum is located on the continuous motion, not on samples: the
stepper marches on a grid of step dt, and each interval in which theta_dot
changes sign is bisected (restoring the saved state and stepping to the
midpoint) down to a few ulps of time.  A sign change caused by an impact is
found the same way, at the impact instant, where theta is then extremal.

Damping ratio (paper, section 3): one positive peak A_m of theta per cycle
(cycles start at upward zero crossings of theta), logarithmic decrement
delta_m = ln(A_m / A_m+1) over the first five cycles, averaged as named in
DAMPING_AVERAGES.
"""
import math
from dataclasses import dataclass

TWO_PI = 2.0 * math.pi

DAMPING_AVERAGES = {
    "printed": "mean over m = 1..5 of ln(A_m / A_m+1) / (2 pi) (the paper's formula)",
    "exact": "mean over m = 1..5 of delta_m / sqrt(4 pi^2 + delta_m^2) (no small-damping approximation)",
    "accumulated": "mean over m = 1..5 of ln(A_1 / A_m+1) / (2 pi) (decrement accumulated from the first peak)",
}


@dataclass
class Extremum:
    t: float  # s
    theta: float  # rad
    kind: int  # +1 maximum, -1 minimum


def _refine(stepper, left, t_right, kind):
    """Extremum of theta in (left.t, t_right] where theta_dot changes sign; leaves the
    stepper at its pre-call state (time t_right)."""
    right = stepper.save()
    lo = left
    t_lo, t_hi = stepper_time(lo), t_right
    best_t, best = t_hi, stepper.read()[0]
    stepper.restore(lo)
    theta_lo = stepper.read()[0]
    if kind * theta_lo > kind * best:
        best_t, best = t_lo, theta_lo
    own = []
    for _ in range(200):
        mid = 0.5 * (t_lo + t_hi)
        if not t_lo < mid < t_hi:
            break
        stepper.restore(lo)
        stepper.advance(mid)
        theta, theta_dot = stepper.read()
        if kind * theta > kind * best:
            best_t, best = mid, theta
        if kind * theta_dot >= 0.0:
            new_lo = stepper.save()
            own.append(new_lo)
            lo, t_lo = new_lo, mid
        else:
            t_hi = mid
    for saved in own:
        stepper.discard(saved)
    stepper.restore(right)
    stepper.discard(right)
    return Extremum(best_t, best, kind)


def stepper_time(saved):
    """Time of a saved state (FMU states carry it as their first element)."""
    return saved[0] if isinstance(saved, tuple) else saved["t"]


def extrema(stepper, t_end, dt):
    """Yield every extremum of theta on (stepper.t, t_end], in time order."""
    theta_dot = stepper.read()[1]
    left = stepper.save()
    n = max(1, math.ceil((t_end - stepper.t) / dt - 1e-9))
    t0 = stepper.t
    for k in range(1, n + 1):
        t_next = t_end if k == n else t0 + k * (t_end - t0) / n
        stepper.advance(t_next)
        new_dot = stepper.read()[1]
        if theta_dot >= 0.0 > new_dot:
            yield _refine(stepper, left, t_next, +1)
        elif theta_dot <= 0.0 < new_dot:
            yield _refine(stepper, left, t_next, -1)
        stepper.discard(left)
        left = stepper.save()
        theta_dot = new_dot
    stepper.discard(left)


def cycle_peaks(stepper, n_cycles, period, dt=None, max_periods=200):
    """Positive peak of theta in each of the first n_cycles cycles (cycles start at
    upward zero crossings of theta; the first at t0 when theta(t0) = 0 and rising)."""
    dt = dt or period / 200.0
    peaks = []
    current = None  # best maximum of the running cycle
    started = False
    theta0, dot0 = stepper.read()
    if theta0 == 0.0 and dot0 > 0.0:
        started = True
    last_theta = theta0
    t_stop = stepper.t + max_periods * period
    while len(peaks) < n_cycles and stepper.t < t_stop:
        t_chunk = min(stepper.t + period, t_stop)
        for ext in extrema(stepper, t_chunk, dt):
            if ext.kind > 0 and ext.theta > 0.0 and started:
                if current is None or ext.theta > current.theta:
                    current = ext
            elif ext.kind < 0 and ext.theta < 0.0:
                # a trough closes the positive half of the running cycle
                if current is not None:
                    peaks.append(current)
                    current = None
                    if len(peaks) == n_cycles:
                        break
                started = True
        last_theta = stepper.read()[0]
    if len(peaks) < n_cycles:
        raise RuntimeError(f"only {len(peaks)} of {n_cycles} cycles with a positive peak within "
                           f"{max_periods} periods (last theta {last_theta!r})")
    return peaks


def damping_ratios(peaks):
    """Every averaging of DAMPING_AVERAGES from the peaks A_1..A_6 (the first six are used)."""
    amps = [p.theta for p in peaks[:6]]
    if len(amps) < 6 or min(amps) <= 0.0:
        raise ValueError(f"peaks {amps!r} are not allowed: six positive peaks are needed")
    deltas = [math.log(amps[m] / amps[m + 1]) for m in range(5)]
    return {
        "printed": sum(deltas) / 5.0 / TWO_PI,
        "exact": sum(dl / math.sqrt(TWO_PI ** 2 + dl * dl) for dl in deltas) / 5.0,
        "accumulated": sum(math.log(amps[0] / amps[m + 1]) for m in range(5)) / 5.0 / TWO_PI,
    }


def damping_ratio(stepper, period, dt=None):
    """(ratios by averaging, peaks) of free vibration from the stepper's current state."""
    peaks = cycle_peaks(stepper, 6, period, dt)
    return damping_ratios(peaks), peaks


def max_abs_theta(stepper, t_end, dt):
    """Largest |theta| of the continuous solution on [stepper.t, t_end] and its time."""
    theta, _ = stepper.read()
    best = Extremum(stepper.t, theta, 1 if theta >= 0 else -1)
    for ext in extrema(stepper, t_end, dt):
        if abs(ext.theta) > abs(best.theta):
            best = ext
    theta, _ = stepper.read()
    if abs(theta) > abs(best.theta):
        best = Extremum(stepper.t, theta, 1 if theta >= 0 else -1)
    return best


def amplitude_ratio(damped, undamped, t_end, dt):
    """max|theta| with the damper / max|theta| without (same forcing) over [t0, t_end]."""
    with_damper = max_abs_theta(damped, t_end, dt)
    without = max_abs_theta(undamped, t_end, dt)
    return abs(with_damper.theta) / abs(without.theta), with_damper, without


def building_peaks(data, storeys):
    """A building run's peaks from its table (a RunResult's data): the FMU's exact running maxima
    at the last row, as arrays per storey / floor (storey or floor 1 first): drift_ratio [1],
    v_abs [m/s], a_abs [m/s2].  Located inside the FMU's steps, not sampled (the communication
    points under-read them)."""
    import numpy as np

    def last(pattern):
        return np.array([float(data[pattern.format(k)][-1]) for k in range(1, storeys + 1)])

    return {"drift_ratio": last("storey[{}].drift_ratio_max"), "v_abs": last("floor[{}].v_abs_max"),
            "a_abs": last("floor[{}].a_abs_max")}
