"""The classical tuned mass damper (pidamper.tuning) against its closed forms: Den Hartog's fixed
points through the FMU by steady-state runs, Warburton's optimum against the variance of the
Lyapunov equation (scipy), the effective mass ratio against an independent eigen-solve."""
import math

import numpy as np
import pytest
from scipy.linalg import eigh, solve_continuous_lyapunov
from scipy.optimize import minimize

from pidamper import tuning
from pidamper.running import simulation

G = 9.81


def lyapunov_variance(mu, f, zeta):
    """Var(x) of an undamped unit primary (M = K = 1) with an absorber (mu, f, zeta of its own
    frequency) under unit white-noise ground acceleration: A P + P A^T + B B^T = 0."""
    wa = f
    mass, k_a, c = np.diag([1.0, mu]), mu * wa ** 2, 2.0 * zeta * mu * wa
    stiffness = np.array([[1.0 + k_a, -k_a], [-k_a, k_a]])
    damping = np.array([[c, -c], [-c, c]])
    inverse = np.linalg.inv(mass)
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-inverse @ stiffness, -inverse @ damping]])
    b = np.array([[0.0], [0.0], [-1.0], [-1.0]])
    return solve_continuous_lyapunov(a, -b @ b.T)[0, 0]


@pytest.mark.parametrize("mu", [0.01, 0.02, 0.05, 0.1])
def test_warburton_is_the_least_variance_of_the_lyapunov_equation(mu):
    found = minimize(lambda p: lyapunov_variance(mu, *p), x0=[1.0, 0.1], method="Nelder-Mead",
                     options={"xatol": 1e-11, "fatol": 1e-18, "maxiter": 20000})
    assert found.x == pytest.approx(tuning.warburton(mu), rel=1e-6)


@pytest.mark.parametrize("mu", [0.02, 0.05])
def test_den_hartog_fixed_points_through_the_fmu(mu):
    """A one-storey building (undamped) with the Den Hartog TMD, driven by F0 sin(Omega t) at each
    fixed point's frequency, Omega^2 / w_n^2 = (1 -+ sqrt(mu / (2 + mu))) / (1 + mu): after the
    transient its amplitude sqrt(x^2 + (v / Omega)^2) is sqrt(1 + 2 / mu) F0 / K."""
    mass, k, force = 2.0e5, 8.0e7, 1.0e4
    wn = math.sqrt(k / mass)
    values = {"storeys": 1, "floor[1].m": mass, "storey[1].k": k, "fidelity": 1, "zeta_s": 0.0}
    tmd = tuning.configuration(values, mu, "den-hartog")
    assert tmd["FR"] == pytest.approx(1 / (1 + mu), rel=1e-15)
    for sign in (-1, 1):
        omega = wn * math.sqrt((1 + sign * math.sqrt(mu / (2 + mu))) / (1 + mu))
        period = 2 * math.pi / omega
        result = simulation.run({**values, **tmd, "F0": force, "Omega": omega}, stop_time=300 * period,
                                output_interval=period / 16)
        length = G / wn ** 2  # the outputs' theta is x / L2, L2 = g / w_1^2
        x, v = result.data["theta"][-1] * length, result.data["theta_dot"][-1] * length
        assert math.hypot(x, v / omega) == pytest.approx(math.sqrt(1 + 2 / mu) * force / k, rel=1e-6)
        assert result.data["impacts"][-1] == 0


def test_the_fmu_tmd_is_the_two_degree_of_freedom_system_the_rules_assume():
    """A one-storey building with Warburton's TMD under a held random ground acceleration: the
    FMU's floor displacement at every communication point is the exact zero-order-hold solution of
    M x'' + K x - c (y' - x') - k_a (y - x) = -M a_g, m y'' + c (y' - x') + k_a (y - x) = -m a_g,
    k_a = m (f w_n)^2, c = 2 zeta m f w_n (scipy's expm), so Warburton's optimum of the Lyapunov
    equation above is the FMU's."""
    from scipy.linalg import expm

    from pidamper.forcing.base import Forcing

    mass, k, mu = 1.0e5, 4.0e6, 0.05
    wn = math.sqrt(k / mass)
    values = {"storeys": 1, "floor[1].m": mass, "storey[1].k": k, "fidelity": 1, "zeta_s": 0.0}
    tmd = tuning.configuration(values, mu, "warburton")
    m, wa = mu * mass, tmd["FR"] * wn
    k_a, c = m * wa ** 2, 2 * tmd["zeta_p"] * m * wa
    dt, n = 2 * math.pi / wn / 20, 200
    ground = np.random.default_rng(7).standard_normal(n + 1)
    times = dt * np.arange(n + 1)
    result = simulation.run({**values, **tmd}, Forcing("white", table=(times, ground), target="a_g"),
                            stop_time=n * dt, output_interval=dt)
    masses = np.diag([mass, m])
    stiffness = np.array([[k + k_a, -k_a], [-k_a, k_a]])
    damping = np.array([[c, -c], [-c, c]])
    inverse = np.linalg.inv(masses)
    a = np.zeros((5, 5))  # the state (x, y, x', y') and the held ground acceleration
    a[:2, 2:4] = np.eye(2)
    a[2:4, :2], a[2:4, 2:4], a[2:4, 4] = -inverse @ stiffness, -inverse @ damping, -1.0
    step = expm(a * dt)
    state, expected = np.zeros(5), [0.0]
    for g in ground[:-1]:
        state[4] = g
        state = step @ state
        expected.append(state[0])
    length = G / wn ** 2
    found = np.asarray(result.data["theta"]) * length
    assert np.max(np.abs(found - expected)) <= 1e-9 * np.max(np.abs(expected))


