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


def test_the_joint_optimum_and_its_flatness_on_a_known_grid():
    """A paraboloid over (FR, mu) peaking at a known cell: that cell, its value, and the share of
    cells within 10 % of it counted by hand; the smallest of its negative likewise; nan skipped."""
    import numpy as np

    from pidamper.studies import paper

    fr, mu = np.meshgrid(np.linspace(0, 1, 11), np.linspace(0, 1, 7), indexing="ij")
    grid = 1.0 - (fr - 0.3) ** 2 - (mu - 0.5) ** 2
    grid[0, 0] = np.nan
    (i, j), top, share = paper.optimum(grid, max)
    assert (i, j) == (3, 3) and top == 1.0
    finite = grid[np.isfinite(grid)]
    assert share == np.count_nonzero(finite >= 0.9) / finite.size
    (k, m), low, share_min = paper.optimum(2.0 - grid, min)
    assert (k, m) == (3, 3) and low == 1.0 and share_min == np.count_nonzero(2.0 - finite <= 1.1) / finite.size
    last = len(paper.JOINT_MU) - 1
    assert paper._cell(0, last).endswith("(edge: largest mu, smallest FR)") and "edge" not in paper._cell(3, 3)
