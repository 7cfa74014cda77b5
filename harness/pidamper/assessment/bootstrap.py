"""Paired bootstrap over records (Efron & Tibshirani 1993, percentile method) for comparisons of
two configurations run on the same records: each resample draws the records once, with
replacement, and evaluates every quantity of both configurations on the same draw, so the
record-to-record variability common to both cancels in their ratio.

`paired(statistic, records)` calls statistic(rows) -> a sequence of numbers (rows: an index array
of the drawn records) and gives an Interval per number; a resample whose statistic cannot be
computed (it raises FragilityError or gives a non-finite number) is left out of that number's
interval and counted in its `unfitted`, never silently dropped."""
from dataclasses import dataclass

import numpy as np

from .fragility import FragilityError


@dataclass
class Interval:
    """A quantity on all records (point) and the central `level` percentile interval (lo, hi) of
    its resamples; resamples drawn and unfitted (left out)."""
    point: float
    lo: float
    hi: float
    resamples: int
    unfitted: int
    level: float = 0.90

    def text(self, digits=3):
        """'point (lo to hi)', or the point alone when no resample could be fitted."""
        if not np.isfinite(self.lo):
            return f"{self.point:.{digits}g}"
        return f"{self.point:.{digits}g} ({self.lo:.{digits}g} to {self.hi:.{digits}g})"


def _values(statistic, rows, size):
    try:
        out = np.asarray(statistic(rows), dtype=float).reshape(-1)
    except FragilityError:
        return np.full(size, np.nan)
    return out if out.size == size else np.full(size, np.nan)


def paired(statistic, records, n=1000, seed=0, level=0.90):
    """[Interval per number of statistic(rows)] over `n` resamples of `records` records
    (numpy default_rng(seed)); the point values from all records in order."""
    if int(records) < 2 or int(n) < 1 or not 0 < level < 1:
        raise ValueError(f"records = {records!r}, n = {n!r}, level = {level!r} are not allowed: records >= 2, "
                         "n >= 1, level in (0, 1)")
    point = np.asarray(statistic(np.arange(records)), dtype=float).reshape(-1)
    rng = np.random.default_rng(seed)
    draws = np.array([_values(statistic, rng.integers(0, records, records), point.size) for _ in range(int(n))])
    tail = 50.0 * (1.0 - level)
    out = []
    for j, value in enumerate(point):
        ok = draws[:, j][np.isfinite(draws[:, j])]
        lo, hi = np.percentile(ok, [tail, 100.0 - tail]) if ok.size else (np.nan, np.nan)
        out.append(Interval(float(value), float(lo), float(hi), int(n), int(n - ok.size), level))
    return out
