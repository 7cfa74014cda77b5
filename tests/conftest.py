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
