"""Closed-form forced oscillator against independent oracles (50-digit mpmath, resonance formula)."""
import math
import random

import mpmath
import pytest

from pidamper_physics import Oscillator

mpmath.mp.dps = 50


def reference(w, x0, v0, c, a, om, psi, tau):
    """Textbook solution in 50-digit arithmetic: homogeneous + particular (Omega != w)."""
    w, x0, v0, c, a, om, psi, tau = (mpmath.mpf(q) for q in (w, x0, v0, c, a, om, psi, tau))
    xe = c / w ** 2
    P = a / (w ** 2 - om ** 2)
    A = x0 - xe - P * mpmath.sin(psi)
    B = (v0 - P * om * mpmath.cos(psi)) / w
    x = xe + A * mpmath.cos(w * tau) + B * mpmath.sin(w * tau) + P * mpmath.sin(om * tau + psi)
    v = w * (B * mpmath.cos(w * tau) - A * mpmath.sin(w * tau)) + P * om * mpmath.cos(om * tau + psi)
    return float(x), float(v)


def resonance(w, x0, v0, a, psi, tau):
    """Exact resonance Omega = w, independent formula (zero-IC responses to sin and cos)."""
    s, c = math.sin(w * tau), math.cos(w * tau)
    x = x0 * c + v0 / w * s + a * (math.sin(psi) * tau * s / (2 * w) + math.cos(psi) * (s - w * tau * c) / (2 * w * w))
    v = -x0 * w * s + v0 * c + a * (math.sin(psi) * (s / (2 * w) + tau * c / 2) + math.cos(psi) * tau * s / 2)
    return x, v


@pytest.mark.parametrize("ratio", [0.0, 0.3, 0.9, 0.999, 1.0 + 1e-6, 1.7, 5.0])
def test_off_resonance_matches_50_digit_reference(ratio):
    w, x0, v0, c, a, psi = 3.13, 0.07, -0.4, 0.3, 1.9, 0.8
    osc = Oscillator(w, x0, v0, c, a, ratio * w, psi)
    for tau in (0.0, 1e-7, 0.01, 0.5, 3.3, 17.0, 120.0):
        x, v = osc.state(tau)[:2]
        xr, vr = reference(w, x0, v0, c, a, ratio * w, psi, tau)
        scale = max(1.0, abs(xr))
        assert abs(x - xr) <= 1e-13 * scale * (1 + w * tau)
        assert abs(v - vr) <= 1e-13 * max(1.0, abs(vr)) * (1 + w * tau)


@pytest.mark.parametrize("psi", [0.0, math.pi / 2, 2.1])
def test_exact_resonance_secular_growth(psi):
    w, x0, v0, a = 1.0, 0.01, 0.02, 0.01
    osc = Oscillator(w, x0, v0, 0.0, a, w, psi)
    for tau in (0.0, 0.3, 6.0, 100.0, 628.3):
        x, v = osc.state(tau)[:2]
        xr, vr = resonance(w, x0, v0, a, psi, tau)
        assert abs(x - xr) <= 4e-16 * (1 + w * tau) * 10
        assert abs(v - vr) <= 4e-16 * (1 + w * tau) * 10


@pytest.mark.parametrize("detune", [1e-12, -1e-12, 1e-9, 1e-15])
def test_near_resonance_keeps_all_digits(detune):
    """Omega = w (1 + detune): the naive particular solution would lose |log10 detune| digits."""
    w, x0, v0, a, psi = 2.0, 0.0, 0.0, 0.5, 0.3
    om = w * (1 + detune)
    osc = Oscillator(w, x0, v0, 0.0, a, om, psi)
    for tau in (0.7, 31.4, 300.0):
        x, v = osc.state(tau)[:2]
        xr, vr = reference(w, x0, v0, 0.0, a, om, psi, tau)
        assert abs(x - xr) <= 1e-14 * max(abs(xr), 1e-3) * (1 + w * tau)
        assert abs(v - vr) <= 1e-14 * max(abs(vr), 1e-3) * (1 + w * tau)


def test_derivatives_satisfy_the_ode_and_bounds_hold():
    rng = random.Random(4)
    for _ in range(50):
        w = rng.uniform(0.2, 20)
        om = rng.choice([w, rng.uniform(0, 30)])
        osc = Oscillator(w, rng.uniform(-1, 1), rng.uniform(-5, 5), rng.uniform(-3, 3), rng.uniform(-2, 2),
                         om, rng.uniform(0, 6.3))
        T = rng.uniform(0.01, 20)
        bounds = osc.bounds(T)
        for k in range(40):
            tau = T * k / 39
            x, v, x2, x3, sf, cf = osc.derivs(tau)
            # second and third derivatives against central differences of the first and second
            h = 1e-5 / w
            up, down = osc.derivs(tau + h), osc.derivs(tau - h)
            assert x2 == pytest.approx((up[1] - down[1]) / (2 * h), abs=1e-6 * bounds[2] + 1e-12)
            assert x3 == pytest.approx((up[2] - down[2]) / (2 * h), abs=1e-6 * bounds[3] + 1e-12)
            for value, bound in ((x - osc.xe, bounds[0]), (v, bounds[1]), (x2, bounds[2]), (x3, bounds[3])):
                assert abs(value) <= bound * (1 + 1e-12) + 1e-300
