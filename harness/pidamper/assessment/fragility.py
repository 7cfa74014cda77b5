"""Lognormal fragility by maximum likelihood over intensity stripes, bootstrap bands, and risk.

Conventions
-----------
* IM is any positive intensity measure (PGA in g or m/s^2, Sa(T1, 5 %) in g, ...); every IM
  argument and result is in the caller's IM unit.  Only ratios and logarithms of IM enter.
* Fragility (damage state DS exceeded given IM = x), with median theta (IM unit) and
  dispersion beta (dimensionless, the standard deviation of ln capacity):

      P(DS | IM = x) = Phi(ln(x / theta) / beta)

* A stripe j is one intensity level x_j at which n_total_j runs were made, n_exceed_j of which
  exceeded the damage state (multiple stripe analysis, MSA; an incremental dynamic analysis, IDA,
  gives the same counts when read at fixed levels, see `fit_records`).
* Rates are mean annual frequencies (1/yr).

Sources
-------
[Baker 2015]  J. W. Baker, "Efficient analytical fragility function fitting using dynamic
    structural analysis", Earthquake Spectra 31(1):579-599 (2015), doi:10.1193/021113EQS025M.
    Binomial likelihood over stripes, maximised over (theta, beta).
[Albert & Anderson 1984]  A. Albert, J. A. Anderson, "On the existence of maximum likelihood
    estimates in logistic regression models", Biometrika 71(1):1-10 (1984).  The MLE of a binary
    regression exists (is finite) iff the data overlap (no complete or quasi-complete separation);
    the same argument holds for the probit link used here.
[Efron & Tibshirani 1993]  B. Efron, R. J. Tibshirani, "An Introduction to the Bootstrap",
    Chapman & Hall (1993), ch. 13: percentile intervals.
[Cornell et al. 2002]  C. A. Cornell, F. Jalayer, R. O. Hamburger, D. A. Foutch, "Probabilistic
    basis for 2000 SAC Federal Emergency Management Agency steel moment frame guidelines",
    J. Struct. Eng. 128(4):526-533 (2002), doi:10.1061/(ASCE)0733-9445(2002)128:4(526).
    lambda_DS = integral P(DS | im) |d lambda_IM(im)| and its closed form under a power-law hazard.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize
from scipy.special import log_ndtr, ndtr, ndtri

__all__ = ["Band", "Fit", "FragilityError", "Risk", "bootstrap", "fit_records", "fit_stripes",
           "hazard_power_law_from_points", "maf_power_law", "maf_ratio", "maf_table", "plot_fragility"]

_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


class FragilityError(ValueError):
    """The data admit no finite lognormal MLE.  `kind` names the case:

    "none"         no exceedance at any stripe: theta -> infinity;
    "all"          every run exceeds at every stripe: theta -> 0;
    "separated"    every exceedance lies at IM >= every non-exceedance (complete or quasi-complete
                   separation, [Albert & Anderson 1984]): beta -> 0, theta not identified;
    "single_level" all runs at one IM level: theta and beta are not separately identified;
    "decreasing"   exceedance is not positively associated with ln IM: beta -> infinity;
    "no_convergence" the optimiser stopped away from a stationary point (not expected once the
                   cases above are excluded: the probit log-likelihood is concave in (-ln theta/beta,
                   1/beta)).
    """

    def __init__(self, kind: str, message: str):
        super().__init__(message)
        self.kind = kind


@dataclass
class Fit:
    """A fitted lognormal fragility P(DS | IM = x) = Phi(ln(x / theta) / beta).

    theta: median (IM unit); beta: dispersion (-); se_ln_theta, se_beta: standard errors from the
    observed information (the analytic Hessian of the negative log-likelihood at the MLE, inverted;
    parameters (ln theta, beta)); cov: that 2x2 covariance of (ln theta, beta); loglik: the maximised
    binomial log-likelihood WITHOUT the constant sum ln C(n_total, n_exceed) (as in [Baker 2015]);
    im, n_total, n_exceed: the stripes fitted (stripes with n_total = 0 dropped).
    """
    theta: float
    beta: float
    se_ln_theta: float
    se_beta: float
    cov: np.ndarray
    loglik: float
    im: np.ndarray = field(repr=False)
    n_total: np.ndarray = field(repr=False)
    n_exceed: np.ndarray = field(repr=False)

    def probability(self, x):
        """P(DS | IM = x) for IM x > 0 (scalar or array, IM unit); 0 at x = 0."""
        x = np.asarray(x, dtype=float)
        with np.errstate(divide="ignore"):
            p = ndtr(np.log(x / self.theta) / self.beta)
        return float(p) if p.ndim == 0 else p

    @property
    def fraction(self) -> np.ndarray:
        """Observed exceedance fraction per stripe, n_exceed / n_total."""
        return self.n_exceed / self.n_total


@dataclass
class Band:
    """Bootstrap over records ([Efron & Tibshirani 1993] percentile method, pointwise).

    levels: IM grid (IM unit); p05, p50, p95: 5/50/95 % pointwise percentiles of the fitted
    fragility over the resamples; theta, beta: the fitted parameters of each successful resample;
    n: resamples drawn; n_failed: resamples skipped because they admit no finite MLE
    (`FragilityError`, e.g. all drawn records exceed at the same stripes).
    """
    levels: np.ndarray
    p05: np.ndarray
    p50: np.ndarray
    p95: np.ndarray
    theta: np.ndarray = field(repr=False)
    beta: np.ndarray = field(repr=False)
    n: int
    n_failed: int


@dataclass
class Risk:
    """Mean annual frequencies (1/yr) of exceeding a damage state with and without the damper,
    and ratio = maf_with / maf_without (< 1: the damper lowers the risk)."""
    maf_with: float
    maf_without: float
    ratio: float


# ----------------------------------------------------------------------------------------------
# likelihood

def _phi_ratios(z):
    """(phi/Phi)(z) and (phi/(1-Phi))(z), both in log space (no 0/0 in the tails)."""
    log_phi = -0.5 * z * z - _LOG_SQRT_2PI
    return np.exp(log_phi - log_ndtr(z)), np.exp(log_phi - log_ndtr(-z))


def _loglik(z, n, y):
    """sum_j y_j ln p_j + (n_j - y_j) ln(1 - p_j), p_j = Phi(z_j) ([Baker 2015]); 0 ln 0 = 0."""
    return float(np.sum(y * log_ndtr(z)) + np.sum((n - y) * log_ndtr(-z)))


def _dz_derivatives(z, n, y):
    """dl/dz_j and d2l/dz_j^2 of the stripe terms (binomial probit, observed, not expected)."""
    r1, r2 = _phi_ratios(z)
    g = y * r1 - (n - y) * r2
    h = -y * r1 * (z + r1) - (n - y) * r2 * (r2 - z)
    return g, h


def _check_stripes(im, n_total, n_exceed):
    im = np.asarray(im, dtype=float)
    n_total = np.asarray(n_total)
    n_exceed = np.asarray(n_exceed)
    if im.ndim != 1 or n_total.shape != im.shape or n_exceed.shape != im.shape:
        raise ValueError(f"im, n_total, n_exceed must be 1-D of one length; shapes {im.shape}, "
                         f"{n_total.shape}, {n_exceed.shape}")
    bad = ~np.isfinite(im) | (im <= 0)
    if bad.any():
        raise ValueError(f"IM levels must be finite and > 0; got im = {im[bad].tolist()}")
    for name, v in (("n_total", n_total), ("n_exceed", n_exceed)):
        vf = v.astype(float)
        if not np.all(np.isfinite(vf)) or np.any(vf != np.round(vf)) or np.any(vf < 0):
            raise ValueError(f"{name} must hold non-negative integers; got {name} = {v.tolist()}")
    n_total = n_total.astype(float)
    n_exceed = n_exceed.astype(float)
    over = n_exceed > n_total
    if over.any():
        raise ValueError(f"n_exceed > n_total at im = {im[over].tolist()}: n_exceed = "
                         f"{n_exceed[over].astype(int).tolist()}, n_total = {n_total[over].astype(int).tolist()}")
    keep = n_total > 0
    return im[keep], n_total[keep], n_exceed[keep]


def _degenerate(im, n, y):
    """Raise FragilityError when no finite MLE with beta > 0 exists (see FragilityError)."""
    counts = f"im = {im.tolist()}, n_exceed = {y.astype(int).tolist()} of n_total = {n.astype(int).tolist()}"
    if im.size == 0:
        raise FragilityError("none", "no runs: every stripe has n_total = 0")
    if y.sum() == 0:
        raise FragilityError("none", f"no exceedance at any stripe ({counts}); the MLE median theta "
                                     "is unbounded (theta -> infinity)")
    if y.sum() == n.sum():
        raise FragilityError("all", f"every run exceeds at every stripe ({counts}); the MLE median "
                                    "theta -> 0")
    if np.unique(im).size < 2:
        raise FragilityError("single_level", f"all stripes at one IM level ({counts}); theta and beta "
                                             "are not separately identified")
    lo_exceed = im[y > 0].min()
    hi_safe = im[y < n].max()
    if lo_exceed >= hi_safe:
        raise FragilityError("separated", f"the stripes separate: every exceedance at IM >= "
                                          f"{lo_exceed:g} and every non-exceedance at IM <= {hi_safe:g} "
                                          f"({counts}); the MLE dispersion beta -> 0")
    # Profile likelihood over c1 = 1/beta is concave (probit is concave in (c0, c1)); its slope at
    # c1 = 0 is proportional to sum_j (y_j - n_j pbar) ln x_j.  If <= 0 the sup is at beta -> inf.
    pbar = y.sum() / n.sum()
    if np.sum((y - n * pbar) * np.log(im)) <= 0:
        raise FragilityError("decreasing", f"exceedance does not increase with IM ({counts}); the MLE "
                                           "dispersion beta -> infinity")


def _start(lx, n, y):
    """Probit regression start: weighted least squares of Phi^-1((y + 0.5)/(n + 1)) on ln x."""
    f = (y + 0.5) / (n + 1.0)
    zt = ndtri(f)
    w = n * np.exp(-zt * zt) / (f * (1.0 - f))          # ~ 2 pi / var(probit of f), delta method
    A = np.stack([np.ones_like(lx), lx], axis=1) * np.sqrt(w)[:, None]
    c0, c1 = np.linalg.lstsq(A, zt * np.sqrt(w), rcond=None)[0]
    if c1 > 0 and np.isfinite(c0):
        a, b = -c0 / c1, 1.0 / c1
        span = lx.max() - lx.min()
        if np.isfinite(a) and 1e-3 * span < b < 1e3 * (span + 1):
            return np.array([a, math.log(b)])
    # fallback: median at the exceedance-weighted mean of ln x, beta from the spread of ln x
    a = float(np.sum(n * lx) / n.sum())
    return np.array([a, math.log(max(np.std(lx), 0.1))])


def fit_stripes(im, n_total, n_exceed) -> Fit:
    """Lognormal fragility by maximum likelihood over IM stripes ([Baker 2015], binomial).

    Maximises l(theta, beta) = sum_j [y_j ln p_j + (n_j - y_j) ln(1 - p_j)],
    p_j = Phi(ln(x_j / theta) / beta), y_j = n_exceed_j, n_j = n_total_j, x_j = im_j > 0 (IM unit).
    The optimiser (scipy.optimize.minimize, "trust-exact", analytic gradient and Hessian) works on
    (ln theta, ln beta), from a weighted probit-regression start.  Stripes with 0 or all exceedances
    enter normally (0 ln 0 = 0, logs of Phi evaluated by log_ndtr); stripes with n_total = 0 are
    dropped.  Standard errors: the observed information, i.e. the analytic Hessian of -l in
    (ln theta, beta) at the optimum, inverted.

    The stripes are assumed independent (MSA with different records per stripe).  With the SAME
    records at every stripe (IDA) the counts are correlated and these standard errors are not
    calibrated; use `bootstrap` over records instead.

    Raises FragilityError (a ValueError; `.kind` names the case) when no finite MLE exists: no
    exceedance anywhere ("none"), all exceed everywhere ("all"), perfect separation ("separated",
    beta -> 0), one IM level ("single_level"), fraction not increasing with IM ("decreasing",
    beta -> inf).  Malformed inputs raise ValueError naming the values.
    """
    im, n, y = _check_stripes(im, n_total, n_exceed)
    _degenerate(im, n, y)
    lx = np.log(im)

    def fun(u):
        a, s = u
        b = math.exp(s)
        z = (lx - a) / b
        g, h = _dz_derivatives(z, n, y)
        dz = np.stack([np.full_like(z, -1.0 / b), -z])          # dz/da, dz/ds
        grad = dz @ g
        hess = (dz * h) @ dz.T
        hess[0, 1] += np.sum(g) / b                               # d2z/da ds = 1/b
        hess[1, 0] += np.sum(g) / b
        hess[1, 1] += np.sum(g * z)                               # d2z/ds2 = z
        return -_loglik(z, n, y), -grad, -hess

    cache = {}

    def get(u):
        key = tuple(u)
        if key not in cache:
            cache.clear()
            cache[key] = fun(u)
        return cache[key]

    u0 = _start(lx, n, y)
    res = optimize.minimize(lambda u: get(u)[0], u0, jac=lambda u: get(u)[1], hess=lambda u: get(u)[2],
                            method="trust-exact", options={"gtol": 1e-10, "maxiter": 200})
    a, s = res.x
    b = math.exp(s)
    z = (lx - a) / b
    g, h = _dz_derivatives(z, n, y)
    if not np.all(np.isfinite(res.x)) or np.max(np.abs(res.jac)) > 1e-6 * math.sqrt(n.sum()):
        raise FragilityError("no_convergence", f"MLE did not converge ({res.message}; theta = "
                                               f"{math.exp(a):g}, beta = {b:g}, gradient = {res.jac})")
    # observed information in (a = ln theta, beta): dz/da = -1/b, dz/db = -z/b,
    # d2z/da db = 1/b^2, d2z/db2 = 2 z/b^2
    dz = np.stack([np.full_like(z, -1.0 / b), -z / b])
    info = -((dz * h) @ dz.T)
    info[0, 1] -= np.sum(g) / b ** 2
    info[1, 0] -= np.sum(g) / b ** 2
    info[1, 1] -= 2.0 * np.sum(g * z) / b ** 2
    cov = np.linalg.inv(info)
    return Fit(theta=math.exp(a), beta=b, se_ln_theta=math.sqrt(cov[0, 0]), se_beta=math.sqrt(cov[1, 1]),
               cov=cov, loglik=_loglik(z, n, y), im=im, n_total=n, n_exceed=y)


def _check_records(im, exceed):
    im = np.asarray(im, dtype=float)
    exceed = np.asarray(exceed)
    if exceed.ndim != 2 or im.ndim != 1 or exceed.shape[1] != im.size:
        raise ValueError(f"exceed must be (records, levels) with levels = len(im); shapes "
                         f"exceed {exceed.shape}, im {im.shape}")
    if exceed.dtype != bool:
        bad = ~np.isin(exceed, (0, 1))
        if bad.any():
            raise ValueError(f"exceed must be boolean (or 0/1); got values {np.unique(exceed[bad])[:5].tolist()}")
        exceed = exceed.astype(bool)
    return im, exceed


def fit_records(im, exceed) -> Fit:
    """`fit_stripes` on an IDA/MSA matrix: im (levels,), IM unit; exceed (records, levels) boolean,
    True where the record scaled to that level exceeds the damage state.  Counts per stripe:
    n_total = records, n_exceed = column sums."""
    im, exceed = _check_records(im, exceed)
    return fit_stripes(im, np.full(im.size, exceed.shape[0]), exceed.sum(axis=0))


def bootstrap(im, exceed, n: int = 1000, seed: int = 0, levels=None) -> Band:
    """Bootstrap band of the fragility by resampling RECORDS (rows of `exceed`) with replacement.

    Each resample (numpy default_rng(seed)) is refitted by `fit_records`; one that admits no finite
    MLE (FragilityError) is skipped and counted in Band.n_failed.  The band is the pointwise 5/50/95 %
    percentile ([Efron & Tibshirani 1993]) of Phi(ln(x/theta_b)/beta_b) over the fitted resamples, on
    `levels` (IM unit; default 200 log-spaced points from min(im)/2 to 2 max(im)).  Resampling whole
    records keeps the dependence between stripes of an IDA, which the binomial standard errors of
    `fit_stripes` ignore.  Raises FragilityError if no resample can be fitted.
    """
    im, exceed = _check_records(im, exceed)
    if int(n) < 1:
        raise ValueError(f"n must be >= 1 resamples; got n = {n}")
    if levels is None:
        levels = np.geomspace(im.min() / 2.0, im.max() * 2.0, 200)
    levels = np.asarray(levels, dtype=float)
    rng = np.random.default_rng(seed)
    m = exceed.shape[0]
    thetas, betas, failed = [], [], 0
    for _ in range(int(n)):
        rows = rng.integers(0, m, m)
        try:
            f = fit_records(im, exceed[rows])
        except FragilityError:
            failed += 1
            continue
        thetas.append(f.theta)
        betas.append(f.beta)
    if not thetas:
        raise FragilityError("none", f"none of the {n} bootstrap resamples could be fitted")
    thetas, betas = np.array(thetas), np.array(betas)
    with np.errstate(divide="ignore"):
        curves = ndtr(np.log(levels[None, :] / thetas[:, None]) / betas[:, None])
    p05, p50, p95 = np.percentile(curves, [5.0, 50.0, 95.0], axis=0)
    return Band(levels=levels, p05=p05, p50=p50, p95=p95, theta=thetas, beta=betas, n=int(n), n_failed=failed)


# ----------------------------------------------------------------------------------------------
# risk

def hazard_power_law_from_points(x1, rate1, x2, rate2):
    """(k0, k) of the power law lambda_IM(x) = k0 x^-k through (x1, rate1) and (x2, rate2):
    k = ln(rate1/rate2) / ln(x2/x1), k0 = rate1 x1^k.  IM unit for x, 1/yr for rates; k0 has unit
    (1/yr) IM^k.  ([Cornell et al. 2002] fit it locally to the hazard curve around the median.)"""
    vals = dict(x1=x1, rate1=rate1, x2=x2, rate2=rate2)
    bad = {k: v for k, v in vals.items() if not (np.isfinite(v) and v > 0)}
    if bad:
        raise ValueError(f"hazard points must be finite and > 0; got {bad}")
    if x1 == x2:
        raise ValueError(f"the two hazard points need distinct IM; got x1 = x2 = {x1}")
    k = math.log(rate1 / rate2) / math.log(x2 / x1)
    return rate1 * x1 ** k, k


def maf_power_law(fit: Fit, k0: float, k: float) -> float:
    """Mean annual frequency (1/yr) of exceeding the damage state under lambda_IM(x) = k0 x^-k:

        lambda_DS = integral_0^inf P(DS | x) |d lambda_IM(x)| = k0 theta^-k exp(k^2 beta^2 / 2)

    ([Cornell et al. 2002]: their closed form for a power-law hazard and lognormal capacity, written
    with the capacity in IM terms, i.e. demand-IM exponent b = 1).  Derivation: integrating by parts,
    lambda_DS = E[lambda_IM(C)] = k0 E[C^-k] for the capacity C ~ LN(ln theta, beta), and
    E[C^-k] = theta^-k exp(k^2 beta^2 / 2).
    k0 in (1/yr) IM^k, k > 0 (-)."""
    if not (np.isfinite(k0) and k0 > 0 and np.isfinite(k) and k > 0):
        raise ValueError(f"power-law hazard needs k0 > 0 and k > 0; got k0 = {k0}, k = {k}")
    return float(k0 * fit.theta ** (-k) * math.exp(0.5 * (k * fit.beta) ** 2))


def _phi_diff(ua, ub):
    """Phi(ub) - Phi(ua) for ub >= ua, without cancellation in the upper tail."""
    return np.where(ua > 0, ndtr(-ua) - ndtr(-ub), ndtr(ub) - ndtr(ua))


def maf_table(fit: Fit, im, rate, tails: str = "power") -> float:
    """Mean annual frequency (1/yr) of exceeding the damage state on a tabulated hazard curve.

    im: IM values (IM unit), strictly ascending, > 0; rate: annual exceedance rates (1/yr), > 0,
    non-increasing.  lambda_DS = -integral P(x) d lambda(x) ([Cornell et al. 2002]) with lambda
    interpolated linearly in (ln x, ln lambda): on each segment lambda = k0_i x^-k_i exactly, and the
    segment integral is evaluated in closed form (integration by parts, lognormal partial moment):

        -int_a^b P dlambda = P(a) lambda(a) - P(b) lambda(b)
                             + k0 theta^-k exp(k^2 beta^2/2) [Phi(u_b) - Phi(u_a)],
        u = ln(x/theta)/beta + k beta,

    so the only error is the interpolation of the table itself (no quadrature error).
    tails = "power" (default): the first and last segments' power laws are extrapolated to IM -> 0
    and IM -> inf (the last segment must fall, k > 0); tails = "truncate": the integral covers
    [im[0], im[-1]] only, a lower bound.
    """
    im = np.asarray(im, dtype=float)
    rate = np.asarray(rate, dtype=float)
    if im.ndim != 1 or rate.shape != im.shape or im.size < 2:
        raise ValueError(f"hazard table needs >= 2 points, im and rate 1-D of one length; shapes "
                         f"{im.shape}, {rate.shape}")
    for name, v in (("im", im), ("rate", rate)):
        bad = ~np.isfinite(v) | (v <= 0)
        if bad.any():
            raise ValueError(f"hazard table {name} must be finite and > 0; got {name} = {v[bad].tolist()}")
    i = np.flatnonzero(np.diff(im) <= 0)
    if i.size:
        raise ValueError(f"hazard table im must be strictly ascending; im[{i[0]}] = {im[i[0]]:g} >= "
                         f"im[{i[0] + 1}] = {im[i[0] + 1]:g}")
    i = np.flatnonzero(np.diff(rate) > 0)
    if i.size:
        raise ValueError(f"hazard table rate must be non-increasing; rate[{i[0]}] = {rate[i[0]]:g} < "
                         f"rate[{i[0] + 1}] = {rate[i[0] + 1]:g}")
    if tails not in ("power", "truncate"):
        raise ValueError(f"tails must be 'power' or 'truncate'; got tails = {tails!r}")
    lx, lr = np.log(im), np.log(rate)
    k = -(np.diff(lr) / np.diff(lx))                     # per segment
    lk0 = lr[:-1] + k * lx[:-1]                          # ln k0 per segment
    a, b = lx[:-1], lx[1:]
    lt, beta = math.log(fit.theta), fit.beta
    if tails == "power":
        if k[-1] <= 0:
            raise ValueError(f"tails='power' needs a falling last segment; rate[-2] = rate[-1] = "
                             f"{rate[-1]:g} would never decay (use tails='truncate')")
        k = np.concatenate([[k[0]], k, [k[-1]]])
        lk0 = np.concatenate([[lk0[0]], lk0, [lk0[-1]]])
        a = np.concatenate([[-np.inf], a, [lx[-1]]])
        b = np.concatenate([[lx[0]], b, [np.inf]])

    def p_lambda(lxe, ks, lk0s):                        # P(x) lambda(x); 0 at x -> 0 and x -> inf
        with np.errstate(invalid="ignore", over="ignore"):
            v = np.exp(log_ndtr((lxe - lt) / beta) + lk0s - ks * lxe)
        return np.where(np.isfinite(lxe), v, 0.0)

    with np.errstate(invalid="ignore"):
        ua = (a - lt) / beta + k * beta
        ub = (b - lt) / beta + k * beta
    ua = np.where(np.isneginf(a), -np.inf, ua)
    ub = np.where(np.isposinf(b), np.inf, ub)
    moment = np.exp(lk0 - k * lt + 0.5 * (k * beta) ** 2) * _phi_diff(ua, ub)
    seg = p_lambda(a, k, lk0) - p_lambda(b, k, lk0) + moment
    return float(np.sum(seg))


def maf_ratio(fit_with: Fit, fit_without: Fit, *, power_law=None, table=None, tails: str = "power") -> Risk:
    """The headline: MAF of exceeding the damage state with the damper over the MAF without, on one
    hazard, given as power_law = (k0, k) (`maf_power_law`) or table = (im, rate) (`maf_table`)."""
    if (power_law is None) == (table is None):
        raise ValueError("give exactly one hazard: power_law=(k0, k) or table=(im, rate)")
    if power_law is not None:
        w, wo = (maf_power_law(f, *power_law) for f in (fit_with, fit_without))
    else:
        w, wo = (maf_table(f, *table, tails=tails) for f in (fit_with, fit_without))
    return Risk(maf_with=w, maf_without=wo, ratio=w / wo)


# ----------------------------------------------------------------------------------------------
# plot

def plot_fragility(ax, fit: Fit, band: Band | None = None, label: str | None = None, data=None,
                   color=None):
    """Draw on matplotlib `ax`: the fitted curve, the 5-95 % bootstrap band shaded (if `band`), and
    markers for the observed fractions data = (im, fraction) (default: the stripes of `fit`; pass
    data=False for none).  The IM grid is band.levels, else log-spaced over the stripes.  Returns the
    curve's Line2D."""
    x = band.levels if band is not None else np.geomspace(fit.im.min() / 2.0, fit.im.max() * 2.0, 200)
    text = f"{label + ': ' if label else ''}θ = {fit.theta:.3g}, β = {fit.beta:.2f}"
    (line,) = ax.plot(x, fit.probability(x), color=color, label=text)
    color = line.get_color()
    if band is not None:
        ax.fill_between(band.levels, band.p05, band.p95, color=color, alpha=0.2, linewidth=0)
    if data is None:
        data = (fit.im, fit.fraction)
    if data is not False:
        ax.plot(np.asarray(data[0]), np.asarray(data[1]), "o", color=color, markersize=4)
    ax.set_ylim(-0.02, 1.02)
    ax.set_ylabel("P(DS | IM)")
    return line


