"""The demands of an assessment run (assessment.demands): residual drifts after the free-vibration
tail against the storeys' own zero-force drifts, peaks against the sampled record, a collapsed run,
and pelicun's column names."""
import math

import numpy as np
import pytest

from pidamper.assessment import assess, demands
from pidamper.forcing import Forcing, ground_motion
from pidamper.running.simulation import run

BUILDING = {"storeys": 3, "floor_m": 1.0e5, "storey_k": 8.0e7, "zeta_s": 0.02, "fidelity": "damped",
            "storey_height": 3.0, "storey[1].Fy": 6.0e5, "storey[2].Fy": 5.0e5, "storey[3].Fy": 3.0e5, "mu": 0.0,
            "d": 100.0}
SUITE = {"generator": "clough-penzien", "count": 1, "seed": 1, "duration": 20.0, "dt": 0.01, "omega_g": 15.6,
         "zeta_g": 0.6, "omega_f": 1.5, "zeta_f": 0.6, "pga": 1.0,
         "envelope": {"kind": "jennings", "t1": 2.0, "t2": 10.0, "c": 0.5}}


@pytest.fixture(scope="module")
def record():
    return ground_motion.suite(SUITE)[0]


def period(values):
    from pidamper_physics import Params
    return 2.0 * math.pi / Params.from_variables({**values, "mu": 0.0}).w2


def test_residual_drift_is_the_storeys_zero_force_drift_once_settled(record):
    """Without P-Delta a building at rest has every storey force zero, so each storey's drift is
    its plastic (zero-force) drift, which the FMU reports.  After the tail, the residual drift ratio
    agrees with it to 1e-3 of the peak drift ratio (measured: 2.7e-4), at two intensities."""
    values = assess.start_values(BUILDING)
    for scale in (3.0, 8.0):
        times, ground = demands.with_tail(scale * record.accel, record.dt, period(values))
        result = run(values, Forcing("record", {}, table=(times, ground), target="a_g"),
                     stop_time=round(times[-1] / 0.01) * 0.01, output_interval=0.01)
        found = demands.demands_of(result.data, 3, [3.0] * 3, 0.0, period(values), 0.01, False)
        for k in (1, 2, 3):
            plastic = abs(result.data[f"storey[{k}].plastic_drift"][-1]) / 3.0
            assert plastic > 0 and abs(found[f"RID-{k}"] - plastic) <= 1e-3 * found[f"PID-{k}"]


def test_run_demands_peaks_bound_the_samples_and_the_ground_is_floor_zero(record):
    values = assess.start_values({**BUILDING, "mu": 0.05, "FR": 0.95, "d": 0.02, "e": 0.5})
    found = demands.run_demands(values, 3.0 * record.accel, record.dt, period(values))
    assert found["collapsed"] == 0 and found["PFA-0"] == 3.0 * np.abs(record.accel).max()
    times, ground = demands.with_tail(3.0 * record.accel, record.dt, period(values))
    assert found["t_end"] == pytest.approx(times[-1], abs=1e-9)
    result = run(values, Forcing("record", {}, table=(times, ground), target="a_g"), stop_time=found["t_end"],
                 output_interval=record.dt)
    for k in (1, 2, 3):  # the located maxima are at least the sampled ones, and close to them
        sampled = np.abs(result.data[f"storey[{k}].drift"]).max() / 3.0
        assert sampled <= found[f"PID-{k}"] <= sampled * 1.01
        assert np.abs(result.data[f"floor[{k}].a"]).max() <= found[f"PFA-{k}"] * (1 + 1e-12)
    assert found["impacts"] > 0 and found["impacts_unrecorded"] == 0 and 0 < found["v_impact_max"] < 5.0
    assert found["stroke"] <= 0.02 + 1e-12


