"""Issue 14, part 2: the damper unit and the shear building as FMUs of their own, co-simulated.

The building (physics and FMU) against scipy.linalg.expm of its state matrix; the unit's impact law
and the momentum it passes through F_s; the co-simulation's measured order against the exact
monolithic model; refusals; the SSP / OSP system files in libcosim.
"""
import math
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import replace

import fmpy
import numpy as np
import pytest
import scipy.linalg
from fmpy.validation import validate_fmu

from pidamper.running import isolated
from pidamper.cosim.components import component_instance
from pidamper.cosim import (BUILDING, UNIT, Scenario, component_fmus, error, export_system, gauss_seidel,
                            ivp_reference, monolithic_reference, physics_gauss_seidel)
from pidamper_physics.shear_motion import ShearMotion, make_building
from pidamper_physics.unit import DamperUnit

MASSES = [1.2e5, 1.0e5, 0.9e5, 0.7e5]
STIFFNESSES = [9e7, 8e7, 7e7, 5e7]


@pytest.fixture(scope="module")
def fmus(fmu_dir):
    """The component FMUs of the default scenario (ShearBuilding3.fmu, the unit) of the session's build."""
    return component_fmus(fmu_dir, Scenario().storeys)


# ---- the building: exact for held inputs (scipy.linalg.expm) ---------------------------------

def expm_run(masses, stiffnesses, zeta, steps):
    """Floor x, v, absolute a after each step (h, F, a_g, [(t in step, floor, J)]) by the matrix
    exponential of the augmented state matrix, impulses added to the velocity at their instants."""
    b = make_building(masses, stiffnesses, zeta)
    n = len(masses)
    M, K, C = np.diag(masses), np.array(b.K), np.array(b.C)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    z = np.zeros(2 * n)
    out = []
    for h, F, ag, kicks in steps:
        aug = np.zeros((2 * n + 1, 2 * n + 1))
        aug[:2 * n, :2 * n] = A
        aug[n:2 * n, 2 * n] = np.asarray(F) / np.asarray(masses) - ag
        t = 0.0
        for t_k, k, J in sorted(kicks) + [(h, None, 0.0)]:
            E = scipy.linalg.expm(aug * (t_k - t))
            z = E[:2 * n, :2 * n] @ z + E[:2 * n, 2 * n]
            if k is not None:
                z[n + k] += J / masses[k]
            t = t_k
        x, v = z[:n], z[n:]
        out.append((x.copy(), v.copy(), (np.asarray(F) - C @ v - K @ x) / np.asarray(masses)))
    return out


def held_inputs(n, count, seed, kicks=True):
    rng = np.random.default_rng(seed)
    steps = []
    for k in range(count):
        h = float(rng.choice([0.003, 0.01, 0.037]))
        F = list(rng.normal(0.0, 2e5, n))
        impulses = []
        if kicks and k % 3 == 1:
            impulses.append((float(rng.uniform(0, h)), int(rng.integers(n)), float(rng.normal(0, 3e3))))
        steps.append((h, F, float(rng.normal(0.0, 2.0)), impulses))
    return steps


@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_building_physics_equals_expm_for_held_inputs_and_impulses(zeta):
    steps = held_inputs(4, 40, seed=1)
    ref = expm_run(MASSES, STIFFNESSES, zeta, steps)
    motion = ShearMotion(make_building(MASSES, STIFFNESSES, zeta))
    t = 0.0
    scale_x = max(np.max(np.abs(x)) for x, _, _ in ref)
    scale_v = max(np.max(np.abs(v)) for _, v, _ in ref)
    for (h, F, ag, kicks), (x_ref, v_ref, a_ref) in zip(steps, ref):
        motion.advance(t + h, F, ag, [(t + tk, k, J) for tk, k, J in kicks])
        t += h
        x, v = motion.floors()
        assert np.max(np.abs(np.array(x) - x_ref)) <= 1e-12 * scale_x
        assert np.max(np.abs(np.array(v) - v_ref)) <= 1e-12 * scale_v
        a = motion.absolute_accelerations(F, x, v)
        assert np.max(np.abs(np.array(a) - a_ref)) <= 1e-10 * max(1.0, np.max(np.abs(a_ref)))


