"""Errors and measures computed the same way for every method's trajectory."""
import math

import numpy as np
from scipy.optimize import brentq


def extrema(traj, t_end, period, per_period=64):
    """Extrema (t, x, kind) of a piecewise dense trajectory, in time order: inside each smooth
    piece the sign changes of v on a fine grid, refined by brentq on v; between pieces (an
    impact or a release) a sign change of v across the boundary, which makes x extremal there."""
    out = []
    previous = None  # (t, x, v) at the end of the previous piece
    for t0, t1, fn in traj.pieces:
        t1 = min(t1, t_end)
        if t1 <= t0:
            continue
        n = max(2, int(math.ceil((t1 - t0) / period * per_period)))
        t = np.linspace(t0, t1, n + 1)
        x, v = np.asarray(fn(t))[:2]
        if previous is not None and previous[2] * v[0] < 0:
            kind = 1 if previous[2] > 0 else -1
            out.append((t0, max(previous[1], x[0]) if kind > 0 else min(previous[1], x[0]), kind))
        for k in np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)[0]:
            kind = 1 if v[k] > 0 else -1
            tz = brentq(lambda s: float(np.asarray(fn(np.array([s])))[1][0]), t[k], t[k + 1], xtol=1e-15,
                        rtol=8.9e-16)
            out.append((tz, float(np.asarray(fn(np.array([tz])))[0][0]), kind))
        previous = (t1, x[-1], v[-1])
    return out


def cycle_peaks(ext, n_cycles=6):
    """One positive peak per cycle (cycles close at troughs), as pidamper.measures does."""
    peaks, current = [], None
    for t, x, kind in ext:
        if kind > 0 and x > 0:
            if current is None or x > current:
                current = x
        elif kind < 0 and x < 0 and current is not None:
            peaks.append(current)
            current = None
            if len(peaks) == n_cycles:
                break
    return peaks


def damping_printed(peaks):
    if len(peaks) < 6 or min(peaks) <= 0:
        return math.nan
    return sum(math.log(peaks[m] / peaks[m + 1]) for m in range(5)) / 5 / (2 * math.pi)


def max_abs(ext, traj, t_end):
    best = abs(traj.sample(np.array([t_end]))[0][0])
    for _, x, _ in ext:
        best = max(best, abs(x))
    return best


def window_peaks(ext, period, t_end):
    """Largest |x| in each primary period (the statistic for ill-conditioned cases)."""
    n = int(math.ceil(t_end / period))
    out = np.zeros(n)
    for t, x, _ in ext:
        k = min(int(t // period), n - 1)
        out[k] = max(out[k], abs(x))
    return out
