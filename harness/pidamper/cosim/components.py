"""The component FMUs (ShearBuilding.fmu, PendulumImpactDamperUnit.fmu): located, rebuilt when stale,
instantiated."""
from pathlib import Path

from .scenario import BUILDING, UNIT


def component_fmus(folder=None):
    """{name: path} of ShearBuilding.fmu and PendulumImpactDamperUnit.fmu: `folder` if given, else
    dist/ of the source checkout, rebuilt (all FMUs, in a fresh process) when missing or stale."""
    from ..running.fmu import default_fmu_path, ensure_built, is_current

    if folder is not None:
        paths = {name: Path(folder) / f"{name}.fmu" for name in (BUILDING, UNIT)}
        missing = [str(p) for p in paths.values() if not p.is_file()]
        if missing:
            raise FileNotFoundError(f"{', '.join(missing)}: no such file (build them with: python -m build_fmu)")
        return paths
    dist = default_fmu_path().parent
    paths = {name: dist / f"{name}.fmu" for name in (BUILDING, UNIT)}
    ensure_built(paths.values(), is_current)
    return paths


def component_instance(path, name, values, messages):
    """One initialised FMU instance whose messages go to the list `messages`."""
    from ..running.instance import FmuInstance

    return FmuInstance(path, values, instance_name=name, logger=lambda status, text: messages.append(text))
