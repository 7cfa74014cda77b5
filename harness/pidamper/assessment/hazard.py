"""A site's seismic hazard curve and the annual figures integrated over it (FEMA P-58-1, 2018,
chapter 8: the time-based assessment).

A `Curve` is the annual rate of exceedance lambda(x) [1/yr] of an intensity x (the study's measure
and unit) at points x_1 < ... < x_n, interpolated linearly in (ln x, ln lambda), so that on each
segment lambda = lambda_a (x / x_a)^-k exactly; it may carry fractile curves beside its mean.
Outside [x_1, x_n] it has no value unless it names a rule ("loglog": its end segments' power laws
continued); a power law k0 x^-k is its own rule.

`Integral` gives the annual figure of a quantity v known at stripes s_1 < ... < s_m (a mean loss, a
probability of exceedance):

    A = int_{s_lo}^{s_m} v(x) |d lambda(x)| + v(s_m) lambda(s_m)

(v held at the top stripe's value above it, zero below the lower limit s_lo, a stripe), with v
between stripes by the integration rule: "loglog" (a power law between two stripes where both
values are > 0, linear in ln x where one is 0), "semilog" (linear in ln x), or "intervals" (each
stripe stands for the interval between the geometric midpoints of its neighbours, the lowest from
s_1^2 / m_1: the rule of the assessments before the site curves).  Every piece is integrated in
closed form against the piecewise power law, so the only error is the interpolation of v.
"""
import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

RULES = ("loglog", "semilog", "intervals")
EXTRAPOLATE = ("none", "loglog")


class HazardError(ValueError):
    """A hazard curve that cannot be read or used: `field` names what is wrong (a column, a stripe...)."""

    def __init__(self, field, value, allowed):
        super().__init__(f"{field} = {value!r}: {allowed}")
        self.field, self.value, self.allowed = field, value, allowed


@dataclass(frozen=True)
class Curve:
    """A hazard curve: intensities x (ascending, > 0) and per curve name its rates [1/yr] (positive,
    non-increasing; the first name is the mean); where it comes from, the spectral period [s] of its
    measure (None: not a spectral acceleration or not stated) and the rule outside its range."""

    x: np.ndarray
    rates: dict
    source: str = ""
    period: float = None
    extrapolate: str = "none"
    site: str = ""
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        x = np.asarray(self.x, dtype=float)
        if x.ndim != 1 or x.size < 2 or not np.all(np.isfinite(x)) or np.any(x <= 0) or np.any(np.diff(x) <= 0):
            raise HazardError("intensities", x.tolist(), "two or more, positive and ascending")
        for name, rate in self.rates.items():
            rate = np.asarray(rate, dtype=float)
            if rate.shape != x.shape or not np.all(np.isfinite(rate)) or np.any(rate <= 0) \
                    or np.any(np.diff(rate) > 0):
                raise HazardError(f"rates of {name}", rate.tolist(), f"{x.size} positive rates, non-increasing "
                                  "with intensity (a hazard curve)")
        if self.extrapolate not in EXTRAPOLATE:
            raise HazardError("extrapolate", self.extrapolate, f"one of {', '.join(EXTRAPOLATE)}")

    @classmethod
    def power_law(cls, k0, k, source="power law"):
        """lambda(x) = k0 x^-k everywhere (its own extrapolation rule)."""
        return cls(np.array([1.0, math.e]), {"mean": np.array([k0, k0 * math.exp(-k)])}, source, None, "loglog")

    @property
    def names(self):
        return list(self.rates)

    @property
    def mean(self):
        return self.names[0]

    def covers(self, x):
        """Whether intensity x lies on the curve (its points, not a rule)."""
        return self.x[0] <= x <= self.x[-1]

    def intensity(self, rate, name=None):
        """The intensity whose rate of exceedance is `rate` [1/yr] on the curve (log-log between its
        points; nan off its range)."""
        lr = np.log(np.asarray(self.rates[name or self.mean], dtype=float))[::-1]
        return float(np.exp(np.interp(math.log(rate), lr, np.log(self.x)[::-1], left=np.nan, right=np.nan)))

    def rate(self, x, name=None):
        """lambda(x) [1/yr] of curve `name` (the mean by default); HazardError outside the curve
        without a rule."""
        x = np.asarray(x, dtype=float)
        if self.extrapolate == "none" and (np.any(x < self.x[0]) or np.any(x > self.x[-1])):
            outside = x[(x < self.x[0]) | (x > self.x[-1])]
            raise HazardError("intensity", float(outside.flat[0]), f"within the hazard curve's {self.x[0]:g} .. "
                              f"{self.x[-1]:g} (no extrapolation rule named)")
        lx, lr = np.log(self.x), np.log(np.asarray(self.rates[name or self.mean], dtype=float))
        s = np.log(x)
        i = np.clip(np.searchsorted(lx, s) - 1, 0, lx.size - 2)
        slope = (lr[i + 1] - lr[i]) / (lx[i + 1] - lx[i])
        return np.exp(lr[i] + slope * (s - lx[i]))


