"""The damage-state fragilities and risk of an assessment's stripes (pidamper assess): per
configuration and damage state the lognormal fit over the stripes (Baker 2015's maximum
likelihood, fragility.fit_records) with its bootstrap band, the mean annual frequency of
exceedance over the study's hazard, and the paired-bootstrap intervals of the ratios to the first
configuration.  `study` is an assess.Study, `rows` its stripe rows."""
import math
from dataclasses import dataclass

import numpy as np

from . import fragility, hazard


def demand_matrix(study, rows, configuration, demand="drift_ratio"):
    """records x levels array of a demand in one configuration."""
    out = np.full((len(study.records), len(study.levels)), np.nan)
    level_index = {v: j for j, v in enumerate(study.levels)}
    for row in rows:
        if row["configuration"] == configuration:
            out[row["record_index"], level_index[row["level"]]] = row[demand]
    return out


@dataclass
class StateFit:
    """One damage state in one configuration: the fit and its bootstrap band, or why there is none
    (fragility.FragilityError.kind: 'none' when no run reached the state, 'all' when every run did...)."""
    exceed: np.ndarray  # records x levels
    fit: object = None
    band: object = None
    failed: str = ""


def analyse(study, rows):
    """{configuration: {state: StateFit}} and the risk table rows."""
    levels = np.asarray(study.levels)
    fits = {}
    for conf in study.configurations:
        drift = demand_matrix(study, rows, conf)
        fits[conf] = {}
        for state, limit in study.damage_states.items():
            exceed = drift >= limit
            try:
                fit = fragility.fit_records(levels, exceed)
                band = fragility.bootstrap(levels, exceed, n=study.bootstrap, seed=study.seed)
                fits[conf][state] = StateFit(exceed, fit, band)
            except fragility.FragilityError as err:
                fits[conf][state] = StateFit(exceed, failed=err.kind)
    return fits, risk(study, fits)


def risk_intervals(study, fits):
    """{state: {configuration: [Interval of the median ratio, Interval of the MAF ratio]}} to the
    first configuration: the paired bootstrap over records (bootstrap.paired), both fits redone on
    each draw; {} for a state whose fits failed."""
    from . import bootstrap

    levels = np.asarray(study.levels)
    confs = list(study.configurations)
    maf = _maf(study)
    out = {}
    for state in study.damage_states:
        if any(fits[c][state].fit is None for c in confs) or len(confs) < 2:
            out[state] = {}
            continue

        def statistic(rows, state=state):
            found = [fragility.fit_records(levels, fits[c][state].exceed[rows]) for c in confs]
            return [x for f in found[1:] for x in (f.theta / found[0].theta, maf(f) / maf(found[0]))]

        found = bootstrap.paired(statistic, len(study.records), n=study.bootstrap, seed=study.seed)
        out[state] = {c: found[2 * i:2 * i + 2] for i, c in enumerate(confs[1:])}
    return out


def _maf(study):
    """fit -> its MAF over the study's hazard: the closed form on a power law (fragility.maf_power_law),
    the exact integral on a site curve (fragility.maf_table; beyond its points its end segments' power
    laws with extrapolate = "loglog", else nothing: the curve's range only)."""
    spec = study.hazard
    if "curve" in spec:
        curve = study.curve
        tails = "power" if curve.extrapolate == "loglog" else "truncate"
        return lambda fit: fragility.maf_table(fit, curve.x, curve.rates[curve.mean], tails)
    return lambda fit: fragility.maf_power_law(fit, spec["k0"], spec["k"])


def varied_power_law(study, slope):
    """The study's power-law hazard with its k scaled by `slope` about its upper cited point (the
    rate there kept): the sensitivity rows; None for a site curve (its fractiles are its spread)."""
    spec = study.hazard
    if "curve" in spec:
        return None
    x_ref = max(p[0] for p in spec.get("points", [[1.0, 0]]))
    k0, k = spec["k0"], spec["k"]
    return hazard.Curve.power_law(k0 * x_ref ** (k * slope - k), k * slope, f"k x {slope:g}")


def risk(study, fits):
    """Rows (state, MAF per configuration, ratio of each to the first) from the study's hazard; a
    state without a fit has no MAF (nan)."""
    maf = _maf(study)
    confs = list(study.configurations)
    rows = []
    for state in study.damage_states:
        values = {c: maf(fits[c][state].fit) if fits[c][state].fit is not None else math.nan for c in confs}
        rows.append((state, values, {c: values[c] / values[confs[0]] for c in confs[1:]}))
    return rows
