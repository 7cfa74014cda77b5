"""Shared fixtures: the FMUs built in a separate process for the whole session."""
import os
import subprocess
import sys

import pytest


#: the session's exit status, for pytest_unconfigure
_EXIT = {}


def pytest_sessionfinish(session, exitstatus):
    _EXIT["status"] = int(exitstatus)


@pytest.hookimpl(trylast=True)
def pytest_unconfigure(config):
    """Leave the test process without the interpreter's teardown, once every result is reported.

    About one full run in two (CI once, fresh clones here twice in four, 2026-11-26) segfaulted
    after its summary, in native code during interpreter teardown ("Fatal Python error:
    Segmentation fault ... <no Python frame>" under PYTHONFAULTHANDLER): the session loads FMU
    binaries (pythonfmu's, ours, the compiled C one), libcosim, Rerun's and Foxglove's native
    libraries, and one of them does not survive the teardown in some orders.  OpenSeesPy, the
    first suspect, now runs only in child processes and the crash remained.  No subset reproduced
    it, so the session ends by os._exit with its own status; PIDAMPER_TEST_TEARDOWN=1 keeps the
    normal teardown (to chase the crash)."""
    if "status" in _EXIT and os.environ.get("PIDAMPER_TEST_TEARDOWN") != "1":
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_EXIT["status"])


#: the building FMUs the session builds beside the pendulum system's and the unit
SESSION_STOREYS = ("1", "2", "3", "10")


@pytest.fixture(scope="session")
def fmu_dir(tmp_path_factory):
    """The FMUs as `python -m build_fmu --storeys 1 2 3 10 --out DIR` builds them (in a fresh
    process); find_fmu looks there for the whole session (PIDAMPER_FMU_DIR), and builds any other
    variant there on demand."""
    out = tmp_path_factory.mktemp("fmu")
    done = subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(out), "--storeys", *SESSION_STOREYS],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    os.environ["PIDAMPER_FMU_DIR"] = str(out)
    return out


@pytest.fixture(scope="session")
def fmu_path(fmu_dir):
    """PendulumImpactDamper.fmu of the session's build."""
    path = fmu_dir / "PendulumImpactDamper.fmu"
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
