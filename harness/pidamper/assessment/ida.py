"""Incremental dynamic analysis to collapse: the hunt-and-fill tracing of one record
(Vamvatsikos & Cornell 2002, section 5.2).

`hunt_and_fill(run, ...)` asks `run(im)` -> (collapsed, demand) at the intensities it chooses:

1. hunt: from `first`, steps that grow by `increment` each run (first, first + step, + 2 step +
   increment, ...) until a run collapses (the last non-collapsing intensity and the first
   collapsing one then bracket the capacity);
2. bracket: bisect the bracket until it is narrower than `tolerance` (relative to its lower end);
3. fill: with runs left, halve the widest gap between the non-collapsing intensities traced, so
   the IDA curve below collapse is drawn evenly.

At most `max_runs` runs.  The collapse capacity is the bracket's lower end (the largest intensity
that did not collapse) with the bracket's upper end; a record that never collapsed within the
runs has no capacity (reported as such, never invented).
"""
from dataclasses import dataclass, field


@dataclass
class Trace:
    """One record's IDA: runs as (im, collapsed, demand) in the order run; the collapse bracket
    (lo, hi) when a run collapsed, else (largest im run, None)."""

    runs: list = field(default_factory=list)
    lo: float = 0.0
    hi: float = None

    @property
    def collapsed(self):
        return self.hi is not None

    @property
    def capacity(self):
        """The collapse intensity: the bracket's midpoint, or None (no run collapsed)."""
        return None if self.hi is None else 0.5 * (self.lo + self.hi)

    def curve(self):
        """(im, demand) of the runs that did not collapse, by intensity: the IDA curve."""
        return sorted((im, d) for im, c, d in self.runs if not c)


def hunt_and_fill(run, first, step, increment=None, tolerance=0.05, max_runs=10):
    """Trace one record (see the module doc); run(im) -> (collapsed, demand)."""
    if not (first > 0 and step > 0 and 0 < tolerance < 1 and max_runs >= 2):
        raise ValueError(f"first = {first!r}, step = {step!r}, tolerance = {tolerance!r}, max_runs = {max_runs!r} "
                         "are not allowed: first and step > 0, tolerance in (0, 1), max_runs >= 2")
    increment = step / 2.0 if increment is None else increment
    trace = Trace()

    def go(im):
        collapsed, demand = run(im)
        trace.runs.append((im, bool(collapsed), demand))
        return collapsed

    im = first
    while len(trace.runs) < max_runs:  # hunt
        if go(im):
            trace.hi = im
            break
        trace.lo = im
        step_now = step + increment * (len(trace.runs) - 1)
        im = im + step_now
    if trace.hi is None:
        return trace
    while len(trace.runs) < max_runs and trace.hi - trace.lo > tolerance * max(trace.lo, 1e-300):  # bracket
        mid = 0.5 * (trace.lo + trace.hi)
        if go(mid):
            trace.hi = mid
        else:
            trace.lo = mid
    while len(trace.runs) < max_runs:  # fill the widest gap below collapse
        below = sorted([0.0] + [im for im, c, _ in trace.runs if not c])
        gaps = [(b - a, a, b) for a, b in zip(below, below[1:])]
        if not gaps:
            break
        width, a, b = max(gaps)
        if width <= tolerance * max(b, 1e-300):
            break
        im = 0.5 * (a + b)
        if go(im):  # a collapse below the bracket (a non-monotone record): the first collapse counts
            trace.hi = im
            trace.lo = max([x for x, c, _ in trace.runs if not c and x < im], default=0.0)
    return trace


#: the numbers of a run's demands that are not interpolated: they say how the run ended
NOT_INTERPOLATED = ("collapsed", "t_end")


def at_level(trace, level):
    """One record's demands at `level` from its IDA trace (runs (im, collapsed, demands dict)):
    (demands, collapsed, exact).

    At or above the collapse intensity (the bracket's midpoint) the demands of the record's lowest
    collapsing run; below it each number of the demands linearly interpolated in intensity between
    the two standing runs around the level, the curve starting at (0, 0) (every demand vanishes with
    the intensity); between the highest standing run below the capacity and the capacity (at most
    half the bracket, tolerance / 2 relative) that run's demands.  `exact`: a run was at the level.
    None for a record that never collapsed and was not traced up to the level."""
    capacity = trace.capacity
    if capacity is not None and level >= capacity:
        im, _, found = min((r for r in trace.runs if r[1]), key=lambda r: r[0])
        return dict(found), True, im == level
    standing = sorted((im, found) for im, c, found in trace.runs if not c and (capacity is None or im < capacity))
    if not standing or level > standing[-1][0]:
        if capacity is None or not standing:
            return None
        return dict(standing[-1][1]), False, False
    upper = next(k for k, (im, _) in enumerate(standing) if im >= level)
    im_b, b = standing[upper]
    if im_b == level:
        return dict(b), False, True
    im_a, a = standing[upper - 1] if upper else (0.0, None)
    w = (level - im_a) / (im_b - im_a)
    out = dict(b)
    for key, value in b.items():
        if key not in NOT_INTERPOLATED and isinstance(value, (int, float)) and not isinstance(value, bool):
            start = 0.0 if a is None else a[key]
            out[key] = float(start + w * (value - start))
    return out, False, False


def leave_one_out(traces, prefixes=("PID-", "PFA-", "RID-")):
    """How well at_level reads demands between runs, measured on the traces themselves: each
    standing run strictly inside a record's curve (below its capacity, neither its lowest nor its
    highest) is left out and read off the others; {prefix: (median, 90th percentile) of |read -
    run| / run} over the runs and every demand whose name starts with the prefix (positive ones).
    Leaving a run out doubles the gap around it, so this overstates the error at the stripes."""
    import numpy as np

    errors = {p: [] for p in prefixes}
    for trace in traces:
        cap = trace.capacity
        standing = sorted((r for r in trace.runs if not r[1] and (cap is None or r[0] < cap)), key=lambda r: r[0])
        for run in standing[1:-1]:
            others = Trace([r for r in trace.runs if r is not run], trace.lo, trace.hi)
            found = at_level(others, run[0])[0]
            for key, value in run[2].items():
                prefix = next((p for p in prefixes if key.startswith(p)), None)
                if prefix is not None and value > 0:
                    errors[prefix].append(abs(found[key] - value) / value)
    return {p: (float(np.median(e)), float(np.percentile(e, 90))) if e else (float("nan"),) * 2
            for p, e in errors.items()}
