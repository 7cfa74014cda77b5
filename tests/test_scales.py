"""Parameter scales the float arithmetic cannot hold are refused, and a frequency that acts on
nothing costs nothing (issue 13 items: steps that never answered)."""
import math

import pytest

from pidamper.running import isolated
from pidamper_physics import Damper, ParameterError, Params


@pytest.mark.parametrize("values", [{"mu": 8e305}, {"g": 1e308}, {"FR": 1e160}, {"L2": 1e-320}])
def test_scales_that_overflow_are_refused_naming_them(values):
    with pytest.raises(ParameterError, match="float arithmetic cannot hold"):
        Params(**values)


@pytest.mark.parametrize("name, value", [("mu", 8e305), ("g", 1e308)])
def test_the_fmu_refuses_them_instead_of_looping(fmu_path, name, value):
    """mu = 8e305 or g = 1e308 made the largest frequency inf and fmi2DoStep loop forever."""
    text = isolated.call("pidamper.benchmarks.fatal_checks:bad_parameter", str(fmu_path), name, value)
    assert text is not None and "float arithmetic cannot hold" in text and "status 3 (error)" in text


@pytest.mark.parametrize("fidelity", [0, 1, 3])
def test_a_frequency_without_a_force_costs_nothing(fidelity):
    """Omega = 1e9 with F0 = 0 took 9 s per 0.01 s step (a span of one forcing period); it acts on
    nothing, so the run equals the one at the default Omega bit for bit, in one piece per step."""
    extra = {"zeta_s": 0.01} if fidelity == 1 else {}
    runs = []
    for omega in (1e9, math.sqrt(9.81)):
        core = Damper(Params(Omega=omega, F0=0.0, fidelity=fidelity, **extra), 0.0, 0.7 * math.sqrt(9.81))
        pieces = [0]
        build = core._segment

        def counting(*args):
            pieces[0] += 1
            return build(*args)

        core._segment = counting
        states = []
        for k in range(1, 201):
            core.advance(0.01 * k)
            states.append(core.get_state())
        runs.append((states, pieces[0]))
    assert runs[0][0] == runs[1][0]
    assert runs[0][1] == runs[1][1] < 2000  # the same pieces (events included) as at a slow Omega
