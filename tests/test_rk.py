"""pidamper_physics.rk (plain-Python DOP853) against scipy's DOP853, exact solutions and convergence rates."""
import math

import numpy as np
import pytest
from scipy.integrate import DOP853
from scipy.integrate._ivp.rk import rk_step
from scipy.special import ellipj

from pidamper_physics.rk import dop853_dense, dop853_step, poly_deriv_bound, poly_derivs, poly_eval

EPS = np.finfo(float).eps

# y' = M y + g(t): two damped, coupled oscillators (rotation + decay), one driven so that the nodes c_s matter.
M = ((0.0, 0.0, 1.0, 0.0), (0.0, 0.0, 0.0, 1.0), (-4.0, 1.0, -0.2, 0.0), (1.0, -9.0, 0.0, -0.1))
Y0 = [1.0, -0.5, 0.3, 2.0]


def linear(t, y):
    u = [sum(a * b for a, b in zip(row, y)) for row in M]
    u[2] += math.cos(2.0 * t)
    return u


def linear_np(t, y):  # the same arithmetic, for scipy
    return np.array(linear(t, list(y)))


def pendulum(t, y):
    return [y[1], -math.sin(y[0])]


def pendulum_exact(t, q0):
    """Exact pendulum q'' = -sin q, q(0) = q0, q'(0) = 0: sin(q/2) = k cd(t | k^2), k = sin(q0/2)."""
    k = math.sin(q0 / 2)
    m = k * k
    sn, cn, dn, _ = ellipj(t, m)
    cd = cn / dn
    return [2 * math.asin(k * cd), -2 * k * (1 - m) * sn / (dn * dn * math.sqrt(1 - m * cd * cd))]


def rotation(t, y):  # y' = i y for y = u + i v
    return [-y[1], y[0]]


def fixed_steps(rhs, y, T, n):
    h = T / n
    f = rhs(0.0, y)
    for i in range(n):
        y, f, _, _ = dop853_step(rhs, i * h, y, f, h, 1e-6, 1e-9)
    return y


@pytest.mark.parametrize("h", [0.05, 0.2, 0.5])  # h |M| up to 5: inside the stability region
def test_step_matches_scipy_rk_step(h):
    rtol, atol = 1e-6, 1e-9
    y_new, f_new, err, K = dop853_step(linear, 0.0, Y0, linear(0.0, Y0), h, rtol, atol)
    K_sp = np.empty((13, 4))
    y_sp, f_sp = rk_step(linear_np, 0.0, np.array(Y0), linear_np(0.0, Y0), h, DOP853.A, DOP853.B, DOP853.C, K_sp)
    scale = atol + np.maximum(np.abs(Y0), np.abs(y_sp)) * rtol
    err_sp = DOP853._estimate_error_norm(DOP853, K_sp, h, scale)  # uses only the class tables E3, E5

    # Stage sums cancel terms up to ~50x the result (A entries reach 43): summation order (numpy's dot vs
    # ours) gives stage differences of eps * h * sum_j |a_sj K_j|, K differences that times |M|.
    size = 50 * h * np.abs(K_sp).max()
    lipschitz = max(sum(abs(a) for a in row) for row in M)
    assert np.abs(np.array(y_new) - y_sp).max() <= 2 * EPS * (np.abs(y_sp).max() + size)
    assert np.abs(np.array(K) - K_sp).max() <= 2 * EPS * (np.abs(K_sp).max() + lipschitz * size)
    assert np.array_equal(f_new, K[12]) and np.abs(np.array(f_new) - f_sp).max() <= 1e-13 * np.abs(f_sp).max()
    # The error estimate E.K cancels to O(h^7) of the O(1) stages: its relative rounding is eps * cond.
    cond = max(np.max((np.abs(E) @ np.abs(K_sp)) / np.abs(E @ K_sp)) for E in (DOP853.E5, DOP853.E3))
    assert err == pytest.approx(err_sp, rel=8 * EPS * cond)


def test_dense_matches_scipy_dense_output():
    h = 0.3
    solver = DOP853(linear_np, 0.0, np.array(Y0), 10.0, first_step=h, rtol=1e-6, atol=1e-9)
    solver.step()
    assert solver.t == h  # accepted at the forced first step
    dense_sp = solver.dense_output()

    y_new, f_new, err, K = dop853_step(linear, 0.0, Y0, linear(0.0, Y0), h, 1e-6, 1e-9)
    assert err <= 1
    coeffs = dop853_dense(linear, 0.0, Y0, h, K, y_new)
    assert len(coeffs) == 4 and all(len(c) == 8 for c in coeffs)
    assert [c[0] for c in coeffs] == Y0
    for c, yi, zi, fi, gi in zip(coeffs, Y0, y_new, K[0], f_new):
        assert poly_eval(c, 1.0) == pytest.approx(zi, rel=4 * EPS, abs=4 * EPS * abs(yi))
        assert poly_derivs(c, 0.0, h)[1] == pytest.approx(fi, rel=4 * EPS)  # Hermite at both ends
        assert poly_derivs(c, 1.0, h)[1] == pytest.approx(gi, rel=1e-12)
    for theta in np.linspace(0.0, 1.0, 20):
        ours = np.array([poly_eval(c, theta) for c in coeffs])
        assert np.abs(ours - dense_sp(theta * h)).max() <= 1e-14 * np.abs(solver.y).max()