def at_period(short, long, period, rates=None):
    """The mean curve of Sa at `period` [s] between two curves of Sa at the periods short.period <
    period < long.period: at each rate of exceedance, ln Sa linear in ln T between the two curves'
    intensities at that rate (the usual interpolation of a uniform-hazard spectrum between the
    periods a model gives).  Rates: the given ones, else every rate of either curve that both reach."""
    ta, tb = short.period, long.period
    if ta is None or tb is None or not ta < period < tb:
        raise HazardError("period", period, f"between the two curves' periods ({ta}, {tb}) s")
    ra, rb = np.asarray(short.rates[short.mean]), np.asarray(long.rates[long.mean])
    if rates is None:
        lo, hi = max(ra.min(), rb.min()), min(ra.max(), rb.max())
        rates = np.unique(np.concatenate([ra, rb]))
        rates = rates[(rates >= lo) & (rates <= hi)]
    rates = np.sort(np.asarray(rates, dtype=float))[::-1]
    f = math.log(period / ta) / math.log(tb / ta)
    x = np.array([math.exp((1.0 - f) * math.log(short.intensity(r)) + f * math.log(long.intensity(r)))
                  for r in rates])
    keep = np.concatenate([[True], np.diff(x) > 0])  # a rate both curves hold flat gives one point
    return Curve(x[keep], {"mean": rates[keep]}, f"{short.source} / {long.source}: Sa({period:g} s) between "
                 f"{ta:g} and {tb:g} s, ln Sa linear in ln T at equal rate", period, short.extrapolate, short.site)


# ---- reading --------------------------------------------------------------------------------

def read(path, extrapolate="none", source="", period=None, imt=None, site=None):
    """The Curve of a file: a CSV (columns im and rate, or im and the mean and fractile columns; a
    rate named `mean` first), nshmp-haz's curves CSV (read_nshmp_csv: `site` picks the row) or a
    USGS hazard JSON (read_usgs: `imt` picks the measure, whose period it gives)."""
    path = Path(path)
    if path.suffix.lower() == ".json":
        curve = read_usgs(path, imt, extrapolate, source)
        if period is not None and curve.period != period:
            raise HazardError("period", period, f"the file's own: its measure {curve.meta['imt']} gives "
                              f"{curve.period}")
        return curve
    with path.open(newline="") as handle:
        rows = [row for row in csv.reader(line for line in handle if not line.startswith("#")) if row]
    if not rows:
        raise HazardError(path.name, "", "a CSV with a header: im, then the rate columns")
    header = [h.strip() for h in rows[0]]
    if header[:3] == ["name", "lon", "lat"]:
        return read_nshmp_csv(path, rows, extrapolate, source, period, site)
    if header[0] != "im" or len(header) < 2:
        raise HazardError(f"{path.name} header", ",".join(header), "im first, then rate (or mean and fractiles "
                          "such as p16, p84)")
    try:
        data = np.array([[float(v) for v in row] for row in rows[1:]], dtype=float)
    except ValueError as err:
        raise HazardError(path.name, str(err), "numbers below the header") from None
    if data.ndim != 2 or data.shape[1] != len(header):
        raise HazardError(path.name, f"{data.shape}", f"{len(header)} numbers on every row")
    rates = {name: data[:, i + 1] for i, name in enumerate(header[1:])}
    return Curve(data[:, 0], rates, source, period, extrapolate)


