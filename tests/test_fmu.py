"""The built FMU under fmpy: validation, step-size independence, state, instances, bad input."""
import math
import sys

import fmpy
import numpy as np
import pytest
from fmpy.validation import validate_fmu

from pidamper import CoreStepper, FmuStepper, forcing
from build_fmu import expected_guid
from pidamper.running import isolated

W2 = math.sqrt(9.81)
PERIOD = 2 * math.pi / W2
FORCED = {"mu": 0.02, "FR": 5.0, "d": 0.1, "e": 0.2, "F0": 0.0981, "Omega": W2, "phi": math.pi / 2}
FREE = {"mu": 0.1, "FR": 5.0, "d": 0.1, "e": 0.2, "theta_dot_0": 0.7 * W2}


def test_fmpy_validate_reports_no_problems(fmu_path):
    assert validate_fmu(str(fmu_path)) == []


def test_model_description_contract(fmu_path):
    md = fmpy.read_model_description(str(fmu_path))
    assert md.coSimulation.modelIdentifier == "PendulumImpactDamper" and md.modelName == "PendulumImpactDamper"
    assert md.guid == expected_guid()
    by_name = {v.name: v for v in md.modelVariables}
    assert by_name["F"].causality == "input" and by_name["F"].unit == "N"
    assert by_name["e"].variability == "tunable" and by_name["M"].variability == "fixed"
    assert by_name["contact_form"].type == "Integer"
    assert by_name["energy_dissipated"].unit == "J" and by_name["a"].unit == "m/s2"
    deps = {u.variable.name: [d.name for d in u.dependencies] for u in md.outputs}
    assert deps["theta"] == [] and deps["a"] == ["F", "a_g"] and deps["contact_force"] == ["F", "a_g"]
    assert by_name["a_g"].causality == "input" and by_name["a_g"].unit == "m/s2"
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    assert md.defaultExperiment.stopTime == "20.0" or float(md.defaultExperiment.stopTime) == 20.0


def test_fmu_runs_its_own_physics_copy(fmu_path):
    """The FMU imports a hash-named copy of the physics, never the source tree's module."""
    import pidamper_physics  # the source tree, imported by this test process
    with FmuStepper(fmu_path, FREE) as stepper:
        stepper.advance(1.0)
    shipped = [name for name in sys.modules if name.startswith("pidamper_physics_")]
    assert shipped, "the FMU did not load a renamed physics package"
    for name in shipped:
        assert sys.modules[name].__file__ != pidamper_physics.__file__


def fmpy_run(fmu_path, h, stop, params, **kw):
    return fmpy.simulate_fmu(str(fmu_path), stop_time=stop, output_interval=h, start_values=params,
                             output=["theta", "theta_dot", "impacts", "energy", "work_in", "energy_dissipated"], **kw)


@pytest.mark.parametrize("params", [FORCED, FREE], ids=["resonance", "free-decay"])
def test_step_size_does_not_change_the_trajectory(fmu_path, params):
    """Communication steps from 1e-4 s to 10 s give one trajectory at common times."""
    stop = 10.0
    ref = fmpy_run(fmu_path, 10.0, stop, params)
    scale = None
    for h in (1e-4, 1e-3, 0.01, 0.1, 1.0, 2.5):
        res = fmpy_run(fmu_path, h, stop, params)
        scale = scale or float(np.abs(res["theta"]).max())
        for name in ("theta", "theta_dot"):
            assert res[name][-1] == pytest.approx(ref[name][-1], abs=1e-9 * scale * (W2 if name == "theta_dot" else 1))
        assert res["impacts"][-1] == ref["impacts"][-1]
        at_5 = res[np.isclose(res["time"], 5.0)]
        if len(at_5):
            mid = FmuStepper(fmu_path, params)
            mid.advance(5.0)
            assert at_5["theta"][0] == pytest.approx(mid.read()[0], abs=1e-9 * scale)
            mid.close()


def test_fmu_equals_the_core(lockstep):
    """The adapter adds nothing: FMU and core agree bit for bit on the same steps."""
    assert lockstep(FORCED, forcing.harmonic(0.05, 0.9 * W2, 0.2, sampled=True), 0.025, 800) > 0


def _run_steps(stepper, times):
    out = []
    for t in times:
        stepper.advance(t)
        out.append((*stepper.read(), stepper.get("impacts"), stepper.get("energy")))
    return out