def test_a_run_that_collapses_stops_with_its_demands_there(record):
    values = assess.start_values({**BUILDING, "p_delta": 1})
    found = demands.run_demands(values, 15.0 * record.accel, record.dt, period(values))
    assert found["collapsed"] == 1 and found["t_end"] < record.dt * record.accel.size
    assert max(found[f"PID-{k}"] for k in (1, 2, 3)) == pytest.approx(0.10, rel=1e-9)
    assert all(math.isnan(found[f"RID-{k}"]) for k in (1, 2, 3))


def through_simulate_fmu(values, accel, dt, period, h):
    """The demands as fmpy.simulate_fmu's full run table gives them (pidamper.run records every output
    at every communication point, stops after the collapse; demands_of reads the table)."""
    times, ground = demands.with_tail(accel, dt, period)
    slots = [f"impact[{k}].v_rel_before" for k in range(1, demands.SLOTS + 1)] + ["impacts_in_step",
                                                                               "impacts_unrecorded"]
    floor, contact = demands.damper_floor(values)
    result = run(values, Forcing("record", {}, table=(times, ground), target="a_g"),
                 stop_time=int(round(times[-1] / h)) * h, output_interval=h,
                 extra_outputs=slots + ["impact_force_peak"] * contact)
    return demands.demands_of(result.data, values["storeys"], [3.0] * 3, float(np.abs(accel).max()), period, h,
                              "collapsed" in result.meta, floor)


#: stops with rubber-like buffers: the contact law gives each impact's force (impact.Contact)
BUFFERS = {"mu": 0.05, "FR": 0.95, "d": 0.02, "e": 0.5, "R": 0.2, "E2": 5.0e7, "nu2": 0.45}


@pytest.mark.parametrize("case, scale, step", [("damper", 3.0, None), ("damper", 3.0, 0.004),
                                               ("collapse", 15.0, None), ("buffers", 3.0, None)])
def test_run_demands_reads_what_simulate_fmu_records(record, case, scale, step):
    """run_demands steps the FMU itself and reads a few outputs: every demand equals, to the last bit,
    the one read off fmpy.simulate_fmu's table of every output (a damper with impacts, a step that is
    not the record's interval, a run that collapses and stops)."""
    extra = {"damper": {"mu": 0.05, "FR": 0.95, "d": 0.02, "e": 0.5}, "collapse": {"p_delta": 1},
             "buffers": BUFFERS}[case]
    values = {**assess.start_values({**BUILDING, **extra}), **{f"storey[{k}].h": 3.0 for k in (1, 2, 3)}}
    found = demands.run_demands(values, scale * record.accel, record.dt, period(values), step)
    expected = through_simulate_fmu(values, scale * record.accel, record.dt, period(values), step or record.dt)
    assert set(found) == set(expected)
    same = lambda a, b: a == b or (math.isnan(a) and math.isnan(b))  # noqa: E731
    assert all(same(found[k], expected[k]) for k in found), {k: (found[k], expected[k]) for k in found
                                                              if not same(found[k], expected[k])}
    assert found["collapsed"] == (case == "collapse") and (found["impacts"] > 0) == (case != "collapse")
    assert (found["impact_force_max"] > 0) == (case == "buffers")


