"""The damped and coupled fidelity levels against their oracles: closed-form damped
oscillators, the matrix exponential of the coupled equations, the energy balance with
viscous losses integrated independently, and an independent event-driven solver."""
import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import expm

from pidamper.oracles.cases import Case
from pidamper.oracles.levels_ref import LevelIvpSolver
from pidamper_physics import Damper, ParameterError, Params

W2 = math.sqrt(9.81)
DAMPED, COUPLED = 1, 2


def at_rest_particle(p, theta_dot0):
    """A damper whose primary starts at theta_dot0 and whose particle is at rest (absolutely:
    at the coupled level its wire then turns at -theta_dot0 L2 / L1)."""
    alpha_dot0 = -theta_dot0 * p.L2 / p.L1 if p.fidelity == COUPLED else 0.0
    return Damper(p, theta_dot0=theta_dot0, alpha_dot0=alpha_dot0)


def test_damped_free_decay_without_contact_is_the_damped_oscillator():
    zs, zp, x0, v0, y0, u0 = 0.03, 0.1, 0.2, -0.4, 0.01, 0.3
    p = Params(d=10.0, FR=3.0, fidelity=DAMPED, zeta_s=zs, zeta_p=zp)
    dm = Damper(p, x0, v0, y0 / p.L1, u0 / p.L1)

    def decay(t, w, z, q0, dq0):
        wd = w * math.sqrt(1 - z * z)
        return math.exp(-z * w * t) * (q0 * math.cos(wd * t) + (dq0 + z * w * q0) / wd * math.sin(wd * t))

    for k in range(1, 301):
        t = 0.03 * k
        dm.advance(t)
        assert dm.x == pytest.approx(decay(t, W2, zs, x0, v0), abs=2e-15)
        assert dm.y == pytest.approx(decay(t, p.w1, zp, y0, u0), abs=2e-15)


@pytest.mark.parametrize("zeta", [0.05, 1e-3])
def test_damped_resonance_settles_on_the_steady_amplitude(zeta):
    """F0 sin(w2 t) on a primary with ratio zeta: steady amplitude F0/(M 2 zeta w2^2), lagging pi/2."""
    p = Params(d=100.0, F0=0.01, Omega=W2, fidelity=DAMPED, zeta_s=zeta, mu=0.0)
    dm = Damper(p, theta_dot0=0.0)
    t = 40.0 / (zeta * W2)  # e^-40: the transient is gone
    dm.advance(t)
    amp = 0.01 / (2 * zeta * W2 * W2)
    assert dm.x == pytest.approx(-amp * math.cos(W2 * t), abs=1e-11 * amp)
    assert dm.v == pytest.approx(amp * W2 * math.sin(W2 * t), abs=1e-11 * amp * W2)


def _expm_solution(p, z0, t, b, om, psi):
    """x, y, v, u of the coupled equations from the 6x6 exponential (harmonic load as two states)."""
    mu, w1, w2 = p.mu, p.w1, p.w2
    cs, cp = 2 * p.zeta_s * w2, 2 * p.zeta_p * w1
    A = np.zeros((7, 7))
    A[0, 2] = A[1, 3] = 1.0
    A[2, :4] = [-(1 + mu) * w2 ** 2 - mu * w1 ** 2, mu * w1 ** 2, -cs - mu * cp, mu * cp]
    A[3, :4] = [w1 ** 2, -w1 ** 2, cp, -cp]
    A[2, 4] = p.F0 / p.M  # times s = sin(om t + psi)
    A[4, 5], A[5, 4] = om, -om  # s' = om c, c' = -om s
    A[2, 6], A[3, 6] = b  # held loads, times the constant state 1
    s0 = np.array(list(z0) + [math.sin(psi), math.cos(psi), 1.0])
    return (expm(A * t) @ s0)[:4]


