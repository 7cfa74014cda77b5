"""The headline ratios' intervals with what record resampling leaves out: the hazard curve's
uncertainty and the modelling uncertainty (a study's [uncertainty] table), by first-order
second-moment (FOSM) terms added to the paired bootstrap's interval.

The headline ratios, each configuration's over the first's: the EAL, the MAF of repair longer than
each threshold, and the median collapse intensity.  Per source i, a one-sigma step gives
delta_i = the change of ln(ratio) (a central difference: half the change between the plus and the
minus side; a one-sided step: the change from the reference); then, the bootstrap's interval
(lo_b, hi_b) about the point R taken as z = ndtri((1 + level) / 2) sigmas each way,

    lo = R exp(-sqrt(ln(R / lo_b)^2 + z^2 sum_i delta_i^2)),   hi = R exp(+sqrt(ln(hi_b / R)^2 + ...)),

the independent sources in quadrature as FEMA P-695 combines its beta_TOT.

Sources:
- hazard: the curve's intensities scaled by exp(+-beta_h) (a fractile curve if the epistemic
  uncertainty is a lognormal factor on the ground motion at every rate; loglog past its ends).  A
  rate error common to every intensity (the curve scaled up or down) cancels in the ratios exactly;
  only the change of the curve's shape moves them.
- a model case [uncertainty.NAME]: the FMU fields named (building or configuration parameters, each
  list item alike) multiplied by `factor` (the plus side) and divided by it (the minus side, unless
  sides = 1) in every configuration that gives the field (a configuration's own value first, else
  the building's); configurations without the fields keep their runs.  The perturbed configurations
  run every record at every stripe (no IDA), so these terms compare the stripes' collapse fit with
  the stripes' collapse fit: the reference is the study's own configurations with that fit.
"""
import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.special import ndtri

from . import bootstrap, fragility, hazard, loss_study


@dataclass(frozen=True)
class Case:
    """A model source: the fields scaled by factor (plus) and 1 / factor (minus, when sides == 2)."""
    name: str
    fields: tuple
    factor: float
    sides: int = 2

    @property
    def signs(self):
        return (1, -1) if self.sides == 2 else (1,)


def cases(spec):
    """The Cases of a study's [uncertainty] table, in file order."""
    return [Case(name, tuple(v["fields"]), float(v["factor"]), int(v.get("sides", 2)))
            for name, v in spec.items() if isinstance(v, dict)]


def _scaled(value, factor):
    return [v * factor for v in value] if isinstance(value, list) else value * factor


def perturbed(building, configurations, case, sign):
    """{configuration: its parameters with the case's fields scaled by factor**sign} of the
    configurations that give one of the fields (their own value, else the building's); the others
    are left out: they keep their runs."""
    out = {}
    for name, params in configurations.items():
        given = {**building, **params}
        scaled = {f: _scaled(given[f], case.factor ** sign) for f in case.fields if f in given}
        if scaled:
            out[name] = {**params, **scaled}
    return out


def label(configuration, case, sign):
    """The run table's configuration name of a perturbed configuration: 'damper@storeys+'."""
    return f"{configuration}@{case.name}{'+' if sign > 0 else '-'}"


def shifted(curve, factor):
    """The curve with its intensities scaled by `factor` (its rates kept; loglog past its ends)."""
    return hazard.Curve(curve.x * factor, dict(curve.rates), f"{curve.source} x {factor:.4g}", curve.period,
                        "loglog", curve.site)


def ratios(study, per_conf, integral, median):
    """{configuration: [ratio of EAL, of each MAF(T > t), of the median collapse intensity]} of every
    configuration but the first over the first; `median(conf, stripes)` the median collapse
    intensity (nan when it has none)."""
    everyone = np.arange(len(study.records))
    confs = list(per_conf)
    values = {c: loss_study.annual(study, per_conf[c], everyone, integral) + [median(c, per_conf[c])]
              for c in confs}
    base = values[confs[0]]
    return {c: [v / b if b > 0 else math.nan for v, b in zip(values[c], base)] for c in confs[1:]}


def median_or_nan(collapse, records):
    """Collapse.median of all `records` records, nan when it has none."""
    try:
        return collapse.median(np.arange(records))
    except fragility.FragilityError:
        return math.nan


def stripes_median(study, stripes):
    """The stripes' lognormal collapse fit's median (nan without a fit)."""
    return median_or_nan(loss_study.Collapse(study.levels, stripes.collapsed, study.beta_m), len(study.records))


def delta(plus, minus=None, reference=None):
    """One sigma of ln(ratio): half the change from minus to plus, or the change from the reference."""
    if minus is not None:
        return 0.5 * (math.log(plus) - math.log(minus))
    return math.log(plus) - math.log(reference)


