"""The yielding buildings through FMI (issue 24): DampedShearBuilding3 and ShearBuilding3 with
yielding storeys, P-Delta and collapse, driven by fmpy as a host does, against the physics core
they wrap (bit for bit), their collapse warning and latch (held outputs, FMU state), and bad
yielding parameters refused at initialization by name."""
import math

import pytest

from pidamper import FmuStepper, find_fmu, forcing
from pidamper.running.instance import FmuInstance
from pidamper_physics import Damper, Params
from pidamper_physics.building import ShearBuilding
from pidamper_physics.storeys import check_storeys
from pidamper_physics.yielding import YieldingMotion

YIELDING = {"fidelity": 1, "zeta_s": 0.02, "mu": 0.05, "FR": 0.95, "d": 0.02, "e": 0.5, "p_delta": 1,
            "collapse_drift": 0.03, **{f"storey[{k}].k": 8e7 for k in (1, 2, 3)},
            "storey[1].Fy": 2e5, "storey[2].Fy": 5e5, "storey[3].Fy": 3e5, "storey[1].b": 0.0}
OUT = [f"storey[{k}].{f}" for k in (1, 2, 3) for f in ("force", "plastic_drift", "drift_ratio_max")] + [
    "energy_hysteretic", "collapsed", "floor[3].x", "floor[1].a", "impacts", "base_shear"]


def test_damped_building_fmu_yields_collapses_and_holds(fmu_dir):
    """The FMU against the core step by step (bit for bit), until and past its collapse: a warning
    names the storey and the time, every output holds from then, the run goes on with fmi2OK."""
    path = find_fmu(storeys=3)
    signal = forcing.kanai_tajimi(12.0, pga=4.0, seed=1, dt=0.01)
    p = Params.from_variables({**YIELDING, "storeys": 3, "storey_Fy": [2e5, 5e5, 3e5]})
    core = Damper(p)
    said = []
    with FmuStepper(path, YIELDING, forcing=signal, logger=lambda status, text: said.append(text)) as fmu:
        held, collapsed_at = None, None
        for k in range(1, 1201):
            t = 0.01 * k
            a = float(signal.value(fmu.t))
            fmu.advance(t)
            if not core.halted:
                core.advance(t, 0.0, a)
                xs, acc, drifts, shear = core.building_outputs(0.0, a)
                assert fmu.get("floor[3].x") == xs[2] and fmu.get("base_shear") == shear
                assert fmu.get("energy_hysteretic") == core.model.storeys.hysteretic
            values = [fmu.get(n) for n in OUT]
            if held is not None:
                assert values == held  # every output holds after the collapse
            elif fmu.get("collapsed"):
                held, collapsed_at = values, t
        assert collapsed_at is not None and fmu.get("storey[1].drift_ratio_max") == pytest.approx(0.03, rel=1e-12)
        assert core.model.storeys.collapse_time == pytest.approx(collapsed_at, abs=0.01 + 1e-12)
    assert any("collapsed" in s and "storey 1" in s for s in said)


def test_collapse_latch_is_part_of_the_fmu_state(fmu_dir):
    path = find_fmu(storeys=3)
    signal = forcing.kanai_tajimi(12.0, pga=4.0, seed=1, dt=0.01)
    with FmuStepper(path, YIELDING, forcing=signal) as fmu:
        for k in range(1, 201):
            fmu.advance(0.01 * k)
        saved = fmu.save()
        for k in range(201, 1201):
            fmu.advance(0.01 * k)
        first = [fmu.get(n) for n in OUT]
        assert first[OUT.index("collapsed")] == 1
        fmu.restore(saved)
        assert fmu.get("collapsed") == 0
        for k in range(201, 1201):
            fmu.advance(0.01 * k)
        assert [fmu.get(n) for n in OUT] == first
        fmu.discard(saved)