@pytest.mark.parametrize("zeta_s,zeta_p,om", [(0.0, 0.0, 2.0), (0.02, 0.05, 2.0), (0.0, 0.0, None)])
def test_coupled_without_contact_is_the_matrix_exponential(zeta_s, zeta_p, om):
    """None: forced exactly at the lower mode's frequency (undamped: secular growth)."""
    p = Params(d=10.0, FR=2.0, mu=0.2, fidelity=COUPLED, zeta_s=zeta_s, zeta_p=zeta_p, F0=0.3, Omega=1.0, phi=0.3)
    if om is None:
        from pidamper_physics.levels import ModalModel
        om = min(lam.imag for lam in ModalModel(p).free[0].lam)
    p = Params(d=10.0, FR=2.0, mu=0.2, fidelity=COUPLED, zeta_s=zeta_s, zeta_p=zeta_p, F0=0.3, Omega=om, phi=0.3)
    force, ground = 0.4, -0.2
    dm = Damper(p, 0.1, 0.2, -0.05, 0.3)
    z0 = (dm.x, dm.y, dm.v, dm.u)
    b = (force / p.M - ground, -ground)
    for t in np.linspace(0.5, 12.0, 24):
        dm.advance(t, force, ground)
        ref = _expm_solution(p, z0, t, b, om, p.phi)
        scale = np.max(np.abs(ref))
        assert np.max(np.abs(np.array([dm.x, dm.y, dm.v, dm.u]) - ref)) <= 1e-12 * scale


@pytest.mark.parametrize("level", [DAMPED, COUPLED])
def test_energy_balance_with_viscous_losses(level):
    """E(0) + integral of the applied power - integral of the dashpot power - impact losses = E(t),
    both integrals by adaptive quadrature along the closed-form pieces (independent of the
    core's bookkeeping, and false unless the pieces solve the equations)."""
    zs, zp, force, ground = 0.03, 0.08, 0.05, 0.4
    p = Params(FR=2.0, d=0.05, e=0.5, F0=0.04, Omega=W2, fidelity=level, zeta_s=zs, zeta_p=zp)
    dm = Damper(p, theta_dot0=0.3 * W2)
    cs, cp = 2 * zs * p.w2 * p.M, 2 * zp * p.w1 * p.m
    applied = viscous = 0.0

    def seen(seg, t0, t1):
        nonlocal applied, viscous
        if t1 <= t0:
            return

        def power(t):
            x, v, y, u = seg.positions(t - t0)
            f = force + p.F0 * math.sin(p.Omega * t + p.phi)
            rel = u - v if level == COUPLED else u
            return (f - p.M * ground) * v - p.m * ground * u, cs * v * v + cp * rel * rel

        applied += quad(lambda t: power(t)[0], t0, t1, epsabs=1e-15, epsrel=1e-13, limit=200)[0]
        viscous += quad(lambda t: power(t)[1], t0, t1, epsabs=1e-15, epsrel=1e-13, limit=200)[0]

    dm.advance(20.0, force, ground, observe=seen)
    assert dm.impacts > 8 and dm.dissipated > 0.01 * dm.energy0 and viscous > 0.05 * dm.energy0
    assert dm.energy0 + applied - viscous - dm.dissipated - dm.energy == pytest.approx(0.0, abs=1e-12 * dm.energy0)
    assert dm.viscous == pytest.approx(viscous, rel=1e-11)
    assert dm.work_in == pytest.approx(applied, rel=1e-11)


@pytest.mark.parametrize("level,zeta_s,zeta_p", [("damped", 0.02, 0.05), ("coupled", 0.02, 0.05), ("coupled", 0, 0)])
@pytest.mark.parametrize("e", [0.2, 0.8])
def test_levels_with_impacts_and_sticking_against_an_independent_solver(level, zeta_s, zeta_p, e):
    """Forced, on an accelerating ground, with impacts: DOP853 at rtol 1e-12 with the same rules."""
    case = Case("c", "c", e=e, FR=2.0, d=0.05, theta_dot_0=0.3 * W2, periods=4, F0=0.05, ground=0.5)
    ref = LevelIvpSolver(case, level, zeta_s, zeta_p, rtol=1e-12, budget=120).solve(case.horizon)
    p = Params(e=e, FR=2.0, d=0.05, F0=0.05, Omega=W2, fidelity=DAMPED if level == "damped" else COUPLED,
               zeta_s=zeta_s, zeta_p=zeta_p)
    dm = at_rest_particle(p, 0.3 * W2)
    grid = np.linspace(0.0, case.horizon, 801)
    rows = np.array(dm.dense(grid, 0.0, 0.5))
    xr = ref.sample(grid)
    assert dm.impacts == len(ref.impacts) > 10
    for k in (0, 2):
        assert np.max(np.abs(rows[:, k] - xr[k])) <= 1e-9 * np.max(np.abs(xr[k]))