def widened(interval, deltas, level=0.90):
    """(lo, hi) of a bootstrap Interval with the FOSM terms `deltas` (ln units, one sigma each) added
    in quadrature (module doc)."""
    z = float(ndtri(0.5 + level / 2))
    extra = (z * math.sqrt(sum(d * d for d in deltas))) ** 2
    point = interval.point
    lo = point * math.exp(-math.sqrt(math.log(point / interval.lo) ** 2 + extra))
    hi = point * math.exp(math.sqrt(math.log(interval.hi / point) ** 2 + extra))
    return lo, hi


@dataclass
class Source:
    """One source: its name and text, the headline ratios per configuration at its plus side and at
    its minus side (a one-sided source: the reference's), and whether it is central."""
    name: str
    text: str
    plus: dict
    minus: dict
    central: bool

    def delta(self, conf, k):
        """One sigma of ln(ratio) of headline k of configuration `conf` (nan where a ratio is not > 0)."""
        plus, minus = self.plus[conf][k], self.minus[conf][k]
        if not (plus > 0 and minus > 0):
            return math.nan
        return delta(plus, minus) if self.central else delta(plus, reference=minus)


@dataclass
class Found:
    """The Sources; per configuration the bootstrap Intervals and the widened (lo, hi) of each
    headline; the perturbed runs' count."""
    sources: list
    intervals: dict
    widened: dict
    runs: int


def assess(study, per_conf, loss_ratios, collapse, run, losses_of):
    """Found for a study with [uncertainty]: per_conf the configurations' StripeLosses, loss_ratios
    their bootstrap ratio Intervals (loss_study.compare), collapse {configuration: Collapse} (the
    IDA's, or None: the stripes'), run(configurations) -> rows of the perturbed configurations' runs
    (all of them at once), losses_of(configurations, rows) -> {configuration: StripeLosses}."""
    spec = study.uncertainty
    confs = list(per_conf)
    rule = study.hazard.get("rule", "loglog")
    integral = hazard.Integral(study.curve, study.levels, rule)
    collapse = collapse or {c: per_conf[c].collapse or loss_study.Collapse(study.levels, per_conf[c].collapsed,
                                                                            study.beta_m) for c in confs}

    def own_median(c, _stripes):
        return median_or_nan(collapse[c], len(study.records))

    sources = []
    if spec.get("hazard"):
        beta = spec["hazard"]
        sides = {s: ratios(study, per_conf, hazard.Integral(shifted(study.curve, math.exp(s * beta)), study.levels,
                                                            rule), own_median) for s in (1, -1)}
        sources.append(Source("hazard", f"the hazard curve's intensities x exp(+-{beta:g})", sides[1], sides[-1],
                              True))
    reference = {c: replace(s, collapse=None) for c, s in per_conf.items()}
    ref = ratios(study, reference, integral, lambda c, s: stripes_median(study, s))
    changed = {label(c, case, sign): p for case in cases(spec) for sign in case.signs
               for c, p in perturbed(study.building, study.configurations, case, sign).items()}
    rows = run(changed)  # every perturbed configuration at once: one pool
    found = losses_of(changed, rows)
    for case in cases(spec):
        sides = {}
        for sign in case.signs:
            mine = {c: found.get(label(c, case, sign), reference[c]) for c in confs}
            sides[sign] = ratios(study, mine, integral, lambda c, s: stripes_median(study, s))
        text = f"{', '.join(case.fields)} x {case.factor:g}" + (f" and / {case.factor:g}" if case.sides == 2 else "")
        sources.append(Source(case.name, text, sides[1], sides.get(-1, ref), case.sides == 2))
    intervals = _intervals(study, loss_ratios, collapse, confs)
    out = {}
    for c in confs[1:]:
        out[c] = []
        for k, interval in enumerate(intervals[c]):
            deltas = [source.delta(c, k) for source in sources]
            out[c].append(widened(interval, [d for d in deltas if np.isfinite(d)]) if np.isfinite(interval.lo)
                          else (math.nan, math.nan))
    return Found(sources, intervals, out, len(rows))


def _intervals(study, loss_ratios, collapse, confs):
    """Per configuration but the first: the bootstrap ratio Intervals of the losses' headlines and of
    the median collapse intensity (a paired bootstrap of its own, the same draws)."""
    def medians(rows):
        found = [collapse[c].median(rows) for c in confs]
        return [f / found[0] for f in found[1:]]

    try:
        median_ratios = bootstrap.paired(medians, len(study.records), n=study.bootstrap, seed=study.seed)
    except fragility.FragilityError:  # no median on all the records
        median_ratios = [bootstrap.Interval(math.nan, math.nan, math.nan, 0, 0)] * (len(confs) - 1)
    return {c: list(loss_ratios[c]) + [median_ratios[i]] for i, c in enumerate(confs[1:])}