def test_the_damper_floor_takes_the_largest_contact_force_over_its_mass(record):
    """With the stops' materials given, impact_force_max is Hertz's peak force of the fastest impact
    (closed form, Johnson 1985 4.2 and 11.4: delta = (15 m* w^2 / (16 E* R^1/2))^(2/5), F = 4/3 E*
    R^1/2 delta^3/2, with the two-body reduced mass m* = m M / (m + M)) to 1e-12, and only the
    damper's floor carries it over its mass on top of the same run's acceleration without it."""
    values = assess.start_values({**BUILDING, **BUFFERS})
    found = demands.run_demands(values, 3.0 * record.accel, record.dt, period(values))
    plain = demands.run_demands(assess.start_values({**BUILDING, **BUFFERS, "R": 0.0}), 3.0 * record.accel,
                                record.dt, period(values))
    from pidamper_physics import Params
    p = Params.from_variables(values)
    reduced = p.m * p.M / (p.m + p.M)
    e_star = 1.0 / ((1 - 0.3 ** 2) / 200e9 + (1 - 0.45 ** 2) / 5.0e7)
    w = found["v_impact_max"]
    delta = (15.0 * reduced * w * w / (16.0 * e_star * math.sqrt(0.2))) ** 0.4
    assert found["impact_force_max"] == pytest.approx(4.0 / 3.0 * e_star * math.sqrt(0.2) * delta ** 1.5, rel=1e-12)
    assert math.isnan(plain["impact_force_max"]) and found["impact_accel"] == found["impact_force_max"] / p.M
    assert found["PFA-3"] == plain["PFA-3"] + found["impact_accel"]
    assert all(found[f"PFA-{k}"] == plain[f"PFA-{k}"] for k in (0, 1, 2))


def test_pelicun_names():
    row = {name: float(j) for j, name in enumerate(demands.names(2))}
    assert list(demands.pelicun_columns(row, 2, event=3)) == [
        "3-PID-1-1", "3-PID-2-1", "3-RID-1-1", "3-RID-2-1", "3-PFA-0-1", "3-PFA-1-1", "3-PFA-2-1", "3-PFV-1-1",
        "3-PFV-2-1"]


def test_the_page_states_the_damper_as_built_and_its_contacts():
    """The page's damper section: the pendulum length L1 = g / (FR w_1)^2 with w_1 the building's first
    natural frequency (numpy's eigenvalues of M^-1 K, an independent solve), the swing d / L1 at the
    stops, and at a stripe the fastest impact's Hertz contact (duration 2.943 delta_m / w, the
    elastic closed form, Johnson 1985, 4.2 and 11.4) as a share of T1."""
    from types import SimpleNamespace

    from pidamper.assessment import page

    m, k, fr = 1.0e5, 8.0e7, 0.95
    stiffness = np.array([[2 * k, -k, 0.0], [-k, 2 * k, -k], [0.0, -k, k]]) / m
    w1 = math.sqrt(np.linalg.eigvalsh(stiffness).min())
    length = 9.81 / (fr * w1) ** 2
    building = {k_: v for k_, v in BUILDING.items() if k_ not in ("mu", "d")}

    def studied(configurations):
        return SimpleNamespace(configurations=configurations, levels=[0.3],
                               start_values=lambda c: assess.start_values({**building, **configurations[c]}))

    study = studied({"bare": {"mu": 0.0, "d": 100.0}, "damper": BUFFERS})
    row = {"configuration": "damper", "level": 0.3, "stroke": 0.02, "impacts": 4, "v_impact_max": 1.5,
           "impact_force_max": 2.0e5, "impact_accel": 2.0, "PFA-3": 8.0}
    text = "\n".join(page.damper_lines(study, [row]))
    assert f"L1 = g / w1^2 = {length:.3g} m" in text and f"d / L1 = {0.02 / length:.3g} rad" in text
    mass, floor = 0.05 * 3 * m, m
    reduced = mass * floor / (mass + floor)
    e_star = 1.0 / ((1 - 0.3 ** 2) / 200e9 + (1 - 0.45 ** 2) / 5.0e7)
    delta = (15.0 * reduced * 1.5 ** 2 / (16.0 * e_star * math.sqrt(0.2))) ** 0.4
    duration = 2.0 * 1.4716 * delta / 1.5  # Hertz: 2 x 1.4716 delta_m / w
    share = 100 * duration * w1 / (2 * math.pi)
    assert f"{duration:.3g} ({share:.2g} %)" in text and "| 25 % |" in text
    assert "g / w1^2" not in "\n".join(page.damper_lines(studied({"bare": {"mu": 0.0, "d": 100.0}}), [row]))
