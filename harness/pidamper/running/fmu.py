"""Find the FMU of a model, building it when it is missing or stale: PendulumImpactDamper (the
pendulum system), DampedShearBuilding<N> (the damper on an N-storey building: `storeys=N`),
ShearBuilding<N> (`storeys=N, damper=False`) or PendulumImpactDamperUnit (`model=`).

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


#: environment variable naming the folder find_fmu uses (a shared cache for a cluster, a test session)
FMU_DIR_VARIABLE = "PIDAMPER_FMU_DIR"


def default_fmu_path(model="PendulumImpactDamper"):
    """<model>.fmu in $PIDAMPER_FMU_DIR if set, else in dist/ of the source checkout, else in a
    per-user cache folder."""
    from build_fmu import sources

    if os.environ.get(FMU_DIR_VARIABLE):
        return Path(os.environ[FMU_DIR_VARIABLE]) / f"{model}.fmu"
    slave, _ = sources()
    repo = slave.parents[2]
    if (repo / "pyproject.toml").is_file() and (repo / "build_fmu").is_dir():
        return repo / "dist" / f"{model}.fmu"
    cache = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "pidamper"
    return cache / f"{model}.fmu"


def is_current(path):
    """True when the FMU at path (named <model>.fmu) was built from the current sources."""
    from build_fmu import expected_guid

    path = Path(path)
    try:
        return fmpy.read_model_description(str(path)).guid == expected_guid(model=path.stem)
    except Exception:
        return False


def build_fmu(out_dir, models=("PendulumImpactDamper",)):
    """Build the FMUs of `models` into out_dir in a fresh process, atomically file by file; returns
    their paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".build-", dir=out_dir))
    try:
        cmd = [sys.executable, "-m", "build_fmu", "--out", str(staging), "--model", *models]
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"building the FMU failed:\n{done.stdout}{done.stderr}")
        for built in staging.iterdir():
            if built.is_file():
                os.replace(built, out_dir / built.name)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return [out_dir / f"{model}.fmu" for model in models]


def ensure_built(paths, current):
    """Build the FMUs at `paths` (each named <model>.fmu, all in one folder) unless current(path)
    holds for each; under a file lock in that folder, so that concurrent callers build once.
    Returns paths."""
    paths = [Path(p) for p in paths]
    if all(current(p) for p in paths):
        return paths
    folder = paths[0].parent
    folder.mkdir(parents=True, exist_ok=True)
    with FileLock(str(folder / ".build.lock")):
        stale = [p for p in paths if not current(p)]  # another process may have built them while we waited
        if stale:
            build_fmu(folder, [p.stem for p in stale])
    return paths


def model_name(storeys=0, damper=True, model=None):
    """The model of find_fmu's arguments (see find_fmu); a ValueError names a value not allowed."""
    from build_fmu import MAX_STOREYS, building_models, family

    if model is not None:
        family(model)  # refuses a name that is no model
        return model
    if storeys == 0 and not isinstance(storeys, bool):
        if not damper:
            raise ValueError("damper = False is not allowed with storeys = 0: the bare building needs storeys in "
                             f"1..{MAX_STOREYS} (the particle alone is model='PendulumImpactDamperUnit')")
        return "PendulumImpactDamper"
    return building_models(storeys, bool(damper))[0]


def find_fmu(path=None, storeys=0, damper=True, model=None):
    """The FMU to run: `path` if given (must exist); else the current build of PendulumImpactDamper
    (storeys = 0), DampedShearBuilding<storeys> (damper = True) or ShearBuilding<storeys> (damper =
    False), or of `model` by name, built on demand once (ensure_built)."""
    if path is not None:
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"--fmu {path}: no such file (build one with: python -m build_fmu)")
        return path
    return ensure_built([default_fmu_path(model_name(storeys, damper, model))], is_current)[0]
