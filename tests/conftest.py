"""Shared fixtures: one FMU built in a separate process for the whole session."""
import subprocess
import sys

import pytest


@pytest.fixture(scope="session")
def fmu_path(tmp_path_factory):
    """The FMU as `python -m build_fmu --out DIR` builds it (in a fresh process)."""
    out = tmp_path_factory.mktemp("fmu")
    done = subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(out)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    path = out / "PendulumImpactDamper.fmu"
    assert path.is_file()
    return path


@pytest.fixture
def lockstep(fmu_path):
    """check(values, forcing, h, n): the FMU and the core, stepped together n steps of h, agree
    bit for bit at every step and on the impact count, which it returns."""
    from pidamper import CoreStepper, FmuStepper

    def check(values, signal, h, n):
        with FmuStepper(fmu_path, values, forcing=signal) as fmu, CoreStepper(values, forcing=signal) as core:
            for k in range(1, n + 1):
                fmu.advance(k * h)
                core.advance(k * h)
                assert fmu.read() == core.read()
            impacts = fmu.get("impacts")
            assert impacts == core.get("impacts")
        return impacts
    return check
