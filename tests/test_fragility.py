"""Lognormal fragility by binomial MLE over stripes, bootstrap bands, and mean annual frequency."""
import math

import numpy as np
import pytest
from scipy import integrate
from scipy.special import log_ndtr
from scipy.stats import binom, norm

from pidamper.assessment.fragility import FragilityError, bootstrap, fit_records, fit_stripes, hazard_power_law_from_points, maf_power_law, maf_ratio, maf_table, plot_fragility

THETA0, BETA0 = 0.5, 0.4            # g, -
IM = np.geomspace(0.1, 1.5, 10)     # g


def p_true(x):
    return norm.cdf(np.log(np.asarray(x) / THETA0) / BETA0)


def binomial_stripes(rng, n_per=20):
    n = np.full(IM.size, n_per)
    return n, rng.binomial(n, p_true(IM))


def ida_matrix(rng, records):
    capacity = np.exp(rng.normal(math.log(THETA0), BETA0, records))
    return capacity[:, None] <= IM[None, :]


def loglik_binom(y, n, x, ln_theta, beta):
    """Independent log-likelihood (scipy's binomial pmf, with its constant), broadcasting."""
    p = norm.cdf((np.log(x) - ln_theta) / beta)
    return np.sum(binom.logpmf(y, n, p), axis=-1)


# -- 1. maximum likelihood -------------------------------------------------------------------------

def test_mle_recovers_median_and_dispersion_within_standard_errors():
    n, y = binomial_stripes(np.random.default_rng(7), n_per=30)
    f = fit_stripes(IM, n, y)
    assert abs(math.log(f.theta / THETA0)) < 3 * f.se_ln_theta
    assert abs(f.beta - BETA0) < 3 * f.se_beta
    assert 0 < f.se_ln_theta < 0.2 and 0 < f.se_beta < 0.2
    assert f.probability(f.theta) == pytest.approx(0.5)
    # the analytic observed information against a finite-difference Hessian of scipy's likelihood
    p0, h = np.array([math.log(f.theta), f.beta]), 1e-4
    hess = np.empty((2, 2))
    for i in range(2):
        for j in range(2):
            ei, ej = np.eye(2)[i] * h, np.eye(2)[j] * h
            hess[i, j] = sum(s * loglik_binom(y, n, IM, *(p0 + si * ei + sj * ej))
                             for s, si, sj in ((1, 1, 1), (-1, 1, -1), (-1, -1, 1), (1, -1, -1))) / (4 * h * h)
    np.testing.assert_allclose(f.cov, np.linalg.inv(-hess), rtol=1e-4)


def test_ida_records_recover_the_capacity_distribution():
    f = fit_records(IM, ida_matrix(np.random.default_rng(3), 200))
    assert abs(math.log(f.theta / THETA0)) < 3 * f.se_ln_theta
    assert abs(f.beta - BETA0) < 3 * f.se_beta
    assert f.n_total.tolist() == [200] * IM.size


def test_standard_errors_are_calibrated_over_repetitions():
    rng = np.random.default_rng(11)
    z = []
    for _ in range(200):
        n, y = binomial_stripes(rng)
        f = fit_stripes(IM, n, y)
        z.append((math.log(f.theta / THETA0) / f.se_ln_theta, (f.beta - BETA0) / f.se_beta))
    z = np.array(z)
    sd = z.std(axis=0, ddof=1)
    assert np.all((0.8 < sd) & (sd < 1.2)), sd                # measured: 1.02, 1.04
    assert np.all(np.abs(z.mean(axis=0)) < 0.35), z.mean(0)   # beta's small-sample bias: -0.2 se