def read_nshmp_csv(path, rows, extrapolate, source, period, site):
    """The Curve of one site of nshmp-haz's curves file (curves/IMT/total.csv: name, lon, lat, then
    the intensities [g]; a row of rates per site); `site` names the row where there are several;
    rates of 0 (below the code's precision) dropped."""
    x = np.array([float(v) for v in rows[0][3:]])
    sites = {row[0].strip(): row for row in rows[1:]}
    if site is None and len(sites) == 1:
        site = next(iter(sites))
    if site not in sites:
        raise HazardError("site", site, f"one of the file's sites: {', '.join(sites)}")
    row = sites[site]
    y = np.array([float(v) for v in row[3:]])
    keep = y > 0
    return Curve(x[keep], {"mean": y[keep]}, source, period, extrapolate,
                 f"{site}, {float(row[2]):g} N {abs(float(row[1])):g} {'W' if float(row[1]) < 0 else 'E'}",
                 {"dropped_zero_rates": int((~keep).sum())})


def read_usgs(path, imt=None, extrapolate="none", source=""):
    """The Curve of a USGS hazard JSON: the nshmp-haz-ws response of the Unified Hazard Tool (status,
    response: [{metadata: {imt, vs30, longitude, latitude, xvalues...}, data: [{component, yvalues}]}]),
    its older static-curve one (metadata xvals, data [{yvals}] of one grid node) or a newer nshmp-haz
    one (response.hazardCurves: [{imt, data: [{component, values: {xs, ys}}]}]); the `Total` component; points at rate 0 (below the service's precision) dropped; `imt` (PGA,
    SA0P5, SA1P0...) picks one measure where the file has several."""
    data = json.loads(Path(path).read_text())
    found = []  # (imt id, x, y, metadata)
    response = data.get("response", data)
    if isinstance(response, list):
        for item in response:
            meta = item.get("metadata", {})
            ids = meta.get("imt", {})
            imt_id = ids.get("value" if "xvals" in meta else "id") if isinstance(ids, dict) else ids
            if "xvals" in meta:  # the static-curve service: one curve per grid node around the site
                nodes = item.get("data", [])
                if len(nodes) != 1:
                    raise HazardError(f"{Path(path).name} {imt_id}", f"{len(nodes)} grid nodes", "one (the site's): "
                                      "the static service answers with the nodes around a site; keep the site's")
                found.append((imt_id, meta["xvals"], nodes[0]["yvals"], meta))
                continue
            total = next((d for d in item.get("data", []) if d.get("component") == "Total"), None)
            if total is not None:
                found.append((imt_id, meta.get("xvalues"), total.get("yvalues"), meta))
    elif isinstance(response, dict) and "hazardCurves" in response:
        meta = response.get("metadata", {})
        for item in response["hazardCurves"]:
            ids = item.get("imt", {})
            total = next((d for d in item.get("data", []) if d.get("component", "").lower() == "total"), None)
            if total is not None:
                found.append((ids.get("value") if isinstance(ids, dict) else ids, total["values"]["xs"],
                              total["values"]["ys"], meta))
    if not found:
        raise HazardError(Path(path).name, "", "a USGS hazard response with a Total component")
    ids = [f[0] for f in found]
    if imt is None and len(found) > 1:
        raise HazardError("imt", None, f"one of {', '.join(map(str, ids))} (the file has several measures)")
    pick = found[0] if imt is None else next((f for f in found if f[0] == imt), None)
    if pick is None:
        raise HazardError("imt", imt, f"one of {', '.join(map(str, ids))}")
    name, x, y, meta = pick
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    keep = y > 0
    site = ", ".join(f"{key} {meta[key]}" for key in ("latitude", "longitude") if key in meta)
    vs30 = meta.get("vs30")
    if vs30 is not None:
        site += f", Vs30 {vs30.get('value', vs30) if isinstance(vs30, dict) else vs30}"
    return Curve(x[keep], {"mean": y[keep]}, source, usgs_period(name), extrapolate, site,
                 {"imt": name, "dropped_zero_rates": int((~keep).sum())})


def usgs_period(imt):
    """The period [s] of a USGS measure id (SA0P5 -> 0.5, SA1P0 -> 1.0); None for PGA and PGV."""
    if not isinstance(imt, str) or not imt.upper().startswith("SA"):
        return None
    return float(imt[2:].upper().replace("P", "."))


# ---- integration ----------------------------------------------------------------------------

