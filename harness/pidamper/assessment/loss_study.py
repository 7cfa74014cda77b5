"""A study's losses and repair time, per stripe and over the hazard (FEMA P-58-1, 2018, chapter 7
for the intensity-based and chapter 8 for the time-based assessment).

Per configuration and stripe j (intensity x_j): the records that did not collapse go through
pelicun (losses.repair) with their own demands; collapse comes from the collapse fragility fitted to
the stripes' collapsed runs (Baker 2015's MLE, fragility.fit_records), or, when no fit is possible
(no run collapsed, or too few), from the observed fraction: the page says which.  Then

    E[L | x_j]      = P_C(x_j) C_rep + (1 - P_C(x_j)) mean_r E[L_r]         (r: records standing)
    P(T > t | x_j)  = P_C(x_j) [T_rep > t] + (1 - P_C(x_j)) mean_r P(T_r > t)

and over the hazard lambda(x) (hazard.Integral: the stripes' values interpolated between them by the
study's rule and integrated in closed form against the curve, held above the top stripe)

    EAL = int E[L | x] |d lambda(x)|,   MAF(T > t) likewise,

from the lowest stripe up (the page shows the loss there and how the EAL moves with the lower limit
and the rule).  Every number per record is stored (OUT/losses.parquet) and the paired bootstrap over
records resamples them."""
import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr

from . import bootstrap, demands, fragility, hazard, losses, p695


@dataclass
class StripeLosses:
    """One configuration: per stripe the collapse probability, and per record (rows) x stripe
    (columns) the mean repair cost [USD], P(irreparable) and P(repair days > t) per threshold t (nan
    where the record collapsed); collapsed (records x stripes, bool); how P_C was obtained."""
    p_collapse: np.ndarray
    collapsed: np.ndarray
    cost: np.ndarray
    irreparable: np.ndarray
    exceed_days: dict
    collapse_source: str
    groups: dict = None  # losses.GROUPS -> records x stripes mean repair cost [USD] (nan: collapsed)
    collapse: object = None  # the Collapse that gave p_collapse (the bootstrap refits it)


class Collapse:
    """P(collapse) at the stripes from the records drawn (an index array): the stripes' collapsed
    runs fitted (fragility.fit_records; the observed fraction when they admit no fit), or, given
    each record's IDA capacity (nan: it did not collapse up to censored_at), the capacities'
    lognormal fit (fragility.fit_capacities, the records that did not collapse censored); beta_m,
    a modelling dispersion (FEMA P-695 Table 7-2), widens either: sqrt(beta^2 + beta_m^2)."""

    def __init__(self, levels, collapsed, beta_m=0.0, capacities=None, censored_at=None):
        self.levels, self.collapsed, self.beta_m = np.asarray(levels, dtype=float), collapsed, beta_m
        self.capacities, self.censored_at = capacities, censored_at

    def fit(self, rows):
        """The lognormal fit (theta, beta) of the records drawn; FragilityError when there is none."""
        if self.capacities is None:
            return fragility.fit_records(self.levels, self.collapsed[rows])
        cap, cen = self.capacities[rows], self.censored_at[rows]
        return fragility.fit_capacities(cap[np.isfinite(cap)], cen[~np.isfinite(cap)])

    def __call__(self, rows):
        """(P_C per stripe, how it was obtained)."""
        try:
            fit = self.fit(rows)
        except fragility.FragilityError as err:
            if self.capacities is None:
                return self.collapsed[rows].mean(axis=0), f"observed fraction per stripe (no lognormal fit: {err.kind})"
            return np.full(self.levels.size, np.nan), f"no IDA fit ({err.kind})"
        beta = math.hypot(fit.beta, self.beta_m)
        with np.errstate(divide="ignore"):
            p = ndtr(np.log(self.levels / fit.theta) / beta)
        text = f"lognormal fit: median {fit.theta:.4g}, beta {fit.beta:.3g}"
        text += f" widened by beta_m = {self.beta_m:g} to {beta:.3g}" if self.beta_m else ""
        if self.capacities is not None:
            text = f"IDA capacities' {text} ({fit.censored} of {fit.n} records did not collapse)"
        return p, text

    def median(self, rows):
        """The median collapse intensity of the records drawn: where half of them collapsed in their
        IDA (FEMA P-695's S_CT, p695.half_collapse), else the lognormal fit's; FragilityError when
        there is none."""
        if self.capacities is None:
            return self.fit(rows).theta
        value = p695.half_collapse(self.capacities[rows])
        if not np.isfinite(value):
            raise fragility.FragilityError("half", "fewer than half of the records collapsed")
        return value


def collapse_probability(levels, collapsed, beta_m=0.0):
    """(P_C per stripe, how it was obtained) from the stripes' collapsed runs (Collapse)."""
    return Collapse(levels, collapsed, beta_m)(np.arange(collapsed.shape[0]))