def test_mle_is_the_binomial_likelihood_maximum():
    # unequal stripe sizes: the binomial weighting matters (a least-squares fit lands elsewhere)
    n = np.array([4, 40, 6, 50, 5, 60, 8, 30, 3, 20])
    y = np.random.default_rng(5).binomial(n, p_true(IM))
    f = fit_stripes(IM, n, y)
    lt = np.linspace(math.log(0.25), math.log(1.0), 601)
    be = np.linspace(0.1, 1.0, 601)
    grid = loglik_binom(y, n, IM, lt[:, None, None], be[None, :, None])
    i, j = np.unravel_index(np.argmax(grid), grid.shape)
    dlt, dbe = lt[1] - lt[0], be[1] - be[0]
    assert abs(math.log(f.theta) - lt[i]) <= dlt and abs(f.beta - be[j]) <= dbe
    const = np.sum(binom.logpmf(y, n, 0.5) - (y * math.log(0.5) + (n - y) * math.log(0.5)))
    assert f.loglik + const == pytest.approx(loglik_binom(y, n, IM, math.log(f.theta), f.beta), abs=1e-9)
    assert f.loglik + const >= grid.max() - 1e-9
    # the test has power: unweighted least squares on the fractions is many grid steps away
    from scipy.optimize import least_squares
    ls = least_squares(lambda u: norm.cdf((np.log(IM) - u[0]) / u[1]) - y / n, [math.log(0.5), 0.4]).x
    assert abs(ls[0] - lt[i]) > 5 * dlt or abs(ls[1] - be[j]) > 5 * dbe


def test_stripes_with_none_or_all_exceeding_and_empty_stripes():
    n = np.array([10, 10, 10, 10, 0])
    y = np.array([0, 3, 7, 10, 0])
    f = fit_stripes([0.2, 0.4, 0.6, 0.8, 5.0], n, y)
    assert 0.4 < f.theta < 0.6 and f.beta > 0 and np.isfinite(f.se_beta)
    assert f.im.tolist() == [0.2, 0.4, 0.6, 0.8]            # the n_total = 0 stripe is dropped


# -- 2. risk ----------------------------------------------------------------------------------------

def test_maf_power_law_closed_form_against_quad_and_table():
    k0, k = 1e-4, 2.5                                        # 1/yr g^k, -
    f = fit_stripes(IM, *binomial_stripes(np.random.default_rng(2)))
    closed = maf_power_law(f, k0, k)
    lt, b = math.log(f.theta), f.beta

    def integrand(u):                                        # P(x) |d lambda/du|, u = ln x (log space)
        return math.exp(log_ndtr((u - lt) / b) + math.log(k * k0) - k * u)

    peak = lt - k * b * b
    quad = sum(integrate.quad(integrand, lo, hi, epsabs=0, epsrel=1e-12, limit=200)[0]
               for lo, hi in ((-np.inf, peak), (peak, np.inf)))
    assert closed == pytest.approx(quad, rel=1e-9)
    x = np.geomspace(1e-3, 1e2, 400)
    assert maf_table(f, x, k0 * x ** -k) == pytest.approx(closed, rel=1e-10)
    assert maf_table(f, x, k0 * x ** -k, tails="truncate") == pytest.approx(closed, rel=1e-3)
    assert maf_table(f, x[150:250], k0 * x[150:250] ** -k, tails="truncate") < closed  # a lower bound


def test_maf_table_on_a_curved_hazard_against_quad_of_the_loglog_interpolant():
    im = np.array([0.05, 0.1, 0.2, 0.4, 0.8, 1.5, 3.0])
    rate = np.array([2e-1, 6e-2, 1.2e-2, 1.5e-3, 1.0e-4, 4e-6, 5e-8])
    f = fit_stripes(IM, *binomial_stripes(np.random.default_rng(4)))
    lx, lr = np.log(im), np.log(rate)
    slope = np.diff(lr) / np.diff(lx)
    lt, b = math.log(f.theta), f.beta

    def integrand(u):                                        # P(x) (-d lambda/du), interpolant + tails
        i = int(np.clip(np.searchsorted(lx, u) - 1, 0, slope.size - 1))
        return -slope[i] * math.exp(log_ndtr((u - lt) / b) + lr[i] + slope[i] * (u - lx[i]))

    edges = [-np.inf, *lx, np.inf]
    quad = sum(integrate.quad(integrand, lo, hi, epsabs=0, epsrel=1e-12, limit=200)[0]
               for lo, hi in zip(edges[:-1], edges[1:]))
    assert maf_table(f, im, rate) == pytest.approx(quad, rel=1e-9)
    inner = sum(integrate.quad(integrand, lo, hi, epsabs=0, epsrel=1e-12)[0] for lo, hi in zip(lx[:-1], lx[1:]))
    assert maf_table(f, im, rate, tails="truncate") == pytest.approx(inner, rel=1e-9)