@dataclass
class Integral:
    """The annual figure of quantities known at the stripes `levels` over curve `name` of `curve`
    (module doc): integral(v) the figure, integral.outside(v) the part of it from intensities the
    curve's points do not cover (its rule's); `lower` the index of the lowest stripe integrated."""

    curve: Curve
    levels: np.ndarray
    rule: str = "loglog"
    lower: int = 0
    name: str = None

    def __post_init__(self):
        if self.rule not in RULES:
            raise HazardError("rule", self.rule, f"one of {', '.join(RULES)}")
        s = self.levels = np.asarray(self.levels, dtype=float)
        x = self.curve.x
        if self.rule == "intervals":
            mids = np.sqrt(s[1:] * s[:-1])
            a = np.concatenate([[s[0] ** 2 / mids[0]], mids])[self.lower:]
            b = np.concatenate([mids, [s[-1]]])[self.lower:]
            rate_b = self.curve.rate(b, self.name)
            rate_b[-1] = 0.0  # the top stripe's interval reaches infinity
            self._weight = self.curve.rate(a, self.name) - rate_b
            self._out = (a < x[0]) | (b > x[-1])
            return
        points = np.union1d(s[self.lower:], x[(x > s[self.lower]) & (x < s[-1])])
        a, b = points[:-1], points[1:]
        self._seg = np.searchsorted(s, a, side="right") - 1  # the stripes' segment of each piece
        self._span = np.log(s[self._seg + 1] / s[self._seg])
        self._ua = np.log(a / s[self._seg]) / self._span  # where the piece starts in its segment (0..1)
        self._ub = np.log(b / s[self._seg]) / self._span
        self._rate_a = self.curve.rate(a, self.name)
        self._drop = self._rate_a - self.curve.rate(b, self.name)
        self._z = np.log(self._rate_a / self.curve.rate(b, self.name))  # kappa ln(b / a)
        self._tail = float(self.curve.rate(s[-1], self.name))
        self._out = np.append((a < x[0]) | (b > x[-1]), not self.curve.covers(s[-1]))

    def __call__(self, v):
        return float(np.sum(self.parts(v)))

    def outside(self, v):
        """The part of the figure from intensities outside the curve's points."""
        return float(np.sum(self.parts(v)[self._out]))

    def parts(self, v):
        """The figure piece by piece (for the loglog and semilog rules the last is the tail above the
        top stripe; for intervals one per stripe from the lower one)."""
        v = np.asarray(v, dtype=float)
        if self.rule == "intervals":
            return v[self.lower:] * self._weight
        v0, v1 = v[self._seg], v[self._seg + 1]
        power = (self.rule == "loglog") & (v0 > 0) & (v1 > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = np.where(power, np.log(np.where(power, v1 / v0, 1.0)), 0.0)  # ln(v1 / v0)
        va = np.where(power, v0 * np.exp(slope * self._ua), v0 + (v1 - v0) * self._ua)
        vb = np.where(power, v0 * np.exp(slope * self._ub), v0 + (v1 - v0) * self._ub)
        z = self._z
        # v = va (x/a)^beta against lambda = lambda_a (x/a)^-kappa: va lambda_a kappa L (e^((beta - kappa) L) - 1) / ((beta - kappa) L)
        grow = slope * (self._ub - self._ua) - z
        pieces = np.where(power, va * self._rate_a * z * _expm1_over(grow),
                          va * self._drop + (vb - va) * self._rate_a * _ramp(z))
        return np.append(pieces, v[-1] * self._tail)


def _expm1_over(z):
    """(e^z - 1) / z, 1 at z = 0."""
    z = np.asarray(z, dtype=float)
    small = np.abs(z) < 1e-8
    safe = np.where(small, 1.0, z)
    return np.where(small, 1.0 + 0.5 * z, np.expm1(safe) / safe)


def _ramp(z):
    """(1 - e^-z (1 + z)) / z = int_0^1 u z e^(-z u) du: the weight of a value rising linearly in
    ln x from 0 to 1 over a piece whose rate falls by e^-z."""
    z = np.asarray(z, dtype=float)
    small = np.abs(z) < 1e-2
    safe = np.where(small, 1.0, z)
    return np.where(small, z / 2 - z ** 2 / 3 + z ** 3 / 8 - z ** 4 / 30,
                    (-np.expm1(-safe) - safe * np.exp(-safe)) / safe)
