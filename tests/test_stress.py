"""Hard-case stability suite through the FMU (pidamper.benchmarks.stress), each under a time limit.

The quick sizes run always; the full sizes (10^4 periods at resonance, 10^5 impacts, 10^6
steps) are marked slow: `make test` runs them, `make test-fast` leaves them out.
Near-grazing and e = 1 runs are sensitive to the last bit (chaos), so sensitive_twins
compares statistics of a run and a twin perturbed by 1e-12, not trajectories.
"""
import pytest

from pidamper.benchmarks.stress import CASES


@pytest.mark.timeout(120)
@pytest.mark.parametrize("name", sorted(CASES))
def test_stress_quick(fmu_path, name):
    ok, detail = CASES[name](fmu_path, quick=True)
    assert ok, detail


@pytest.mark.slow
@pytest.mark.timeout(300)
@pytest.mark.parametrize("name", ["resonance_no_contact", "resonance_with_damper", "elastic_long", "step_sizes",
                                  "long_run_memory", "parameter_extremes"])
def test_stress_full(fmu_path, name):
    ok, detail = CASES[name](fmu_path, quick=False)
    assert ok, detail