def test_building_fmu_equals_expm_and_declares_its_feedthrough(fmu_dir):
    path = component_fmus(storeys=4)[BUILDING]  # ShearBuilding4.fmu, built on demand: exactly four floors
    assert path.name == "ShearBuilding4.fmu" and validate_fmu(str(path)) == []
    md = fmpy.read_model_description(str(path))
    deps = {u.variable.name: [d.name for d in u.dependencies] for u in md.outputs}
    assert deps["floor[2].a"] == ["F[2]"] and deps["floor[2].x"] == [] and deps["floor[4].v"] == []
    assert not any("[5]" in v.name for v in md.modelVariables) and "storeys" not in deps
    steps = held_inputs(4, 24, seed=2)
    ref = expm_run(MASSES, STIFFNESSES, 0.03, steps)
    values = {"zeta_s": 0.03, **{f"floor[{k + 1}].m": m for k, m in enumerate(MASSES)},
              **{f"storey[{k + 1}].k": s for k, s in enumerate(STIFFNESSES)}}
    messages = []
    slave = component_instance(path, "b", values, messages)
    try:
        fmu = slave.fmu
        names = [f"floor[{k}].{q}" for q in "xva" for k in range(1, 5)]
        vr_out = slave.vr(*names)
        t = 0.0
        for (h, F, ag, kicks), (x_ref, v_ref, a_ref) in zip(steps, ref):
            inputs = {"a_g": ag, **{f"F[{k + 1}]": f for k, f in enumerate(F)},
                      **{f"J[{k + 1}]": 0.0 for k in range(4)}}
            for tk, k, J in kicks:
                inputs[f"J[{k + 1}]"], inputs[f"t_J[{k + 1}]"] = J, t + tk
            fmu.setReal(slave.vr(*inputs), list(inputs.values()))
            fmu.doStep(t, h)
            t += h
            got = dict(zip(names, fmu.getReal(vr_out)))
            for k in range(4):
                assert got[f"floor[{k + 1}].x"] == pytest.approx(x_ref[k], abs=1e-12 * np.max(np.abs(x_ref)))
                assert got[f"floor[{k + 1}].v"] == pytest.approx(v_ref[k], abs=1e-12 * np.max(np.abs(v_ref)))
                assert got[f"floor[{k + 1}].a"] == pytest.approx(a_ref[k], abs=1e-10 * np.max(np.abs(a_ref)))
        # feedthrough: a new F[2] shows in floor[2].a before any step, F[1] does not touch it
        before = fmu.getReal(slave.vr("floor[2].a", "floor[3].a"))
        fmu.setReal(slave.vr("F[2]"), [steps[-1][1][1] + 1e5])
        after = fmu.getReal(slave.vr("floor[2].a", "floor[3].a"))
        assert after[0] - before[0] == pytest.approx(1e5 / MASSES[1], rel=1e-9) and after[1] == before[1]
    finally:
        slave.close()
    assert messages == []


# ---- the unit: impact law, momentum through F_s ------------------------------------------------

UNIT_CASE = {"m": 6000.0, "M_s": 1e5, "L1": 0.25, "g": 9.81, "d": 0.02}