def test_power_law_from_points_and_the_damper_ratio():
    k0, k = hazard_power_law_from_points(0.2, 1e-2, 0.8, 1e-4)
    assert k == pytest.approx(math.log(100) / math.log(4))
    assert k0 * 0.2 ** -k == pytest.approx(1e-2) and k0 * 0.8 ** -k == pytest.approx(1e-4)
    bare = fit_stripes(IM, [20] * 10, [0, 0, 1, 3, 7, 12, 16, 18, 20, 20])
    damped = fit_stripes(IM * 1.6, [20] * 10, [0, 0, 1, 3, 7, 12, 16, 18, 20, 20])  # 1.6x stronger
    assert damped.theta == pytest.approx(1.6 * bare.theta) and damped.beta == pytest.approx(bare.beta)
    r = maf_ratio(damped, bare, power_law=(k0, k))
    assert r.ratio == pytest.approx(1.6 ** -k) and r.maf_with == pytest.approx(maf_power_law(damped, k0, k))
    x = np.geomspace(0.01, 10, 50)
    assert maf_ratio(damped, bare, table=(x, k0 * x ** -k)).ratio == pytest.approx(1.6 ** -k, rel=1e-9)


# -- 3. bootstrap -----------------------------------------------------------------------------------

def test_bootstrap_band_covers_the_true_curve():
    levels = THETA0 * np.exp(BETA0 * np.array([-1.0, 0.0, 1.0]))   # P = 0.16, 0.5, 0.84
    covered = []
    for seed in range(20):
        band = bootstrap(IM, ida_matrix(np.random.default_rng(seed), 40), n=100, seed=seed, levels=levels)
        assert band.n_failed == 0 and band.theta.size == 100
        assert np.all(band.p05 <= band.p50) and np.all(band.p50 <= band.p95)
        covered.append((band.p05 <= p_true(levels)) & (p_true(levels) <= band.p95))
    assert np.mean(covered) >= 0.65, np.mean(covered)          # measured 0.80 for this 90 % band


def test_bootstrap_band_narrows_with_more_records():
    levels = np.geomspace(IM[0], IM[-1], 40)
    width = {}
    for records in (20, 320):
        band = bootstrap(IM, ida_matrix(np.random.default_rng(1), records), n=200, seed=1, levels=levels)
        width[records] = np.mean(band.p95 - band.p05)
    assert width[320] < 0.6 * width[20], width                  # measured 0.39; sqrt(20/320) = 0.25


def test_bootstrap_skips_and_counts_unfittable_resamples():
    exceed = np.array([[0, 0, 1, 1], [0, 1, 1, 1], [0, 0, 0, 1], [0, 0, 1, 1], [0, 1, 1, 1]], dtype=bool)
    im = [0.1, 0.2, 0.4, 0.8]
    band = bootstrap(im, exceed, n=300, seed=3)
    assert band.n_failed > 0 and band.theta.size + band.n_failed == 300
    assert band.levels[0] == pytest.approx(0.05) and band.levels[-1] == pytest.approx(1.6)
    again = bootstrap(im, exceed, n=300, seed=3)
    np.testing.assert_array_equal(band.theta, again.theta)
    with pytest.raises(FragilityError, match="none of the 50 bootstrap resamples"):
        bootstrap(im, np.array([[0, 0, 1, 1]] * 3, dtype=bool), n=50)


def test_plot_fragility_draws_curve_band_and_markers():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    exceed = ida_matrix(np.random.default_rng(0), 30)
    f, band = fit_records(IM, exceed), bootstrap(IM, exceed, n=50)
    fig, ax = plt.subplots()
    line = plot_fragility(ax, f, band, label="bare", data=(IM, exceed.mean(axis=0)))
    assert len(ax.lines) == 2 and len(ax.collections) == 1 and "bare" in line.get_label()
    plt.close(fig)


# -- 4. degenerate inputs ---------------------------------------------------------------------------