def stripe_losses(study, rows, configuration, components, realizations, seed, sink=None, collapse=None):
    """StripeLosses of one configuration (rows: the study's run rows); `sink(level, frame)` receives
    each stripe's realizations (losses.repair's frame with record_index); `collapse` a Collapse
    (default: the stripes' collapsed runs)."""
    spec = study.losses
    levels = np.asarray(study.levels)
    n_rec, n_lev = len(study.records), len(levels)
    mine = [r for r in rows if r["configuration"] == configuration]
    collapsed = np.zeros((n_rec, n_lev), bool)
    index = {v: j for j, v in enumerate(study.levels)}
    for r in mine:
        collapsed[r["record_index"], index[r["level"]]] = bool(r["collapsed"])
    collapse = collapse or Collapse(levels, collapsed, study.beta_m)
    p_c, source = collapse(np.arange(n_rec))
    thresholds = spec["repair_days"]
    cost, irreparable = np.full((n_rec, n_lev), np.nan), np.full((n_rec, n_lev), np.nan)
    exceed = {t: np.full((n_rec, n_lev), np.nan) for t in thresholds}
    groups = {g: np.full((n_rec, n_lev), np.nan) for g in losses.GROUPS}
    names = [f"{name}-1" for name in demands.names(study.storeys)]
    for j, level in enumerate(study.levels):
        standing = [r for r in mine if r["level"] == level and not r["collapsed"]]
        if not standing:
            continue
        import pandas as pd
        frame = pd.DataFrame([[r[n[:-2]] for n in names] for r in standing], columns=names,
                             index=[r["record_index"] for r in standing])
        found = losses.repair(frame, components, spec["replacement_cost"], spec["replacement_days"],
                              spec["floor_area"], realizations, seed + j, spec.get("demand_dispersion", 0.0),
                              spec.get("total_loss"))
        if sink is not None:
            sink(level, found)
        grouped = found.groupby("record", sort=False)
        rec = np.array(list(grouped.groups))
        cost[rec, j] = grouped["cost"].mean().to_numpy()
        irreparable[rec, j] = grouped["irreparable"].mean().to_numpy()
        for t in thresholds:
            exceed[t][rec, j] = (found["days_parallel"] > t).groupby(found["record"], sort=False).mean().to_numpy()
        for g in losses.GROUPS:
            groups[g][rec, j] = grouped[f"cost_{g}"].mean().to_numpy()
    return StripeLosses(p_c, collapsed, cost, irreparable, exceed, source, groups, collapse)


def configuration_losses(study, rows, conf, collapse=None):
    """(StripeLosses, its realizations per stripe as frames) of one configuration."""
    frames = []
    sink = lambda level, frame: frames.append(frame.assign(configuration=conf, level=level))  # noqa: E731
    found = stripe_losses(study, rows, conf, study.losses["model"], study.losses["realizations"], study.seed, sink,
                          collapse)
    return found, frames


def configurations_losses(study, rows, confs, collapse=None, workers=1):
    """{configuration: configuration_losses(...)} of `confs` on up to `workers` processes; collapse
    {configuration: Collapse} or None (the stripes')."""
    args = [(study, rows, c, collapse[c] if collapse else None) for c in confs]
    if min(workers or 1, len(confs)) > 1:
        from concurrent.futures import ProcessPoolExecutor
        with ProcessPoolExecutor(max_workers=min(workers, len(confs))) as pool:
            return dict(zip(confs, pool.map(configuration_losses, *zip(*args))))
    return {c: configuration_losses(*a) for c, a in zip(confs, args)}


def stripe_values(study, stripes, rows_drawn):
    """Per stripe the list of E[L | x_j] (USD) and P(T > t | x_j) per threshold of one configuration from the
    records `rows_drawn` (the bootstrap's draw; collapse refitted on it); None when the collapse
    has no fit on them."""
    spec = study.losses
    collapse = stripes.collapse or Collapse(study.levels, stripes.collapsed, study.beta_m)
    p_c, _ = collapse(rows_drawn)
    if np.isnan(p_c).any():
        return None
    cost = _mean_standing(stripes.cost[rows_drawn])
    cost = np.where(np.isnan(cost), spec["replacement_cost"], cost)  # every drawn record collapsed there
    out = [p_c * spec["replacement_cost"] + (1 - p_c) * cost]
    for t in spec["repair_days"]:
        p = _mean_standing(stripes.exceed_days[t][rows_drawn])
        p = np.where(np.isnan(p), 1.0, p)
        out.append(p_c * (spec["replacement_days"] > t) + (1 - p_c) * p)
    return out


def annual(study, stripes, rows_drawn, integral):
    """[EAL, MAF(T > t) per threshold] of one configuration from the records `rows_drawn` over the
    hazard: integral a hazard.Integral over the study's stripes."""
    values = stripe_values(study, stripes, rows_drawn)
    if values is None:
        return [math.nan] * (1 + len(study.losses["repair_days"]))
    return [integral(v) for v in values]