@pytest.mark.parametrize("mode,e", [(0, 0.5), (1, 0.5), (0, 0.03)], ids=["mean-force", "impulse-aware", "plastic"])
def test_unit_impact_law(fmus, mode, e):
    """One impact in one step from r = 0, r' = v0 under a_s = 0: J from the two-body law, the jump
    of the particle only (mode 0; plastic in the unit's frame when m > e M_s) or of the pair
    (mode 1), the two-body energy loss, and the closed-form flight after it; FMU and core alike."""
    m, M_s, d = UNIT_CASE["m"], UNIT_CASE["M_s"], UNIT_CASE["d"]
    w, v0, h = math.sqrt(9.81 / 0.25), 0.3, 0.1
    t_hit = math.asin(d * w / v0) / w
    approach = math.sqrt(v0 * v0 - (w * d) ** 2)
    mu = m * M_s / (m + M_s)
    two_body = mu * (1 + e) * approach, 0.5 * mu * (1 - e * e) * approach ** 2  # J, loss
    if mode == 1:
        (J, loss), after = two_body, -e * approach
    elif m < e * M_s:
        (J, loss), after = two_body, approach - two_body[0] / m
    else:  # the particle would still approach the stop in the unit's frame: plastic there
        J, after, loss = m * approach, 0.0, 0.5 * m * approach ** 2 * (M_s - m) / M_s
    tau = h - t_hit
    r_end = d * math.cos(w * tau) + after / w * math.sin(w * tau)
    rd_end = -d * w * math.sin(w * tau) + after * math.cos(w * tau)
    values = {**UNIT_CASE, "e": e, "impulse_aware": mode, "r_dot_0": v0}
    core = DamperUnit(**values)
    core.advance(h, 0.0)
    slave = component_instance(fmus[UNIT], "u", values, [])
    try:
        slave.fmu.doStep(0.0, h)
        names = ("F_s", "J_s", "t_J", "r", "r_dot", "energy_dissipated")
        got = dict(zip(names, slave.fmu.getReal(slave.vr(*names))))
        impacts = slave.fmu.getInteger(slave.vr("impacts"))[0]
    finally:
        slave.close()
    assert got == {"F_s": core.F_s, "J_s": core.J_s, "t_J": core.t_J, "r": core.r, "r_dot": core.rd,
                   "energy_dissipated": core.dissipated} and impacts == core.impacts == 1
    assert got["J_s"] == pytest.approx(J, rel=1e-12) and got["t_J"] == pytest.approx(t_hit, rel=1e-12)
    assert got["energy_dissipated"] == pytest.approx(loss, rel=1e-12)
    assert got["r"] == pytest.approx(r_end, abs=1e-12 * d) and got["r_dot"] == pytest.approx(rd_end, abs=1e-12 * v0)
    # F_s h: minus the particle's absolute momentum change (the frame's jump J/M_s in mode 1),
    # less the impulse that J_s carries in mode 1
    particle = m * (got["r_dot"] - v0 + (J / M_s if mode else 0.0))
    assert got["F_s"] * h == pytest.approx(-particle - (J if mode else 0.0), rel=1e-12)


