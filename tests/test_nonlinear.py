"""The nonlinear level against an independent integration (numpy mass-matrix form, solve_ivp
at rtol 1e-13, its own impact law), and the coupled level as its small-angle limit."""
import math

import numpy as np
import pytest

from pidamper.oracles.nonlinear_ref import NonlinearReference, sample
from pidamper_physics import Damper, Params

W2 = math.sqrt(9.81)
COUPLED, NONLINEAR = 2, 3


def start(p, theta_dot0, theta0=0.0):
    """Primary swinging, particle at rest (its wire turns back against the bob)."""
    return Damper(p, theta0, theta_dot0, 0.0, -theta_dot0 * p.L2 / p.L1)


@pytest.mark.parametrize("amplitude,zeta", [(0.3, 0.0), (1.2, 0.0), (1.2, 0.03)])
def test_large_swings_with_impacts_against_an_independent_integration(amplitude, zeta):
    """Swings up to 1.2 rad (a 9 % slower pendulum than the linear model's), impacts that stay
    resolvable (e = 0.7), forcing and a ground acceleration."""
    p = Params(e=0.7, FR=2.0, d=0.15, fidelity=NONLINEAR, zeta_s=zeta, zeta_p=2 * zeta, F0=0.2, Omega=0.9 * W2)
    force, ground = 0.1, 0.3
    dm = start(p, amplitude * W2)
    ref = NonlinearReference(p, fx=force / p.M - ground, fy=-ground)
    T = 3 * 2 * math.pi / W2
    pieces = ref.solve(0.0, 0.0, amplitude * W2, -amplitude * W2 * p.L2 / p.L1, T)
    grid = np.linspace(0.0, T, 301)
    rows = []
    for t in grid:
        dm.advance(t, force, ground)
        rows.append(dm.angles())
    rows = np.array(rows)
    r = sample(pieces, grid)
    assert dm.impacts == len(ref.impacts) >= 3
    assert np.max(np.abs(rows[:, 0] - r[:, 0])) <= 1e-8 * amplitude
    assert np.max(np.abs(rows[:, 2] - r[:, 1])) <= 1e-8 * amplitude * p.L2 / p.L1
    t_core = []
    dm2 = start(p, amplitude * W2)
    dm2.on_impact = lambda t, *rest: t_core.append(t)
    dm2.advance(T, force, ground)
    assert np.max(np.abs(np.array(t_core) - np.array([t for t, _ in ref.impacts]))) <= 1e-9


def test_energy_balance_measures_the_integration_error():
    """Applied work and dashpot losses are integrated beside the motion: the balance closes
    to the integrator's tolerance over a run with impacts, a ride on a stop and releases."""
    p = Params(e=0.05, FR=1.5, d=0.02, mu=0.3, fidelity=NONLINEAR, zeta_s=0.01, zeta_p=0.02, F0=0.05, Omega=W2)
    dm = start(p, 0.4 * W2)
    dm.advance(15.0, 0.02, 0.1)
    assert dm.impacts > 10 and dm.viscous > 0.01 * dm.energy0 and dm.dissipated > 0.01 * dm.energy0
    balance = dm.energy0 + dm.work_in - dm.viscous - dm.dissipated - dm.energy
    assert abs(balance) <= 1e-10 * dm.energy0


@pytest.mark.parametrize("e", [0.5, 0.05])
def test_coupled_is_the_small_angle_limit(e):
    """Scaling the start and the clearance by s, the nonlinear motion / s converges to the
    coupled level's (which does not depend on s) as s^2: sticking and releases included (e = 0.05)."""
    def theta(level, s):
        p = Params(e=e, FR=2.0, d=0.05 * s, fidelity=level, zeta_s=0.02, zeta_p=0.05, F0=0.02 * s, Omega=W2)
        dm = start(p, 0.3 * W2 * s)
        out = []
        for t in np.linspace(0.0, 6.0, 241):
            dm.advance(t)
            out.append(dm.angles()[0] / s)
        return np.array(out), dm.impacts

    lin, n_lin = theta(COUPLED, 1.0)
    errors = []
    for s in (0.1, 0.01):
        nl, n_nl = theta(NONLINEAR, s)
        if e > 0.1:  # chatter tails are counted to a resolution that differs between the levels
            assert n_nl == n_lin
        errors.append(np.max(np.abs(nl - lin)) / np.max(np.abs(lin)))
    assert errors[0] < 1e-2
    assert 50 < errors[0] / errors[1] < 200  # second order in the amplitude


def test_impact_law_conserves_momentum_and_restitution_in_angle_coordinates():
    p = Params(e=0.6, FR=2.0, d=0.1, mu=0.2, fidelity=NONLINEAR)
    from pidamper_physics.nonlinear import NonlinearModel
    m = NonlinearModel(p)
    th, ph = 0.4, math.asin(-0.1 / p.L1)
    (x, v, y, u), loss, before, after = m.collide(th, 1.3, ph, -2.0, 1, p.e)
    assert after == pytest.approx(-p.e * before, rel=1e-15)
    e0, e1 = m.energy(th, 1.3, ph, -2.0), m.energy(x, v, y, u)
    assert e0 - e1 == pytest.approx(loss, rel=1e-12)
    # horizontal momentum of the impulse pair: the impulse on the pair is internal, so
    # M xb' + m yp' changes only through the pendulum rods: the generalised momentum
    # conjugate to theta (whose virtual motion moves both bodies alike) is conserved
    def p_theta(dth, dph):
        c = math.cos(th - ph)
        return (p.M + p.m) * p.L2 ** 2 * dth + p.m * p.L2 * p.L1 * c * dph
    assert p_theta(v, u) == pytest.approx(p_theta(1.3, -2.0), rel=1e-14)