@dataclass
class CapacityFit:
    """The collapse fragility fitted to the records' collapse intensities (IDA): a lognormal of
    median theta and dispersion beta by maximum likelihood, the records that never collapsed
    (censored: their capacity lies above the largest intensity run) counted through the
    survival function.  n: records, censored: how many of them did not collapse."""
    theta: float
    beta: float
    n: int
    censored: int

    def probability(self, x):
        x = np.asarray(x, dtype=float)
        with np.errstate(divide="ignore"):
            p = ndtr(np.log(x / self.theta) / self.beta)
        return float(p) if p.ndim == 0 else p


def fit_capacities(capacities, censored_at=()):
    """CapacityFit of the collapse intensities `capacities` (> 0) and the records that did not
    collapse up to the intensities `censored_at` (> 0).  Without censoring the MLE is closed:
    ln theta the mean of ln c, beta their standard deviation (ddof 0); with it, the censored
    likelihood sum ln phi((ln c - m)/b)/b + sum ln(1 - Phi((ln s - m)/b)) is maximised."""
    c = np.asarray(capacities, dtype=float)
    s = np.asarray(censored_at, dtype=float)
    if c.ndim != 1 or s.ndim != 1 or not np.all(np.isfinite(c)) or np.any(c <= 0) or np.any(s <= 0) \
            or not np.all(np.isfinite(s)):
        raise FragilityError("input", f"capacities = {c.tolist()!r}, censored_at = {s.tolist()!r} are not allowed: "
                                      "finite intensities > 0")
    if len(c) < 2 or np.ptp(np.log(c)) == 0.0:
        raise FragilityError("none" if len(c) == 0 else "single_level",
                             f"{len(c)} collapse intensities {c.tolist()!r} are not allowed: two distinct ones or "
                             "more are needed (the records that did not collapse only bound the fit)")
    lc = np.log(c)
    m, b = float(lc.mean()), float(lc.std())
    if len(s):
        ls = np.log(s)

        def nll(p):
            mu, lb = p
            beta = math.exp(lb)
            return -(np.sum(-0.5 * ((lc - mu) / beta) ** 2 - lb) + np.sum(log_ndtr(-(ls - mu) / beta)))

        best = optimize.minimize(nll, [m, math.log(b)], method="Nelder-Mead",
                                 options={"xatol": 1e-12, "fatol": 1e-14, "maxiter": 20000})
        m, b = float(best.x[0]), math.exp(float(best.x[1]))
    return CapacityFit(math.exp(m), b, len(c) + len(s), len(s))
