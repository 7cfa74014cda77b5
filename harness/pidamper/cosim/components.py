"""The component FMUs (ShearBuilding<N>.fmu, PendulumImpactDamperUnit.fmu): located, built on demand
when missing or stale, instantiated."""
from pathlib import Path

from .scenario import BUILDING, UNIT


def component_fmus(folder=None, storeys=3):
    """{BUILDING: path of ShearBuilding<storeys>.fmu, UNIT: path of PendulumImpactDamperUnit.fmu}:
    in `folder` if given, else where find_fmu looks, built (in a fresh process, under its lock)
    when missing or stale."""
    from ..running.fmu import default_fmu_path, ensure_built, is_current

    names = {BUILDING: f"{BUILDING}{storeys}", UNIT: UNIT}
    if folder is not None:
        paths = {role: Path(folder) / f"{name}.fmu" for role, name in names.items()}
        missing = [str(p) for p in paths.values() if not p.is_file()]
        if missing:
            raise FileNotFoundError(f"{', '.join(missing)}: no such file (build them with: python -m build_fmu "
                                    f"--storeys {storeys})")
        return paths
    paths = {role: default_fmu_path(name) for role, name in names.items()}
    ensure_built(paths.values(), is_current)
    return paths


def component_instance(path, name, values, messages):
    """One initialised FMU instance whose warnings and errors go to the list `messages`."""
    from ..running.instance import FmuInstance

    def hear(status, text):
        if status != 0:  # fmi2OK: which build of the physics runs
            messages.append(text)
    return FmuInstance(path, values, instance_name=name, logger=hear)