def drive(seed, count=300):
    """a_s for a run with impacts on both stops, chatter, riding and release: held levels of 0.3 s
    (pressing the particle on a stop needs |a_s| > w1^2 d = 0.78 m/s2) plus noise."""
    rng = np.random.default_rng(seed)
    return [float(v) for v in np.repeat(rng.normal(0.0, 4.0, count // 30), 30) + rng.normal(0.0, 0.3, count)]


@pytest.mark.parametrize("mode", [0, 1], ids=["mean-force", "impulse-aware"])
def test_momentum_passed_through_F_s_equals_what_the_particle_lost(fmus, mode):
    values = {**UNIT_CASE, "e": 0.5, "zeta_p": 0.05, "impulse_aware": mode, "r_dot_0": 0.2}
    h, a_s = 0.01, drive(3)
    core = DamperUnit(**values)
    core.bound_work()
    slave = component_instance(fmus[UNIT], "u", values, [])
    passed = frame = impulses = 0.0
    riding = 0
    try:
        names = ("F_s", "J_s", "r", "r_dot")
        for k, a in enumerate(a_s):
            core.advance(k * h + h, a)  # the time the FMU reaches: current + step
            slave.fmu.setReal(slave.vr("a_s"), [a])
            slave.fmu.doStep(k * h, h)
            F_s, J_s, r, rd = slave.fmu.getReal(slave.vr(*names))
            assert (F_s, J_s, r, rd) == (core.F_s, core.J_s, core.r, core.rd)  # the adapter adds nothing
            passed += F_s * h + (J_s if mode else 0.0)
            impulses += J_s
            frame += a * h + (J_s / values["M_s"] if mode else 0.0)  # the attachment's velocity as the unit sees it
            riding += core.contact != 0
    finally:
        slave.close()
    assert core.impacts > 50 and riding > 50
    lost = -values["m"] * ((core.rd - values["r_dot_0"]) + frame)  # particle's absolute momentum lost
    assert passed == pytest.approx(lost, abs=1e-12 * values["m"] * sum(abs(a) for a in a_s) * h)
    assert impulses != 0.0


def test_F_s_is_the_exact_mean_force_of_the_step():
    """Without an impact in the step, F_s is the mean of m w1^2 r + c r' over it (Simpson on a twin
    sampled at h/64), or -m a_s while riding; with impacts it adds J_s / h (mean-force mode)."""
    values = {**UNIT_CASE, "e": 0.5, "zeta_p": 0.05, "r_dot_0": 0.2}
    m, w = values["m"], math.sqrt(9.81 / values["L1"])
    c = 2 * 0.05 * m * w
    h, sub = 0.01, 64
    unit, twin = DamperUnit(**values), DamperUnit(**values)
    checked = 0
    for k, a in enumerate(drive(4, 210)):
        samples = [m * w * w * twin.r + c * twin.rd]
        for i in range(1, sub + 1):
            twin.advance(k * h + i * h / sub, a)
            samples.append(m * w * w * twin.r + c * twin.rd)
        unit.advance((k + 1) * h, a)
        assert (unit.r, unit.rd) == pytest.approx((twin.r, twin.rd), abs=1e-13)
        if unit.impacts_in_step or unit.contact or twin.contact:
            continue
        simpson = (samples[0] + samples[-1] + 4 * sum(samples[1:-1:2]) + 2 * sum(samples[2:-1:2])) / (3 * sub)
        assert unit.F_s == pytest.approx(simpson, rel=1e-9, abs=1e-9 * m)
        checked += 1
    assert checked > 50


@pytest.mark.parametrize("mode,e", [(0, 0.99), (1, 0.9)], ids=["mean-force", "impulse-aware"])
def test_chatter_collapses_into_riding_and_the_particle_is_released(mode, e):
    """Pressed on stop +1 (a_s = -5 m/s2 < -w1^2 d): a finite chatter sequence, then the particle
    rides with F_s = -m a_s exactly; pressed the other way it leaves and ends riding stop -1."""
    unit = DamperUnit(**UNIT_CASE, e=e, impulse_aware=mode, r_dot_0=0.5)
    unit.bound_work()
    t, h = 0.0, 0.5
    while not unit.contact:
        assert t < 60.0, "chatter did not collapse"
        t += h
        unit.advance(t, -5.0)
        assert unit.pieces <= unit.max_pieces
    chatter = unit.impacts
    assert unit.contact == 1 and chatter > 10 and unit.r == UNIT_CASE["d"] and unit.rd == 0.0
    t += h
    unit.advance(t, -3.0)
    assert unit.contact == 1 and unit.impacts == chatter and unit.F_s == -UNIT_CASE["m"] * -3.0
    t += h
    unit.advance(t, 0.5)  # |a_s| < w1^2 d: released at the step's start, swings free
    assert unit.contact == 0 and abs(unit.r) < UNIT_CASE["d"]
    while not unit.contact:
        assert t < 120.0, "no riding on the other stop"
        t += h
        unit.advance(t, 5.0)
    assert unit.contact == -1 and unit.r == -UNIT_CASE["d"]


# ---- the co-simulation converges to the monolithic model ------------------------------------

def slope(hs, errors):
    return float(np.polyfit(np.log(hs), np.log(errors), 1)[0])


@pytest.fixture(scope="module")
def convergence():
    scn = Scenario()
    times = np.arange(1, 501) * 0.01
    ref = ivp_reference(scn, times)
    hs = [0.01 / 2 ** p for p in range(2, 6)]
    errors = {mode: [error(physics_gauss_seidel(scn, h, mode)[0], scn, 0.01, ref) for h in hs]
              for mode in ("mean", "impulse", "impulse-extrapolated")}
    return scn, times, ref, hs, errors


def test_independent_reference_agrees_with_the_monolithic_core(convergence):
    scn, times, ref, _, _ = convergence
    assert ivp_reference.impacts == 20
    mono = monolithic_reference(scn, times)
    assert np.max(np.abs(mono - ref)) <= 1e-9 * np.max(np.abs(ref))


def test_cosimulation_converges_first_order_and_second_with_extrapolated_impulse_aware_inputs(convergence):
    _, _, _, hs, errors = convergence
    assert 0.7 <= slope(hs, errors["mean"]) <= 1.3
    assert 0.85 <= slope(hs, errors["impulse"]) <= 1.15
    assert 1.8 <= slope(hs, errors["impulse-extrapolated"]) <= 2.2
    assert errors["impulse-extrapolated"][-1] < 0.05 * errors["impulse"][-1]
    assert max(errors["mean"]) < 1e-2  # the momentum arrives: no error of the order of the mass ratio


def test_fmu_master_is_the_physics_master(fmus):
    """fmpy's Gauss-Seidel on the two FMUs reproduces the physics-level master bit for bit (so the
    measured orders are the FMUs')."""
    scn = replace(Scenario(), stop_time=2.0)
    for mode in ("mean", "impulse", "impulse-extrapolated"):
        run = gauss_seidel(scn, 0.0025, mode, fmus)
        core, _, _ = physics_gauss_seidel(scn, 0.0025, mode)
        assert run.impacts == core.impacts > 5 and np.array_equal(run.x, core.x) and np.array_equal(run.r, core.r)
        assert run.notes == []


def test_mean_force_cannot_follow_a_particle_heavier_than_e_M_s_but_impulse_aware_can():
    """m > e M_s: the mean-force unit's plastic rule separates the pair as with restitution m/M_s
    (documented): its error stalls; the impulse-aware coupling converges."""
    scn = replace(Scenario(), e=0.03)  # m / M_s = 0.06
    times = np.arange(1, 501) * 0.01
    ref = monolithic_reference(scn, times)  # this case sticks: the independent reference cannot
    hs = [0.01 / 2 ** p for p in (2, 4, 6)]
    mean = [error(physics_gauss_seidel(scn, h, "mean")[0], scn, 0.01, ref) for h in hs]
    aware = [error(physics_gauss_seidel(scn, h, "impulse")[0], scn, 0.01, ref) for h in hs]
    assert mean[-1] > 0.5 * mean[0] > 5e-3
    assert 0.85 <= slope(hs, aware) <= 1.15 and aware[-1] < 0.05 * mean[-1]


# ---- refusals ---------------------------------------------------------------------------------

REFUSED = [
    (UNIT, {"m": 2e5}, {}, "m = 200000.0 is not allowed: it must be < M_s = 100000.0"),
    (UNIT, {"d": 0.0}, {}, "d = 0.0 is not allowed"),
    (UNIT, {"e": 1.5}, {}, "e = 1.5 is not allowed"),
    (UNIT, {"impulse_aware": 2}, {}, "impulse_aware = 2 is not allowed"),
    (UNIT, {"r_0": 0.2}, {}, "r_0 = 0.2 is not allowed"),
    (UNIT, {"zeta_p": 1.0}, {}, "zeta_p = 1.0 is not allowed"),
    (UNIT, {}, {"a_s": float("nan")}, "a_s = nan is not allowed: the input must be finite"),
    (BUILDING, {"floor[2].m": -1.0}, {}, "floor[2].m = -1.0 is not allowed"),
    (BUILDING, {"storey[3].k": float("inf")}, {}, "storey[3].k = inf is not allowed"),
    (BUILDING, {"storey[2].h": 0.0}, {}, "storey[2].h = 0.0 is not allowed"),
    (BUILDING, {"storey[3].h": float("nan")}, {}, "storey[3].h = nan is not allowed"),
    (BUILDING, {"zeta_s": 1.0}, {}, "zeta_s = 1.0 is not allowed"),
    (BUILDING, {}, {"F[1]": float("inf")}, "F[1] = inf is not allowed: the input must be finite"),
    (BUILDING, {}, {"t_J[2]": float("nan")}, "t_J[2] = nan is not allowed"),
]


def test_bad_values_are_refused_naming_the_value(fmus):
    cases = [(str(fmus[model]), values, inputs) for model, values, inputs, _ in REFUSED]
    texts = isolated.call("pidamper.cosim.refusals:refusals", cases)
    for (model, values, inputs, expected), text in zip(REFUSED, texts):
        assert text is not None, f"{model}: {values or inputs} was accepted"
        assert expected in text and "status 3" in text, (model, values, inputs, text)
    # and the defaults are accepted
    assert isolated.call("pidamper.cosim.refusals:refusals", [(str(fmus[m]), {}, {}) for m in (UNIT, BUILDING)]) == [None, None]


# ---- system files ------------------------------------------------------------------------------

def test_ssp_and_osp_files_describe_the_coupled_system_and_run_in_libcosim(fmus, tmp_path):
    scn = Scenario()
    paths = export_system(tmp_path, scn, fmus)
    assert sorted(p.name for p in paths) == ["DamperOnBuilding-impulse.ssp", "DamperOnBuilding.ssp",
                                             "OspSystemStructure-impulse.xml", "OspSystemStructure.xml"]
    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription"}
    with zipfile.ZipFile(tmp_path / "DamperOnBuilding-impulse.ssp") as z:
        assert {"resources/ShearBuilding3.fmu", "resources/PendulumImpactDamperUnit.fmu"} <= set(z.namelist())
        root = ET.fromstring(z.read("SystemStructure.ssd"))
    links = {(c.get("startElement"), c.get("startConnector"), c.get("endElement"), c.get("endConnector"))
             for c in root.iterfind(".//ssd:Connection", ns)}
    assert links == {("building", "floor[3].a", "unit", "a_s"), ("unit", "F_s", "building", "F[3]"),
                     ("unit", "J_s", "building", "J[3]"), ("unit", "t_J", "building", "t_J[3]")}
    from libcosimpy.CosimExecution import CosimExecution  # a test dependency (pyproject): no skip
    from libcosimpy.CosimObserver import CosimObserver

    ex = CosimExecution.from_ssp_file(str(tmp_path / "DamperOnBuilding-impulse.ssp"), step_size=1_000_000)
    unit = ex.slave_index_from_instance_name("unit")
    vr = {v.name.decode(): v.reference for v in ex.slave_variables(unit)}
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer=observer)
    assert ex.step(10)
    assert observer.last_real_values(unit, [vr["m"], vr["L1"]]) == pytest.approx([scn.m, scn.L1], rel=1e-15)
    assert observer.last_integer_values(unit, [vr["impulse_aware"]]) == [1]


def test_fmu_states_restore_both_components(fmus):
    scn = replace(Scenario(), stop_time=1.0)
    messages = []
    b = component_instance(fmus[BUILDING], "b", scn.building_values(), messages)
    u = component_instance(fmus[UNIT], "u", scn.unit_values(True), messages)
    try:
        def step(k, h=0.005):
            u.fmu.setReal(u.vr("a_s"), b.fmu.getReal(b.vr("floor[3].a")))
            u.fmu.doStep(k * h, h)
            F_s, J_s, t_J = u.fmu.getReal(u.vr("F_s", "J_s", "t_J"))
            b.fmu.setReal(b.vr("F[3]", "J[3]", "t_J[3]", "a_g"), [F_s, J_s, t_J, scn.ground(k * h, 0.005)])
            b.fmu.doStep(k * h, h)
            return b.fmu.getReal(b.vr("floor[3].x", "floor[3].v")) + u.fmu.getReal(u.vr("r", "r_dot"))

        for k in range(40):
            step(k)
        saved = [bytes(s.fmu.serializeFMUstate(s.fmu.getFMUstate())) for s in (b, u)]
        first = [step(k) for k in range(40, 120)]
        for s, blob in zip((b, u), saved):
            s.fmu.setFMUstate(s.fmu.deSerializeFMUstate(blob))
        assert [step(k) for k in range(40, 120)] == first
        assert u.fmu.getInteger(u.vr("impacts"))[0] > 0
    finally:
        u.close()
        b.close()
