"""The paired bootstrap over records: its 90 % interval of a with/without ratio covers the true
ratio at the nominal rate on synthetic studies whose truth is known, and resamples that cannot be
fitted are counted, not hidden."""
import numpy as np
import pytest

from pidamper.assessment.bootstrap import paired
from pidamper.assessment.fragility import FragilityError


def test_the_90_percent_interval_of_a_ratio_covers_the_truth_at_the_nominal_rate():
    """400 studies of 44 records: lognormal capacities of two configurations on the same records
    (median 1.0 and 1.3, dispersion 0.4, correlation 0.8 between the configurations' log
    capacities).  Ratios: of the fitted medians (true 1.3) and of the mean annual frequencies
    under a power-law hazard k0 x^-k (closed form, true 1.3^-k since the dispersions are equal).
    Unpaired resampling would ignore the correlation and cover about 99.9 % (intervals 2.2 times
    wider): the upper bound catches it."""
    rng = np.random.default_rng(1)
    n, beta, rho, k = 44, 0.4, 0.8, 2.4
    truth = np.array([1.3, 1.3 ** -k])
    hits = np.zeros(2)
    for s in range(400):
        z, e = rng.standard_normal(n), rng.standard_normal(n)
        la = beta * z
        lb = np.log(1.3) + beta * (rho * z + np.sqrt(1 - rho ** 2) * e)

        def ratios(rows):  # lognormal MLE: mean and (ddof 0) variance of the logs
            a, b = la[rows], lb[rows]
            shift = b.mean() - a.mean()
            return np.exp(shift), np.exp(-k * shift + 0.5 * k * k * (b.var() - a.var()))

        for j, iv in enumerate(paired(ratios, n, n=400, seed=s)):
            hits[j] += iv.lo <= truth[j] <= iv.hi
    coverage = hits / 400
    assert np.all((coverage >= 0.85) & (coverage <= 0.95)), coverage


def test_resamples_that_cannot_be_fitted_are_counted():
    """A statistic that fails on resamples drawing record 0 twice or more, or gives nan on those
    without it: both are counted in `unfitted`; the interval uses the rest."""
    def statistic(rows):
        drawn = np.sum(rows == 0)
        if drawn > 1:
            raise FragilityError("separated", "record 0 drawn twice")
        return [float(np.mean(rows)), np.nan if drawn == 0 else 1.0]

    first, second = paired(statistic, 10, n=2000, seed=3)
    rng = np.random.default_rng(3)
    draws = [np.sum(rng.integers(0, 10, 10) == 0) for _ in range(2000)]
    assert first.unfitted == sum(d > 1 for d in draws) and second.unfitted == sum(d != 1 for d in draws)
    assert first.point == 4.5 and first.lo < 4.5 < first.hi and second.lo == second.hi == 1.0


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="records = 1"):
        paired(lambda rows: [1.0], 1)


def test_the_damage_state_ratios_are_paired_over_the_same_records():
    """analysis.risk_intervals: two configurations with the same exceedances give ratio 1 on every
    draw (a zero-width interval: the draws are paired; unpaired ones would spread); a configuration
    whose capacities are 1.3 times larger has its median ratio's point at the ratio of the fits."""
    from types import SimpleNamespace

    from pidamper.assessment import analysis, fragility

    rng = np.random.default_rng(5)
    levels = np.geomspace(0.2, 3.0, 8)
    capacity = np.exp(np.log(0.8) + 0.4 * rng.standard_normal(30))
    exceed = {"a": capacity[:, None] <= levels, "b": capacity[:, None] <= levels, "c": 1.3 * capacity[:, None] <= levels}
    fits = {c: {"DS": analysis.StateFit(e, fragility.fit_records(levels, e))} for c, e in exceed.items()}
    study = SimpleNamespace(levels=list(levels), configurations={"a": {}, "b": {}, "c": {}}, damage_states={"DS": 0.01},
                            records=[None] * 30, bootstrap=30, seed=0, hazard={"k0": 1e-3, "k": 2.5})
    found = analysis.risk_intervals(study, fits)["DS"]
    same_median, same_maf = found["b"]
    assert same_median.lo == same_median.hi == same_median.point == 1.0 and same_maf.lo == same_maf.hi == 1.0
    median, maf = found["c"]
    assert median.point == pytest.approx(fits["c"]["DS"].fit.theta / fits["a"]["DS"].fit.theta, rel=1e-12)
    assert median.lo <= median.point <= median.hi and maf.lo <= maf.point <= maf.hi and median.unfitted < 30
