"""Find the damper FMU, building it when it is missing or stale.

A built FMU carries a GUID derived from a hash of its sources, so a stale build
(sources changed since) is detected without unpacking anything but the
modelDescription.  Builds run in a fresh Python process: pythonfmu imports the
model module to describe it, and the FMU should never share a module cache with
the process that built it.

Builds are safe under concurrency: processes that find the FMU missing or stale at once (a study's
pool, Dask workers, two shells) take a file lock beside it; the first builds, the others wait and
reuse its build.  A build is written into a temporary folder and moved into place file by file
(`os.replace`), so no process ever opens a half-written FMU.
"""
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import fmpy
from filelock import FileLock

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
    """True when the FMU at path (named <model>.fmu) was built from the current sources."""
    from build_fmu import expected_guid

    path = Path(path)
    try:
        return fmpy.read_model_description(str(path)).guid == expected_guid(model=path.stem)
    except Exception:
        return False


def build_fmu(out_dir):
    """Build the FMUs into out_dir in a fresh process, atomically file by file; returns the damper's path."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".build-", dir=out_dir))
    try:
        cmd = [sys.executable, "-m", "build_fmu", "--out", str(staging)]
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"building the FMU failed:\n{done.stdout}{done.stderr}")
        for built in staging.iterdir():
            if built.is_file():
                os.replace(built, out_dir / built.name)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return out_dir / FMU_NAME


def ensure_built(paths, current):
    """Build into the folder of `paths` unless current(path) holds for each; under a file lock there,
    so that concurrent callers build once.  Returns paths."""
    paths = [Path(p) for p in paths]
    if all(current(p) for p in paths):
        return paths
    folder = paths[0].parent
    folder.mkdir(parents=True, exist_ok=True)
    with FileLock(str(folder / ".build.lock")):
        if not all(current(p) for p in paths):  # another process may have built them while we waited
            build_fmu(folder)
    return paths


def find_fmu(path=None):
    """The FMU to run: `path` if given (must exist), else the current default build."""
    if path is not None:
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"--fmu {path}: no such file (build one with: python -m build_fmu)")
        return path
    return ensure_built([default_fmu_path()], is_current)[0]