def test_coupled_sticking_rides_the_stop_and_releases_like_the_reference():
    """Low restitution on a shaken primary: long rides on a stop (the release rule is the
    contact force of the coupled equations reaching zero)."""
    case = Case("c", "c", e=0.05, FR=1.5, d=0.02, mu=0.3, theta_dot_0=0.4 * W2, periods=3, F0=0.0)
    ref = LevelIvpSolver(case, "coupled", 0.01, 0.0, rtol=1e-12, budget=120).solve(case.horizon)
    p = Params(e=0.05, FR=1.5, d=0.02, mu=0.3, fidelity=COUPLED, zeta_s=0.01)
    dm = at_rest_particle(p, 0.4 * W2)
    grid = np.linspace(0.0, case.horizon, 601)
    rows = np.array(dm.dense(grid))
    xr = ref.sample(grid)
    assert np.max(np.abs(rows[:, 0] - xr[0])) <= 1e-9 * np.max(np.abs(xr[0]))
    gap = rows[:, 0] - rows[:, 2]
    riding = np.mean(np.abs(np.abs(gap) - p.d) < 1e-12)
    assert riding > 0.2


@pytest.mark.parametrize("kwargs,name", [
    (dict(zeta_s=0.02), "zeta_s"),
    (dict(zeta_p=0.02), "zeta_p"),
    (dict(fidelity=DAMPED, zeta_s=1.0), "zeta_s"),
    (dict(fidelity=DAMPED, zeta_p=-0.1), "zeta_p"),
    (dict(fidelity=4), "fidelity"),
    (dict(fidelity=DAMPED, contact_form=1), "contact_form"),
    (dict(fidelity=COUPLED, mu=0.0, FR=1.0), "mu, FR, zeta_s, zeta_p"),
])
def test_a_level_refuses_what_it_cannot_model(kwargs, name):
    with pytest.raises(ParameterError) as err:
        Damper(Params(**kwargs))
    assert err.value.name == name
    assert "it must" in str(err.value) or "needs" in str(err.value) or "level" in str(err.value)


@pytest.mark.parametrize("level", [DAMPED, COUPLED, 3])
def test_each_level_through_the_fmu_equals_the_core(lockstep, level):
    """The FMU's fidelity parameter selects the same physics as the core, bit for bit, under
    a sampled harmonic force and an accelerogram."""
    from pidamper import forcing
    values = {"fidelity": level, "zeta_s": 0.02, "zeta_p": 0.05, "FR": 2.0, "d": 0.05, "e": 0.5,
              "theta_dot_0": 0.3 * W2}
    assert lockstep(values, forcing.harmonic(0.05, W2, 0.0, True), 0.01, 400) > 3
    quake = forcing.kanai_tajimi(duration=4.0, dt=0.01, pga=2.0, seed=2)
    lockstep(values, quake, 0.01, 400)


def test_bench_levels_writes_its_report(fmu_path, tmp_path):
    """`pidamper bench --levels` at one amplitude: every level's FMU makes the core's impacts
    (measure refuses otherwise), the report holds a row per level with the costs, and the
    nonlinear level is its own reference."""
    from pidamper.benchmarks import levels

    rows = levels.measure(amplitudes=(0.1,), repeats=1, fmu=fmu_path)
    levels.write(rows, tmp_path, repeats=1)
    assert [r["level"] for r in rows] == list(levels.LEVELS)
    assert rows[-1]["theta_error"] == 0.0 and 1e-3 < rows[2]["theta_error"] < 1e-2  # coupled: 0.46 A^2
    assert all(r["fmpy_us_per_step"] > 0 and r["us_per_step"] > 0 for r in rows)
    report = (tmp_path / "README.md").read_text()
    assert "--levels --repeats 1" in report and report.count("| 0.1 |") == 4
    assert (tmp_path / "levels-error.png").stat().st_size > 0
