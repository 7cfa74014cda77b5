"""Base excitation: a ground acceleration a_g acts on both bodies (x and y measured from the
ground), which the force input F alone cannot express."""
import math

import numpy as np
import pytest

from pidamper import forcing
from pidamper.oracles.cases import Case
from pidamper.oracles.odesolvers import IvpSolver
from pidamper_physics import Damper, Params

W2 = math.sqrt(9.81)


def test_constant_ground_acceleration_without_contact_is_the_closed_form():
    ag = 0.7
    p = Params(d=10.0, FR=3.0)
    dm = Damper(p)
    w1 = p.w1
    for k in range(1, 201):
        t = 0.05 * k
        dm.advance(t, 0.0, ag)
        assert dm.x == pytest.approx(-ag / W2 ** 2 * (1 - math.cos(W2 * t)), abs=1e-14)
        assert dm.y == pytest.approx(-ag / w1 ** 2 * (1 - math.cos(w1 * t)), abs=1e-14)
    assert dm.energy0 + dm.work_in - dm.energy == pytest.approx(dm.dissipated, abs=1e-14)


@pytest.mark.parametrize("e", [0.2, 0.8])
def test_base_excitation_with_impacts_and_sticking_against_an_independent_solver(e):
    """A free decay on a ground accelerating at 3 m/s2: DOP853 at rtol 1e-12 with the same
    impact, stick and release rules (pidamper.oracles.odesolvers) as the oracle."""
    case = Case("ground", "ground", e=e, theta_dot_0=0.5 * W2, periods=4, ground=3.0)
    ref = IvpSolver(case, "DOP853", 1e-12, logic=True, budget=120).solve(case.horizon)
    grid = np.linspace(0.0, case.horizon, 801)
    core = Damper(Params(e=e), theta_dot0=0.5 * W2)
    x = np.array([row[0] for row in core.dense(grid, 0.0, 3.0)])
    xr = ref.sample(grid)[0]
    assert core.impacts > 20 and len(ref.impacts) > 20
    assert np.max(np.abs(x - xr)) <= 1e-8 * np.max(np.abs(xr))


def test_ground_acceleration_is_not_a_force_on_the_primary():
    """F = -M a_g moves the primary alike only while nothing touches; the particle differs."""
    a = Damper(Params(), theta_dot0=1.0)
    b = Damper(Params(), theta_dot0=1.0)
    a.advance(0.05, 0.0, 2.0)
    b.advance(0.05, -2.0 * 1.0, 0.0)
    assert a.x == pytest.approx(b.x, abs=1e-15) and a.y != b.y


def test_accelerogram_through_the_fmu_equals_the_core(lockstep):
    quake = forcing.kanai_tajimi(duration=10.0, dt=0.01, pga=3.0, seed=4)
    assert quake.target == "a_g" and np.max(np.abs(quake.table[1])) == pytest.approx(3.0)
    assert lockstep({"mu": 0.05, "d": 0.05, "theta_dot_0": 0.0}, quake, 0.01, 1000) > 10


def test_kanai_tajimi_is_reproducible_and_band_limited():
    a = forcing.kanai_tajimi(duration=20.0, dt=0.005, seed=9)
    b = forcing.kanai_tajimi(duration=20.0, dt=0.005, seed=9)
    assert np.array_equal(a.table[1], b.table[1])
    spectrum = np.abs(np.fft.rfft(a.table[1])) ** 2
    freqs = np.fft.rfftfreq(len(a.table[1]), 0.005) * 2 * math.pi
    peak = freqs[np.argmax(np.convolve(spectrum, np.ones(50) / 50, mode="same"))]
    assert 5.0 < peak < 40.0  # the filter's ground frequency band (omega_g = 15.6 rad/s)