def test_the_effective_mass_ratio_is_the_first_modes():
    masses, stiffnesses = [3.0e5, 2.5e5, 2.0e5], [9e7, 7e7, 5e7]
    values = {"storeys": 3, **{f"floor[{i + 1}].m": m for i, m in enumerate(masses)},
              **{f"storey[{i + 1}].k": s for i, s in enumerate(stiffnesses)}}
    k = np.diag(np.add(stiffnesses, stiffnesses[1:] + [0.0])) - np.diag(stiffnesses[1:], 1) - np.diag(stiffnesses[1:], -1)
    _, shapes = eigh(k, np.diag(masses))
    phi = shapes[:, 0] / shapes[-1, 0]
    assert tuning.effective_mass_ratio(values, 0.02) == pytest.approx(0.02 * sum(masses) / np.dot(masses, phi ** 2),
                                                                      rel=1e-12)
    assert tuning.effective_mass_ratio({**values, "storeys": 0}, 0.02) == 0.02


@pytest.mark.parametrize("call, says", [
    (lambda: tuning.den_hartog(0.0), "mu = 0.0 is not allowed"),
    (lambda: tuning.warburton(2.5), "mu = 2.5 is not allowed: a mass ratio in \\(0, 2\\)"),
    (lambda: tuning.configuration({}, 0.02, "optimal"), "tmd = 'optimal' is not allowed: one of den-hartog, warburton"),
])
def test_bad_tuning_input_is_named(call, says):
    with pytest.raises(ValueError, match=says):
        call()


def test_a_study_names_a_tmd_and_gets_its_tuning(tmp_path):
    """[configurations.tmd] mu = 0.05, tmd = "warburton" runs Warburton's TMD of the building's
    effective mass ratio, its stops out of reach."""
    from pidamper.assessment import assess

    from test_loss_study import write_yielding_study

    path = write_yielding_study(tmp_path)
    path.write_text(path.read_text().replace("[suite]", '[configurations.tmd]\nmu = 0.05\ntmd = "warburton"\n\n[suite]'))
    study = assess.load(path)
    values = assess.start_values(study.building)
    f, zeta = tuning.warburton(tuning.effective_mass_ratio(values, 0.05))
    assert study.configurations["tmd"] == {"mu": 0.05, "FR": f, "zeta_p": zeta, "d": tuning.FAR}
    assert tuning.effective_mass_ratio(values, 0.05) > 0.05  # the first mode's mass is less than the building's


@pytest.mark.parametrize("lines, says", [
    ('mu = 0.05\ntmd = "best"', r"configurations\.tmd\.tmd = 'best' is not allowed: one of \"den-hartog\""),
    ('mu = 0.05\ntmd = "warburton"\nFR = 0.9', r"configurations\.tmd\.FR = 0\.9 is not allowed: not with tmd"),
    ('tmd = "warburton"', r"configurations\.tmd\.mu = \(missing\) is not allowed: a mass ratio > 0"),
    ('mu = 0.05\ntmd = "den-hartog"\nfidelity = "linear"', r"configurations\.tmd\.tmd = 'den-hartog' is not allowed: "
                                                           r"a fidelity of \"damped\""),
])
def test_a_bad_tmd_configuration_is_named(tmp_path, lines, says):
    from pidamper.assessment import assess
    from pidamper.assessment.study_file import StudyError

    from test_loss_study import write_yielding_study

    path = write_yielding_study(tmp_path)
    path.write_text(path.read_text().replace("[suite]", f"[configurations.tmd]\n{lines}\n\n[suite]"))
    with pytest.raises(StudyError, match=says):
        assess.load(path)
