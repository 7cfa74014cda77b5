"""The FMUs there are: PendulumImpactDamper (the paper's pendulum system), PendulumImpactDamperUnit
(the particle and its stops alone) and, per storey count N = 1..MAX_STOREYS, DampedShearBuilding<N>
(the damper on an N-storey building) and ShearBuilding<N> (the bare building, for co-simulation
with the unit).  Names only: nothing here imports the model."""
import re

MODEL_NAME = "PendulumImpactDamper"
UNIT = "PendulumImpactDamperUnit"
#: the FMUs `python -m build_fmu` always builds
BASE_MODELS = (MODEL_NAME, UNIT)
#: the building families, one FMU per storey count
FAMILIES = ("DampedShearBuilding", "ShearBuilding")
MAX_STOREYS = 10  # pidamper_physics.params.MAX_STOREYS (a test checks they agree)


def check_storeys(n):
    """n if it is a storey count the building FMUs exist for, else a ValueError naming the range."""
    if type(n) is not int or not 1 <= n <= MAX_STOREYS:
        raise ValueError(f"storeys = {n!r} is not allowed: an integer in 1..{MAX_STOREYS} (a building FMU per "
                         "storey count; 0 is the pendulum system, PendulumImpactDamper)")
    return n


def building_models(n, damper=None):
    """The building FMUs of n storeys: (DampedShearBuilding<n>, ShearBuilding<n>), or the one
    with (damper=True) or without (False) the damper."""
    check_storeys(n)
    names = (f"DampedShearBuilding{n}", f"ShearBuilding{n}")
    return names if damper is None else (names[0] if damper else names[1],)


def models(storeys=()):
    """The FMUs `python -m build_fmu --storeys ...` builds: BASE_MODELS, then both building FMUs of
    each storey count."""
    return list(BASE_MODELS) + [name for n in storeys for name in building_models(n)]


def family(model):
    """(family: the model name, or its prefix for a building, storey count or 0) of a model name; a
    ValueError names the allowed ones."""
    if model in BASE_MODELS:
        return model, 0
    found = re.fullmatch(r"(DampedShearBuilding|ShearBuilding)(\d+)", model)
    if found and 1 <= int(found.group(2)) <= MAX_STOREYS and not found.group(2).startswith("0"):
        return found.group(1), int(found.group(2))
    raise ValueError(f"model {model!r} is not allowed: one of {', '.join(BASE_MODELS)}, DampedShearBuilding<N> or "
                     f"ShearBuilding<N> with N in 1..{MAX_STOREYS}")