def test_state_save_restore_and_serialize_continue_bit_identically(fmu_path):
    with FmuStepper(fmu_path, FREE) as s:
        s.advance(3.3)
        state = s.fmu.getFMUstate()
        blob = s.fmu.serializeFMUstate(state)
        times = [3.3 + 0.07 * k for k in range(1, 200)]
        first = _run_steps(s, times)
        s.fmu.setFMUstate(state)
        s.t = 3.3
        again = _run_steps(s, times)
        s.fmu.freeFMUstate(state)
    assert again == first
    with FmuStepper(fmu_path, FREE, instance_name="restored") as r:
        restored = r.fmu.deSerializeFMUstate(blob)
        r.fmu.setFMUstate(restored)
        r.t = 3.3
        assert _run_steps(r, times) == first
        r.fmu.freeFMUstate(restored)


def test_two_instances_with_different_parameters(fmu_path):
    other = {**FREE, "FR": 2.0, "e": 0.5, "d": 0.05}
    times = [0.05 * k for k in range(1, 400)]
    with FmuStepper(fmu_path, FREE, instance_name="a") as a, FmuStepper(fmu_path, other, instance_name="b") as b:
        both = [(_run_steps(a, [t]), _run_steps(b, [t])) for t in times]
    with FmuStepper(fmu_path, FREE, instance_name="solo-a") as a:
        solo_a = _run_steps(a, times)
    with FmuStepper(fmu_path, other, instance_name="solo-b") as b:
        solo_b = _run_steps(b, times)
    assert [x[0][0] for x in both] == solo_a
    assert [x[1][0] for x in both] == solo_b
    assert solo_a != solo_b


def test_tunable_restitution_takes_effect_at_the_communication_point(fmu_path):
    with FmuStepper(fmu_path, FREE) as fmu, CoreStepper(FREE) as core:
        for t in (1.0, 2.0):
            fmu.advance(t)
            core.advance(t)
        fmu.set("e", 0.9)
        core.core.set_restitution(0.9)
        for k in range(1, 100):
            fmu.advance(2.0 + 0.05 * k)
            core.advance(2.0 + 0.05 * k)
            assert fmu.read() == core.read()


# ---- bad input: an FMI error whose message names the variable, value and rule -----------

class Capture:
    def __init__(self):
        self.messages = []

    def __call__(self, component, instance, status, category, message):
        self.messages.append(message.decode() if isinstance(message, bytes) else str(message))

    def text(self):
        return "\n".join(self.messages)


BAD_PARAMETERS = [("g", 0.0, "g = 0.0"), ("M", -1.0, "M = -1.0"), ("mu", -0.5, "mu = -0.5"),
                  ("L2", float("nan"), "L2 = nan"), ("FR", 0.0, "FR = 0.0"), ("d", 0.0, "d = 0.0"),
                  ("d_angle", -1.0, "d_angle = -1.0"), ("e", 1.5, "e = 1.5"), ("e", -0.2, "e = -0.2"),
                  ("contact_form", 2, "contact_form = 2"), ("Omega", float("inf"), "Omega = inf"),
                  ("theta_0", 0.5, "penetrates"), ("angle_limit", -0.1, "angle_limit = -0.1"),
                  ("angle_limit", float("nan"), "angle_limit = nan")]


# Each of these makes the FMU fail with fmi2Fatal, after which (FMI standard, and pythonfmu 0.7
# in practice) no instance of the FMU may be used again in that process: they run in a child.

@pytest.mark.parametrize("name,value,expected", BAD_PARAMETERS)
def test_invalid_parameter_is_an_fmi_error_with_its_message(fmu_path, name, value, expected):
    text = isolated.call("pidamper.benchmarks.fatal_checks:bad_parameter", str(fmu_path), name, value)
    assert text is not None, f"{name} = {value} was accepted"
    assert expected in text and "not allowed" in text and "status 3 (error)" in text


@pytest.mark.parametrize("value", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_input_is_refused(fmu_path, value):
    result = isolated.call("pidamper.benchmarks.fatal_checks:bad_input", str(fmu_path), value)
    assert result["error"] is not None and f"F = {value!r}" in result["error"] and "finite" in result["error"]


@pytest.mark.parametrize("action", ["back", "mismatch", "fixed", "tunable-range"])
def test_host_misuse_is_refused(fmu_path, action):
    """A step back in time, a step from the wrong time, a fixed parameter after initialization,
    a tunable parameter out of range: each an FMI error."""
    assert isolated.call("pidamper.benchmarks.fatal_checks:host_misuse", str(fmu_path), action) is True


def test_last_bit_time_mismatch_is_accepted(fmu_path):
    with FmuStepper(fmu_path, FREE) as s:  # libcosim passes times that differ in the last bits
        s.advance(1.0)
        s.do_step(1.0 + 2e-16, 0.1)
        assert s.t == pytest.approx(1.1)