@pytest.mark.parametrize("n_exceed, kind, message", [
    ([0, 0, 0], "none", r"no exceedance at any stripe .*n_exceed = \[0, 0, 0\] of n_total = \[5, 5, 5\]"),
    ([5, 5, 5], "all", r"every run exceeds at every stripe .*n_exceed = \[5, 5, 5\]"),
    ([0, 0, 5], "separated", r"every exceedance at IM >= 0.4 and every non-exceedance at IM <= 0.2"),
    ([0, 3, 5], "separated", r"every exceedance at IM >= 0.2 and every non-exceedance at IM <= 0.2"),
    ([4, 2, 1], "decreasing", r"does not increase with IM .*n_exceed = \[4, 2, 1\]"),
])
def test_degenerate_stripes_are_refused_naming_the_counts(n_exceed, kind, message):
    with pytest.raises(FragilityError, match=message) as err:
        fit_stripes([0.1, 0.2, 0.4], [5, 5, 5], n_exceed)
    assert err.value.kind == kind and isinstance(err.value, ValueError)


def test_single_level_and_malformed_stripes_are_refused():
    with pytest.raises(FragilityError, match=r"one IM level .*im = \[0.3, 0.3\]") as err:
        fit_stripes([0.3, 0.3], [10, 10], [4, 6])
    assert err.value.kind == "single_level"
    with pytest.raises(ValueError, match=r"im = \[-0.1\]"):
        fit_stripes([-0.1, 0.2], [5, 5], [1, 2])
    with pytest.raises(ValueError, match=r"n_exceed > n_total at im = \[0.2\]: n_exceed = \[7\], n_total = \[5\]"):
        fit_stripes([0.1, 0.2], [5, 5], [1, 7])
    with pytest.raises(ValueError, match=r"n_total = \[5.5, 5.0\]"):
        fit_stripes([0.1, 0.2], [5.5, 5], [1, 2])
    with pytest.raises(ValueError, match=r"shapes \(2,\), \(3,\), \(2,\)"):
        fit_stripes([0.1, 0.2], [5, 5, 5], [1, 2])
    with pytest.raises(ValueError, match=r"boolean .*got values \[2\]"):
        fit_records([0.1, 0.2], [[0, 1], [2, 1]])
    with pytest.raises(ValueError, match=r"exceed \(2, 3\), im \(2,\)"):
        fit_records([0.1, 0.2], np.zeros((2, 3), dtype=bool))


def test_malformed_hazards_are_refused_naming_the_value():
    f = fit_stripes(IM, *binomial_stripes(np.random.default_rng(0)))
    with pytest.raises(ValueError, match=r"im\[1\] = 0.3 >= im\[2\] = 0.2"):
        maf_table(f, [0.1, 0.3, 0.2], [1e-2, 1e-3, 1e-4])
    with pytest.raises(ValueError, match=r"rate\[0\] = 0.001 < rate\[1\] = 0.01"):
        maf_table(f, [0.1, 0.2, 0.3], [1e-3, 1e-2, 1e-4])
    with pytest.raises(ValueError, match=r"rate = \[0.0\]"):
        maf_table(f, [0.1, 0.2], [1e-3, 0.0])
    with pytest.raises(ValueError, match=r"rate\[-2\] = rate\[-1\] = 0.001"):
        maf_table(f, [0.1, 0.2, 0.3], [1e-2, 1e-3, 1e-3])
    assert maf_table(f, [0.1, 0.2, 0.3], [1e-2, 1e-3, 1e-3], tails="truncate") > 0
    with pytest.raises(ValueError, match=r"tails = 'linear'"):
        maf_table(f, [0.1, 0.2], [1e-2, 1e-3], tails="linear")
    with pytest.raises(ValueError, match=r"k = -1"):
        maf_power_law(f, 1e-4, -1)
    with pytest.raises(ValueError, match=r"x1 = x2 = 0.2"):
        hazard_power_law_from_points(0.2, 1e-2, 0.2, 1e-3)
    with pytest.raises(ValueError, match=r"'rate2': -1"):
        hazard_power_law_from_points(0.2, 1e-2, 0.4, -1)
    with pytest.raises(ValueError, match="exactly one hazard"):
        maf_ratio(f, f)
