"""The materials (issue 25): restitution from the impact (Equation 18 as printed, Johnson's and
Thornton's laws), each impact's peak force, pressure and duration against an integrated contact
(solve_ivp), the energy balance with a velocity-dependent e in every particle model, constant-e runs
untouched, the impact record in the FMU and the run's log, and bad materials refused by name."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pidamper import FmuStepper, find_fmu, forcing
from pidamper.running.instance import FmuInstance
from pidamper_physics import Damper, Params
from pidamper_physics.impact import (JOHNSON, PRINTED, THORNTON, YIELD_ONSET, Contact, check_contact,
                                     hertz_loading_time)
from pidamper_physics.unit import DamperUnit

STEEL = dict(E1=200e9, nu1=0.3, E2=200e9, nu2=0.3)
RHO = 7850.0


def sphere(R, rho=RHO):
    return 4.0 / 3.0 * math.pi * R ** 3 * rho


def steel(law, S_y=300e6, R=0.01, e_max=0.95):
    return Contact(law, S_y, 200e9, 0.3, 200e9, 0.3, R, e_max)


# ---- the laws against their formulas ---------------------------------------------------------------

@pytest.mark.parametrize("v, expected", [(0.1, 0.7615693711982819), (0.5, 0.5092921335558410),
                                         (2.0, 0.3601239212423001)])
def test_equation_18_as_printed_by_hand(v, expected):
    """e = 3.1 S_y^(5/8) E*^(-1/2) v^(-1/4) rho^(-1/8), E* = E / (1 - nu^2), for a solid steel sphere
    (m* = its mass: the density 3 m* / (4 pi R^3) is steel's); expected by hand (a calculator)."""
    R = 0.01
    by_hand = 3.1 * 300e6 ** 0.625 * (200e9 / (1 - 0.09)) ** -0.5 * v ** -0.25 * RHO ** -0.125
    assert by_hand == pytest.approx(expected, rel=1e-14)
    assert steel(PRINTED, R=R).restitution(v, sphere(R), 0.2) == pytest.approx(expected, rel=1e-14)


def test_e_max_binds_at_low_speed():
    """Every material law exceeds (or reaches) 1 at low speed: e_max then binds, exactly."""
    R = 0.01
    for law in (PRINTED, JOHNSON, THORNTON):
        assert steel(law, R=R, e_max=0.9).restitution(1e-4, sphere(R), 0.2) == 0.9
    assert steel(PRINTED, R=R, e_max=0.9).restitution(0.5, sphere(R), 0.2) < 0.9  # and not above it


def test_johnson_in_his_density_form():
    """Johnson (1985, 11.5): e^2 = (3 pi^(5/4) 4^(3/4) / 10) (p_d/E*) (m v^2 / (2 p_d R^3))^(-1/4),
    for a solid sphere e = 1.7176 (p_d/E*)^(1/2) (rho v^2 / p_d)^(-1/8), p_d = 3 S_y, two-body E*."""
    R, S_y = 0.01, 300e6
    E = 1.0 / (2 * (1 - 0.09) / 200e9)
    p_d = 3.0 * S_y
    for v in (0.3, 1.0, 3.0):
        density_form = (3 * math.pi ** 1.25 * 4 ** 0.75 / 10) ** 0.5 * (2 * math.pi / 3) ** -0.125
        expected = density_form * math.sqrt(p_d / E) * (RHO * v * v / p_d) ** -0.125
        assert density_form == pytest.approx(1.7176, abs=1e-4)
        assert steel(JOHNSON, R=R).restitution(v, sphere(R), 0.2) == pytest.approx(expected, rel=1e-14)


def test_thornton_against_his_closed_form():
    """Thornton (1997): e = sqrt(6 sqrt(3) / 5) sqrt(1 - r^2/6) (r / (r + 2 sqrt(6/5 - r^2/5)))^(1/4),
    r = V_y / v, V_y = 1.56 (p_y^5 / (E*^4 rho))^(1/2): his formula, not the force law we integrate."""
    R = 0.01
    c = steel(THORNTON, R=R, e_max=1.0)
    p_y = YIELD_ONSET * 300e6
    V_y = 1.56 * math.sqrt(p_y ** 5 / (c.E ** 4 * RHO))
    assert c.yield_speed(sphere(R)) == pytest.approx(V_y, rel=2e-3)  # 1.56 is rounded
    V_y = c.yield_speed(sphere(R))
    for v in (1.0001 * V_y, 2 * V_y, 0.1, 1.0, 10.0):
        r = V_y / v
        expected = math.sqrt(6 * math.sqrt(3) / 5) * math.sqrt(1 - r * r / 6) * (
            r / (r + 2 * math.sqrt(6 / 5 - r * r / 5))) ** 0.25
        assert c.restitution(v, sphere(R), 0.2) == pytest.approx(expected, rel=1e-13)
    assert c.restitution(0.5 * V_y, sphere(R), 0.2) == 1.0  # elastic below the yield speed


def test_hertz_loading_time_against_quadrature():
    from scipy.integrate import quad
    for s in (0.0, 1e-3, 0.3, 0.75, 0.87, 0.9, 0.99, 1.0):
        ref = quad(lambda x: 1 / math.sqrt(1 - x ** 2.5), 0, s, limit=400, epsabs=1e-15, epsrel=1e-14)[0] if s < 1 \
            else 0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
        assert hertz_loading_time(s) == pytest.approx(ref, rel=1e-12, abs=1e-15)


# ---- the contact against an integrated force law ------------------------------------------------

def integrate(force, m, v):
    """(peak force, duration, rebound speed) of m d'' = -force(d, loading) from d = 0, d' = v, by
    solve_ivp (DOP853, rtol 1e-12) with events at the turn and at separation."""
    state = {"peak": 0.0}

    def loading(t, y):
        return [y[1], -force(y[0], True) / m]

    turn = lambda t, y: y[1]
    turn.terminal, turn.direction = True, -1
    T = 10.0 * (m * m / (0.01 * 1e22 * v)) ** 0.2 + 1.0
    one = solve_ivp(loading, (0, T), [0.0, v], method="DOP853", rtol=1e-12, atol=1e-30, events=turn)
    t1, d_max = one.t_events[0][0], one.y_events[0][0][0]
    state["peak"] = force(d_max, True)
    unload = force.unloading(d_max)

    def back(t, y):
        return [y[1], -unload(y[0]) / m]

    apart = lambda t, y: unload(y[0]) if y[0] > unload.rest else -1.0
    apart.terminal, apart.direction = True, -1
    two = solve_ivp(back, (0, T), [d_max, 0.0], method="DOP853", rtol=1e-12, atol=1e-30, events=apart)
    return state["peak"], t1 + two.t_events[0][0], -two.y_events[0][0][1]


class Hertz:
    """Hertz's force law (elastic: the unloading is the loading)."""

    def __init__(self, E, R):
        self.k = 4.0 / 3.0 * E * math.sqrt(R)

    def __call__(self, d, loading=True):
        return self.k * max(d, 0.0) ** 1.5

    def unloading(self, d_max):
        law = lambda d: self(d)
        law.rest = 0.0
        return law


class ThorntonLaw:
    """Thornton's (1997) force law: Hertz to first yield, F_y + pi p_y R (d - d_y) beyond, Hertz
    unloading from the flattened radius R_p (written out here from his paper)."""

    def __init__(self, E, R, p_y):
        self.E, self.R, self.p_y = E, R, p_y
        self.d_y = R * (math.pi * p_y / (2 * E)) ** 2
        self.F_y = math.pi ** 3 * R * R * p_y ** 3 / (6 * E * E)

    def __call__(self, d, loading=True):
        if d <= self.d_y:
            return 4.0 / 3.0 * self.E * math.sqrt(self.R) * max(d, 0.0) ** 1.5
        return self.F_y + math.pi * self.p_y * self.R * (d - self.d_y)

    def unloading(self, d_max):
        F = self(d_max)
        if d_max <= self.d_y:
            R_p, rest = self.R, 0.0
        else:
            R_p = 4 * self.E / (3 * F) * ((2 * F + self.F_y) / (2 * math.pi * self.p_y)) ** 1.5
            rest = d_max - (3 * F / (4 * self.E * math.sqrt(R_p))) ** (2 / 3)
        k = 4.0 / 3.0 * self.E * math.sqrt(R_p)
        law = lambda d: k * max(d - rest, 0.0) ** 1.5
        law.rest = rest
        return law


@pytest.mark.parametrize("v", [1e-3, 1e-2, 0.1, 0.3, 0.6])
def test_elastic_impact_against_integrated_hertz(v):
    """High-strength steel (S_y = 2 GPa) keeps these impacts elastic: peak force, duration and
    the peak pressure p0 = (6 F E*^2 / (pi^3 R^2))^(1/3) against solve_ivp to 1e-6."""
    R = 0.01
    c = steel(THORNTON, S_y=2e9, R=R)
    m = sphere(R) / 2  # two equal spheres' reduced mass: any m* will do
    force, pressure, duration, plastic, e = c.hit(v, m)
    assert not plastic and e == 1.0
    peak, time, rebound = integrate(Hertz(c.E, R), m, v)
    assert force == pytest.approx(peak, rel=1e-6)
    assert duration == pytest.approx(time, rel=1e-6)
    assert rebound == pytest.approx(v, rel=1e-6)
    assert pressure == pytest.approx((6 * force * c.E ** 2 / (math.pi ** 3 * R * R)) ** (1 / 3), rel=1e-12)
    assert pressure < YIELD_ONSET * 2e9
    assert duration == pytest.approx(2.868266 * (m * m / (R * c.E ** 2 * v)) ** 0.2, rel=1e-6)


@pytest.mark.parametrize("v", [0.01, 0.1, 0.5, 2.0])
def test_plastic_impact_against_its_integrated_force_law(v):
    """Mild steel (S_y = 300 MPa) yields: peak force, duration and the rebound (so e) of the
    elastic-plastic contact against its own force law integrated, to 1e-6; the pressure is held at
    the limit 1.6 S_y."""
    R = 0.01
    c = steel(THORNTON, R=R, e_max=1.0)
    m = sphere(R)
    force, pressure, duration, plastic, e = c.hit(v, m)
    assert plastic and pressure == YIELD_ONSET * 300e6
    peak, time, rebound = integrate(ThorntonLaw(c.E, R, YIELD_ONSET * 300e6), m, v)
    assert force == pytest.approx(peak, rel=1e-6)
    assert duration == pytest.approx(time, rel=1e-6)
    assert e == pytest.approx(rebound / v, rel=1e-6)


# ---- the models: energy balance, constant e untouched --------------------------------------------

MATERIAL = dict(restitution=PRINTED, S_y=300e6, R=0.0084, e_max=0.95, **STEEL)


def test_constant_e_with_materials_moves_as_without():
    """restitution = 0 with the materials given computes every impact's contact but moves the
    bodies exactly as the run without them (bit for bit), and so as before this issue."""
    runs = []
    for extra in ({}, dict(MATERIAL, restitution=0)):
        core = Damper(Params(mu=0.02, e=0.2, F0=0.0981, Omega=math.sqrt(9.81), phi=math.pi / 2, **extra), 0, 0, 0, 0)
        states = []
        for k in range(1, 2001):
            core.advance(0.01 * k)
            states.append((core.x, core.v, core.y, core.u, core.impacts, core.dissipated))
        runs.append((states, core))
    assert runs[0][0] == runs[1][0]
    assert runs[1][1].impacts > 50 and runs[1][1].contacts.force_peak > 0.0


@pytest.mark.parametrize("law", [PRINTED, JOHNSON, THORNTON])
def test_pendulum_fmu_energy_balance_with_the_law(fmu_path, law):
    """E(0) + work in - E(T) = impact losses + viscous, to 1e-12 of the work in, with e changing
    from impact to impact (the damped level: dashpots too)."""
    values = dict(MATERIAL, restitution=law, mu=0.02, F0=0.0981, Omega=math.sqrt(9.81), phi=math.pi / 2,
                  theta_dot_0=0.0, fidelity=1, zeta_s=0.01, zeta_p=0.02)
    with FmuStepper(fmu_path, values) as fmu:
        e0 = fmu.get("energy")
        es = set()
        for k in range(1, 3001):
            fmu.advance(0.01 * k)
            if fmu.get("impacts_in_step"):
                es.add(fmu.get("impact[1].e"))
        balance = e0 + fmu.get("work_in") - fmu.get("energy") - fmu.get("energy_dissipated") - fmu.get("energy_viscous")
        assert fmu.get("impacts") > 50 and len(es) > 20  # e depends on the impact
        assert abs(balance) <= 1e-12 * fmu.get("work_in")


def test_damped_building_energy_balance_with_the_law(fmu_dir):
    values = dict(MATERIAL, restitution=THORNTON, R=0.5, mu=0.05, FR=1.0, d=0.02, fidelity=1, zeta_s=0.02)
    signal = forcing.kanai_tajimi(8.0, pga=3.0, seed=2, dt=0.01)
    with FmuStepper(find_fmu(storeys=3), values, forcing=signal) as fmu:
        e0 = fmu.get("energy")
        for k in range(1, 801):
            fmu.advance(0.01 * k)
        balance = e0 + fmu.get("work_in") - fmu.get("energy") - fmu.get("energy_dissipated") - fmu.get("energy_viscous")
        assert fmu.get("impacts") > 10 and fmu.get("impacts_plastic") > 0
        assert abs(balance) <= 1e-12 * abs(fmu.get("work_in"))


def test_unit_energy_balance_with_the_law():
    """The unit on a structure of overwhelming mass (m* = m to 1e-12), impulse-aware, under a held
    a_s: 0.5 m r'^2 + 0.5 m w1^2 r^2 changes by -m a_s (r(T) - r(0)) minus the impacts' losses."""
    m, a_s = 10.0, 0.8
    unit = DamperUnit(m=m, M_s=m * 1e12, L1=0.5, d=0.02, impulse_aware=1, r_dot_0=0.6, **dict(MATERIAL, R=0.05))
    w2 = 9.81 / 0.5
    energy = lambda: 0.5 * m * (unit.rd ** 2 + w2 * unit.r ** 2)
    e0, r0, es = energy(), unit.r, set()
    for k in range(1, 4001):
        unit.advance(0.001 * k, a_s)
        if unit.impacts_in_step:
            es.add(unit.contacts.hit[0])
    balance = e0 - m * a_s * (unit.r - r0) - energy() - unit.dissipated
    assert unit.impacts > 20 and len(es) > 10
    assert abs(balance) <= 1e-11 * e0


# ---- the FMUs' record, the log, the warning and bad input -----------------------------------------

def test_fmu_records_each_impact_and_the_step_peaks(fmu_path):
    """impact[k].e is the printed law at that impact's v_rel_before (recomputed here by hand), the
    step's peaks are the largest of its impacts, impacts_plastic counts the plastic ones."""
    values = dict(MATERIAL, mu=0.02, F0=0.0981, Omega=math.sqrt(9.81), phi=math.pi / 2, theta_dot_0=0.0)
    m_star = 1.0 * 0.02 / 1.02
    rho = 3 * m_star / (4 * math.pi * 0.0084 ** 3)
    plastic = 0
    with FmuStepper(fmu_path, values) as fmu:
        for k in range(1, 1001):
            fmu.advance(0.01 * k)
            n = min(fmu.get("impacts_in_step"), 16)
            forces = []
            for j in range(1, n + 1):
                w = abs(fmu.get(f"impact[{j}].v_rel_before"))
                by_hand = 3.1 * 300e6 ** 0.625 * (200e9 / 0.91) ** -0.5 * w ** -0.25 * rho ** -0.125
                e = fmu.get(f"impact[{j}].e")
                after = fmu.get(f"impact[{j}].v_rel_after")
                if after != 0.0:  # 0: the plastic impact that ends a chatter
                    assert e == pytest.approx(min(0.95, by_hand), rel=1e-12)
                forces.append(fmu.get(f"impact[{j}].force_peak"))
                plastic += fmu.get(f"impact[{j}].plastic")
                assert fmu.get(f"impact[{j}].duration") > 0.0
            if fmu.get("impacts_in_step") <= 16:
                assert fmu.get("impact_force_peak") == max(forces, default=0.0)
            if fmu.get("impacts_in_step") == 0:
                assert fmu.get("contact_pressure_peak") == 0.0
        assert plastic > 0 and fmu.get("impacts_plastic") >= plastic


def test_logged_run_carries_the_contact(tmp_path, fmu_path):
    from pidamper.runlog.logged_run import run_logged
    from pidamper.runlog.mcap_log import read_run
    from pidamper.scenes.scene import load

    scene = load("steel-on-steel")
    run_logged(scene.start_values, scene.make_forcing(), stop_time=16.0, out_dir=tmp_path, name="steel", fmu=fmu_path)
    _, _, impacts, _ = read_run(tmp_path / "steel.mcap")
    assert len(impacts) > 20
    assert (impacts["force_peak"] > 0).all() and (impacts["duration"] > 0).all()
    assert set(impacts["plastic"].tolist()) <= {0, 1} and impacts["plastic"].sum() > 0
    bounced = impacts["v_rel_after"] != 0
    assert np.allclose(-impacts["v_rel_after"][bounced] / impacts["v_rel_before"][bounced], impacts["e"][bounced],
                       rtol=1e-9)


def test_long_contact_is_warned_once(fmu_path):
    """A soft contact (rubber-like moduli) lasting more than 5 % of the primary's period is warned
    about through the FMI logger, once."""
    said = []
    values = dict(restitution=0, R=0.001, E1=2e5, E2=2e5, S_y=1e9, mu=0.1, e=0.5)
    with FmuStepper(fmu_path, values, logger=lambda status, text: said.append(text)) as fmu:
        for k in range(1, 501):
            fmu.advance(0.01 * k)
        assert fmu.get("impacts") > 2
    warned = [t for t in said if "lasts" in t and "period" in t]
    assert len(warned) == 1, said


@pytest.mark.parametrize("name, value, words", [
    ("E1", 0.0, "E1 = 0.0 is not allowed"), ("E2", -1e9, "E2 = -1000000000.0 is not allowed"),
    ("S_y", 0.0, "S_y = 0.0 is not allowed"), ("nu1", 0.5, "nu1 = 0.5 is not allowed: a Poisson's ratio"),
    ("nu2", -1.0, "nu2 = -1.0 is not allowed"), ("e_max", 0.0, "e_max = 0.0 is not allowed"),
    ("e_max", 1.5, "e_max = 1.5 is not allowed"), ("R", -0.01, "R = -0.01 is not allowed"),
    ("restitution", 4, "restitution = 4 is not allowed")])
@pytest.mark.parametrize("model", ["pendulum", "building", "unit"])
def test_bad_materials_refused_at_initialization(fmu_dir, model, name, value, words):
    """Refused with fmi2Error at initialization, the message naming the value (in a child process,
    as every refusal test: a refused instance is not reused)."""
    from pidamper.running import isolated

    path = {"pendulum": fmu_dir / "PendulumImpactDamper.fmu", "building": find_fmu(storeys=1),
            "unit": fmu_dir / "PendulumImpactDamperUnit.fmu"}[model]
    values = {"restitution": 1, "R": 0.01, name: value}
    text = isolated.call("pidamper.benchmarks.fatal_checks:bad_values", str(path), values)
    assert text is not None and words in text and "status 3 (error)" in text, text


def test_a_material_law_needs_a_radius():
    with pytest.raises(ValueError, match=r"R = 0.0 is not allowed: the radius"):
        check_contact(restitution=PRINTED, R=0.0)
    assert check_contact(restitution=0, R=0.0) is None  # no contact model: the constant e alone


def test_contact_is_continuous_at_the_yield_speed_and_sane_far_from_it():
    """The elastic and elastic-plastic branches join at the yield speed (force, duration, e), and
    across 12 decades of speed and mass every answer is finite, e in (0, 1], the duration > 0."""
    for S_y, R in ((300e6, 0.01), (2e9, 0.05), (50e6, 1e-4)):
        c = steel(THORNTON, S_y=S_y, R=R, e_max=1.0)
        for m in (1e-3, 1.0, 1e4):
            V_y = c.yield_speed(m)
            below, above = c.hit(V_y * (1 - 1e-12), m), c.hit(V_y * (1 + 1e-12), m)
            assert not below[3] and above[3]
            for k in (0, 2, 4):
                assert above[k] == pytest.approx(below[k], rel=1e-9)
            for v in np.logspace(-8, 4, 25):
                force, pressure, duration, plastic, e = c.hit(v, m)
                assert all(math.isfinite(x) for x in (force, pressure, duration, e))
                assert force > 0 and duration > 0 and 0 < e <= 1 and pressure <= YIELD_ONSET * S_y * (1 + 1e-12)


def test_a_massless_particle_meets_its_stop_without_a_contact():
    """mu = 0 (no particle mass): no force, the laws' limit e_max, no division by zero."""
    core = Damper(Params(mu=0.0, **MATERIAL), 0, 0.5, 0, 0)
    core.advance(5.0)
    assert core.impacts > 0 and core.contacts.force_peak == 0.0 and core.contacts.hit[0] == 0.95


def test_unit_fmu_is_its_core_with_materials(fmu_dir):
    """PendulumImpactDamperUnit with Thornton's law: every step's F_s, J_s and the contact outputs
    equal the core's (the adapter adds nothing), the peaks are the step's."""
    values = dict(MATERIAL, restitution=THORNTON, R=0.05, r_dot_0=0.5, impulse_aware=1)
    core = DamperUnit(**values)
    seen = 0
    with FmuInstance(fmu_dir / "PendulumImpactDamperUnit.fmu", values) as fmu:
        for k in range(1, 3001):
            a_s = 2.0 * math.sin(6.0 * k * 1e-3)
            fmu.set("a_s", a_s)
            fmu.do_step((k - 1) * 1e-3, 1e-3)
            core.advance((k - 1) * 1e-3 + 1e-3, a_s)  # the end time the FMU computes
            assert fmu.get("F_s") == core.F_s and fmu.get("J_s") == core.J_s
            assert fmu.get("impact_force_peak") == core.contacts.force_peak
            assert fmu.get("impacts_plastic") == core.contacts.plastic
            seen += fmu.get("impacts_in_step") > 0
            if fmu.get("impacts_in_step") == 0:
                assert fmu.get("impact_force_peak") == 0.0
    assert seen > 3 and core.contacts.plastic > 3