def _mean_standing(values):
    """Per stripe the mean over the records standing (nan where none stood)."""
    standing = np.isfinite(values)
    count = standing.sum(axis=0)
    total = np.where(standing, values, 0.0).sum(axis=0)
    return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def compare(study, per_conf, integral, n=None, seed=None):
    """Paired bootstrap of every configuration's [EAL, MAF(T > t)...] and of their ratios to the
    first configuration: {configuration: [Interval...]}, {configuration: [ratio Interval...]}."""
    confs = list(per_conf)
    size = 1 + len(study.losses["repair_days"])

    def statistic(rows_drawn):
        values = [annual(study, per_conf[c], rows_drawn, integral) for c in confs]
        ratios = [v / b if b > 0 else np.nan for c in values[1:] for v, b in zip(c, values[0])]
        return [x for v in values for x in v] + ratios

    found = bootstrap.paired(statistic, len(study.records), n=n or study.bootstrap, seed=study.seed if seed is None
                             else seed)
    values = {c: found[i * size:(i + 1) * size] for i, c in enumerate(confs)}
    base = len(confs) * size
    ratios = {c: found[base + i * size: base + (i + 1) * size] for i, c in enumerate(confs[1:])}
    return values, ratios


def repair_complete(stripes, frames, level_index, days, replacement_days):
    """Fraction of buildings repaired against days after the event at one stripe: (1 - P_C) times
    the standing records' realizations' empirical CDF of days_parallel, plus P_C once the
    replacement is done."""
    p_c = stripes.p_collapse[level_index]
    done = np.zeros_like(np.asarray(days, dtype=float))
    if frames is not None and len(frames):
        sample = np.sort(frames["days_parallel"].to_numpy())
        done = np.searchsorted(sample, days, side="right") / sample.size
    return (1 - p_c) * done + p_c * (np.asarray(days) >= replacement_days)


@dataclass
class HazardFigures:
    """What the EAL owes to the hazard and the integration, every record counted: per configuration
    the EAL [USD/yr] by (lower stripe index, rule) (convergence), by curve name (the mean and its
    fractiles), the part from intensities outside the curve's points, the mean loss at the lowest
    stripe [USD], a bound on what lies below it [USD/yr] (the loss there at most the lowest
    stripe's: v(s_1) (lambda(x_1) - lambda(s_1)), x_1 the curve's first point) and an estimate of it
    (the power law through the two lowest stripes continued down to x_1); nan where the curve starts
    above s_1 or the lowest losses are 0."""
    convergence: dict
    curves: dict
    outside: dict
    lowest: dict
    below: dict
    trend: dict


def hazard_figures(study, per_conf, rule, lowers=3):
    """HazardFigures of the configurations' StripeLosses (every record) under the study's curve."""
    everyone = np.arange(len(study.records))
    loss = {c: (stripe_values(study, s, everyone) or [None])[0] for c, s in per_conf.items()}
    curve = study.curve
    convergence, curves, outside, below = {}, {}, {}, {}
    for lower in range(min(lowers, len(study.levels) - 1)):
        for how in hazard.RULES:
            try:
                integral = hazard.Integral(curve, study.levels, how, lower)
            except hazard.HazardError:  # the intervals rule reaches below the curve's first point
                convergence[lower, how] = {c: math.nan for c in loss}
                continue
            convergence[lower, how] = {c: integral(v) if v is not None else math.nan for c, v in loss.items()}
    for name in curve.names:
        integral = hazard.Integral(curve, study.levels, rule, 0, name)
        curves[name] = {c: integral(v) if v is not None else math.nan for c, v in loss.items()}
    integral = hazard.Integral(curve, study.levels, rule)
    start = study.levels[0]
    reach = curve.x[0] < start
    trend = {}
    for c, v in loss.items():
        outside[c] = integral.outside(v) if v is not None else math.nan
        below[c] = (v[0] * float(curve.rate(curve.x[0]) - curve.rate(start)) if reach and v is not None
                    else math.nan)
        trend[c] = _below_trend(curve, study.levels, v) if reach and v is not None else math.nan
    return HazardFigures(convergence, curves, outside, {c: v[0] if v is not None else math.nan
                                                         for c, v in loss.items()}, below, trend)


def _below_trend(curve, levels, v):
    """int_{x_1}^{s_1} v |d lambda| with v the power law through the two lowest stripes' values
    (nan when either is 0)."""
    (s1, s2), (v1, v2) = levels[:2], v[:2]
    if not (v1 > 0 and v2 > 0):
        return math.nan
    x0 = curve.x[0]
    slope = math.log(v2 / v1) / math.log(s2 / s1)
    piece = hazard.Integral(curve, [x0, s1], "loglog")
    return piece([v1 * (x0 / s1) ** slope, v1]) - v1 * float(curve.rate(s1))
