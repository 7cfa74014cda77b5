"""Start values for the FMU of one model.

Scenes, studies and the Python API write one set of names: the pendulum system's parameters,
`storeys` choosing the building (0: PendulumImpactDamper.fmu; N: DampedShearBuilding<N>.fmu) and
floor[k].m, storey[k].k, storey[k].h of any k.  Each FMU has only its own variables, so the values
are fitted to the model that runs them: `storeys` goes (the model is the choice), a building drops
the pendulum primary's parameters (they play no part in it) and the floors beyond its own.
"""
import re

from build_fmu import family
from pidamper_fmu.particle_tables import PENDULUM_ONLY

_PER_FLOOR = re.compile(r"(floor|storey)\[(\d+)\]\.\w+")


def storeys_of(values):
    """The storey count `values` ask for (0: the pendulum system)."""
    n = values.get("storeys", 0)
    if type(n) is not int and not (isinstance(n, float) and n.is_integer()):
        raise ValueError(f"storeys = {n!r} is not allowed: an integer in 0..10 (0: the pendulum system)")
    return int(n)


def for_model(model, values):
    """`values` fitted to `model` (see the module doc); a value the model cannot honour is refused
    with a ValueError naming it."""
    kind, n = family(model)
    values = dict(values)
    asked = storeys_of(values) if "storeys" in values else n  # unset: the named FMU's
    values.pop("storeys", None)
    if kind not in ("PendulumImpactDamper", "DampedShearBuilding"):
        return values
    if asked != n:
        raise ValueError(f"storeys = {asked!r} is not allowed with {model}.fmu, which models "
                         f"{'the pendulum system (storeys = 0)' if n == 0 else f'{n} storeys'}: leave the FMU "
                         "unnamed and the matching one is found, or name that one")
    if n == 0:
        if values.get("damper_floor", 0) == 0:
            values.pop("damper_floor", None)
        return values
    if values.get("contact_form", 0) != 0:
        raise ValueError(f"contact_form = {values['contact_form']!r} is not allowed with a building: it has the "
                         "displacement form (0) only")
    for name in PENDULUM_ONLY:
        values.pop(name, None)
    for name in list(values):
        found = _PER_FLOOR.fullmatch(name)
        if found and int(found.group(2)) > n:
            del values[name]
    return values
