"""The paper study runs the physics core directly; on a sample of its grid points the FMU gives
the same measures, for both readings."""
import math

import pytest

from pidamper import FmuStepper
from pidamper.measures import damping_ratio, max_abs_theta
from pidamper.studies.paper import HORIZON, PERIOD, READINGS, amplitude, damping, params


@pytest.mark.parametrize("reading", READINGS)
def test_core_and_fmu_measures_agree_on_sample_points(fmu_path, reading):
    for FR, d, e in ((1.5, 0.05, 0.2), (5.0, 0.1, 0.2), (4.0, 0.2, 0.8)):
        values = params(reading, FR, d, e, 0.1)
        with FmuStepper(fmu_path, values) as stepper:
            fmu = damping_ratio(stepper, PERIOD)[0]
        assert fmu == damping(values)
    forced = params(reading, 5.0, 0.1, 0.2, 0.02, forced=True)
    with FmuStepper(fmu_path, forced) as stepper:
        fmu_peak = abs(max_abs_theta(stepper, HORIZON * PERIOD, PERIOD / 50).theta)
    assert fmu_peak == amplitude(forced)


def test_readings_differ_only_in_the_contact_rule():
    a, b = params("consistent", 5.0, 0.1, 0.2, 0.1), params("paper-reading", 5.0, 0.1, 0.2, 0.1)
    assert {k for k in a if a[k] != b[k]} == {"contact_form"}
    assert a["theta_dot_0"] == pytest.approx(0.7 * math.sqrt(9.81))
