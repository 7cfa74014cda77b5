"""Find the damper FMU, building it when it is missing or stale.

A built FMU carries a GUID derived from a hash of its sources, so a stale build
(sources changed since) is detected without unpacking anything but the
modelDescription.  Builds run in a fresh Python process: pythonfmu imports the
model module to describe it, and the FMU should never share a module cache with
the process that built it.
"""
import os
import subprocess
import sys
from pathlib import Path

import fmpy

FMU_NAME = "PendulumImpactDamper.fmu"


def default_fmu_path():
    """dist/ of the source checkout, else a per-user cache folder."""
    from build_fmu import sources

    slave, _ = sources()
    repo = slave.parents[2]
    if (repo / "pyproject.toml").is_file() and (repo / "build_fmu").is_dir():
        return repo / "dist" / FMU_NAME
    cache = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "pidamper"
    return cache / FMU_NAME


def is_current(path):
    """True when the FMU at path was built from the current sources."""
    from build_fmu import expected_guid

    try:
        return fmpy.read_model_description(str(path)).guid == expected_guid()
    except Exception:
        return False


def build_fmu(out_dir):
    """Build the FMU into out_dir in a fresh process; returns its path."""
    out_dir = Path(out_dir)
    cmd = [sys.executable, "-m", "build_fmu", "--out", str(out_dir)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"building the FMU failed:\n{done.stdout}{done.stderr}")
    return out_dir / FMU_NAME


def find_fmu(path=None):
    """The FMU to run: `path` if given (must exist), else the current default build."""
    if path is not None:
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"--fmu {path}: no such file (build one with: python -m build_fmu)")
        return path
    path = default_fmu_path()
    if not is_current(path):
        build_fmu(path.parent)
    return path