def test_linear_global_error_order_8():
    """y'' = -y over 20 s with fixed steps: the global error falls by 2^8 per halving of h."""
    errors = []
    for n in (25, 50, 100):
        y = fixed_steps(rotation, [1.0, 0.0], 20.0, n)
        errors.append(max(abs(y[0] - math.cos(20.0)), abs(y[1] - math.sin(20.0))))
    assert errors[-1] > 1e-12  # rounding does not dominate
    for coarse, fine in zip(errors, errors[1:]):
        assert 230 < coarse / fine < 285


def scipy_fixed_steps(fun, y, T, n):
    h = T / n
    y = np.array(y)
    f = fun(0.0, y)
    K = np.empty((13, len(y)))
    for i in range(n):
        y, f = rk_step(fun, i * h, y, f, h, DOP853.A, DOP853.B, DOP853.C, K)
    return y


def test_pendulum_global_error_order():
    """q'' = -sin q, q0 = 3 rad, over 20 s against the exact (elliptic) solution.  An order-8 method gains
    2^8 per halving asymptotically; DOP853's principal error constant is small, so over the h reachable in
    double precision the h^9 term still dominates and the gain is ~2^9.  scipy's own DOP853 steps give the
    same trajectory (to 1% of the error), so this is the method's behaviour.  An order-7 bug gives <= 2^7."""
    q0, T = 3.0, 20.0
    exact = pendulum_exact(T, q0)
    errors = []
    for n in (50, 100, 200):
        y = fixed_steps(pendulum, [q0, 0.0], T, n)
        errors.append(max(abs(a - b) for a, b in zip(y, exact)))
        y_sp = scipy_fixed_steps(lambda t, y: np.array([y[1], -np.sin(y[0])]), [q0, 0.0], T, n)
        assert np.abs(np.array(y) - y_sp).max() < 1e-2 * errors[-1]
    assert errors[-1] > 1e-11  # rounding does not dominate
    for coarse, fine in zip(errors, errors[1:]):
        assert 150 < coarse / fine < 700


def test_dense_output_error_order():
    """One step of the rotation y' = i y from (1, 0): max interpolation error over the step ~ h^8."""
    errors = []
    for h in (0.8, 0.4, 0.2):
        y0 = [1.0, 0.0]
        y_new, _, _, K = dop853_step(rotation, 0.0, y0, rotation(0.0, y0), h, 1e-6, 1e-9)
        cu, cv = dop853_dense(rotation, 0.0, y0, h, K, y_new)
        errors.append(max(max(abs(poly_eval(cu, th) - math.cos(th * h)), abs(poly_eval(cv, th) - math.sin(th * h)))
                          for th in np.linspace(0.0, 1.0, 201)))
    assert errors[-1] > 1e-13
    for coarse, fine in zip(errors, errors[1:]):
        assert coarse / fine > 100


def _polynomials():
    h = 0.5
    y0 = [3.0, 0.0]
    y_new, _, _, K = dop853_step(pendulum, 0.0, y0, pendulum(0.0, y0), h, 1e-6, 1e-9)
    polys = [(c, h) for c in dop853_dense(pendulum, 0.0, y0, h, K, y_new)]
    rng = np.random.default_rng(7)
    polys += [(tuple(rng.normal(size=8)), 0.7), (tuple(rng.normal(size=8) * 3.0 ** np.arange(8)), 2.0)]
    return polys


@pytest.mark.parametrize("c,h", _polynomials())
def test_poly_deriv_bound_bounds_samples(c, h):
    thetas = np.linspace(0.0, 1.0, 1001)
    assert poly_deriv_bound(c, 0, h) == pytest.approx(sum(abs(ck) for ck in c))
    for j in range(4):
        bound = poly_deriv_bound(c, j, h)
        sampled = max(abs(poly_derivs(c, th, h)[j]) for th in thetas)
        assert sampled <= bound * (1 + 1e-12)
    # on [0, 1] all-positive coefficients make the bound exact (at theta = 1)
    pos = tuple(abs(ck) for ck in c)
    for j in range(4):
        assert poly_derivs(pos, 1.0, h)[j] == pytest.approx(poly_deriv_bound(pos, j, h), rel=1e-13)


@pytest.mark.parametrize("c,h", _polynomials())
def test_poly_derivs_match_finite_differences(c, h):
    def p(t):  # the polynomial as a function of t, t0 = 0
        return poly_eval(c, t / h)

    for theta in (0.1, 0.37, 0.5, 0.83):
        t = theta * h
        got = poly_derivs(c, theta, h)
        assert got[0] == poly_eval(c, theta)
        # 4th-order central differences: truncation ~ d^4 max|p^(j+4)|, rounding ~ eps |p| / d^j
        d1, d2, d3 = 1e-3 * h, 3e-3 * h, 2e-2 * h
        fd = {1: (-p(t + 2 * d1) + 8 * p(t + d1) - 8 * p(t - d1) + p(t - 2 * d1)) / (12 * d1),
              2: (-p(t + 2 * d2) + 16 * p(t + d2) - 30 * p(t) + 16 * p(t - d2) - p(t - 2 * d2)) / (12 * d2 ** 2),
              3: (-p(t + 3 * d3) + 8 * p(t + 2 * d3) - 13 * p(t + d3) + 13 * p(t - d3) - 8 * p(t - 2 * d3)
                  + p(t - 3 * d3)) / (8 * d3 ** 3)}
        for j, d in ((1, d1), (2, d2), (3, d3)):
            tol = d ** 4 * poly_deriv_bound(c, j + 4, h) + 1e3 * EPS * poly_deriv_bound(c, 0, h) / d ** j
            assert abs(got[j] - fd[j]) <= tol
            assert tol < 1e-5 * poly_deriv_bound(c, j, h)  # the check has teeth