def test_a_state_saved_after_the_collapse_holds_its_outputs(fmu_dir):
    """Saved after the collapse, restored and run on: every output is still the one held at the
    collapse (floor accelerations included, which the held input of a later step would change)."""
    path = find_fmu(storeys=3)
    signal = forcing.kanai_tajimi(12.0, pga=4.0, seed=1, dt=0.01)
    names = OUT + ["floor[2].a", "floor[3].a", "a", "theta"]
    with FmuStepper(path, YIELDING, forcing=signal) as fmu:
        k = 0
        while not fmu.get("collapsed"):
            k += 1
            fmu.advance(0.01 * k)
        held = [fmu.get(n) for n in names]
        for k in range(k + 1, k + 50):
            fmu.advance(0.01 * k)
        saved = fmu.save()
        for k in range(k + 1, k + 50):
            fmu.advance(0.01 * k)
        fmu.restore(saved)
        assert [fmu.get(n) for n in names] == held
        fmu.advance(fmu.t + 0.01)
        assert [fmu.get(n) for n in names] == held
        fmu.discard(saved)


def test_bare_building_fmu_is_the_yielding_core(fmu_dir):
    """ShearBuilding3 with yielding storeys and P-Delta, bit for bit with YieldingMotion."""
    path = find_fmu(storeys=3, damper=False)
    values = {"zeta_s": 0.02, "p_delta": 1, "storey[1].Fy": 6e5, "storey[2].Fy": 5e5, "storey[3].Fy": 3e5,
              **{f"storey[{k}].k": 8e7 for k in (1, 2, 3)}}
    signal = forcing.kanai_tajimi(6.0, pga=3.0, seed=3, dt=0.01)
    law = check_storeys([8e7] * 3, [6e5, 5e5, 3e5], [0.02] * 3, [3.0] * 3, [1e5] * 3, 1, 9.81, 0.1)
    core = YieldingMotion(ShearBuilding([1e5] * 3, [8e7] * 3, 0.02, [3.0] * 3, law.geometric), law, 0.1)
    with FmuInstance(path, values) as fmu:
        for k in range(1, 601):
            a = float(signal.value(0.01 * (k - 1)))
            fmu.set("a_g", a)
            fmu.do_step(0.01 * (k - 1), 0.01)
            core.advance(0.01 * (k - 1) + 0.01, [0.0] * 3, a)
            assert [fmu.get(f"floor[{i}].x") for i in (1, 2, 3)] == core.x
            assert [fmu.get(f"storey[{i}].force") for i in (1, 2, 3)] == core.storey_forces()
            assert fmu.get("energy_hysteretic") == core.hysteretic
        assert core.storeys.events > 10
        e = fmu.get("energy") + fmu.get("energy_viscous") + fmu.get("energy_hysteretic") - fmu.get("work_in")
        assert abs(e) < 1e-9 * fmu.get("work_in")


@pytest.mark.parametrize("damper, values, expected", [
    (True, {"storey[2].Fy": -1.0}, "storey[2].Fy = -1.0"),
    (True, {"storey[3].Fy": 1e5, "storey[3].b": 1.0}, "storey[3].b = 1.0"),
    (False, {"storey[1].Fy": 1e5, "collapse_drift": 0.0}, "collapse_drift = 0.0"),
    (False, {"p_delta": 1, "storey[1].k": 1e5}, "storey[1].k = 100000.0"),
    (False, {"storey[1].Fy": 1e5, "storey[1].b": 0.0, "zeta_s": 0.0}, "storey[1].b = 0.0"),
])
def test_bad_yielding_parameters_are_refused_at_initialization(fmu_dir, damper, values, expected):
    from pidamper.running import isolated

    path = find_fmu(storeys=3, damper=damper)
    text = isolated.call("pidamper.benchmarks.fatal_checks:bad_values", str(path), values)
    assert text is not None and expected in text and "not allowed" in text and "status 3 (error)" in text
    assert math.isfinite(len(text))
