"""ShearBuilding: a linear shear building alone, exact for held inputs (a thin adapter over
pidamper_physics.shear_motion.ShearMotion; conventions of adapter.py / slave.py).

Parameters storeys (1..10), floor[k].m, storey[k].k (k = 1..10; entries beyond storeys are
ignored), zeta_s (classical modal damping: every mode at this ratio).  Inputs a_g (ground
acceleration), F[k] (force on floor k), and for an impulse-aware host J[k], t_J[k]: an impulse J[k]
on floor k at time t_J[k] inside the coming step (ignored when J[k] = 0; a t_J[k] outside the step
is clamped into it: a host that passes it a step late, such as a Jacobi master, has it applied at
the step's start).  Outputs floor[k].x, floor[k].v (relative to the ground) and floor[k].a, the
absolute acceleration x_k'' + a_g = (M^-1 (F - C x' - K x))_k (direct feedthrough from F[k],
none from a_g); floors beyond storeys read 0.  Locals: energy, base_shear.

Defaults: three storeys of 1e5 kg floors and 8e7 N/m storeys: first period 0.4992 s (modes 0.499,
0.178, 0.123 s), no damping.
"""
import uuid

from pythonfmu import Integer, Real
from pythonfmu.default_experiment import DefaultExperiment

from pidamper_physics import ParameterError
from pidamper_physics.params import FLOOR_MASS, MAX_STOREYS, STOREY_STIFFNESS
from pidamper_physics.shear_motion import ShearMotion, make_building

from .adapter import ComponentSlave

SOURCE_HASH = "development"  # replaced by build_fmu with a hash of the shipped sources
VERSION = "0.1.0"

MODEL = "ShearBuilding"
FLOORS = range(1, MAX_STOREYS + 1)

#: the default building (see the module doc)
DEFAULT_STOREYS, DEFAULT_FLOOR_M, DEFAULT_STOREY_K = 3, FLOOR_MASS, STOREY_STIFFNESS

PARAMETERS = (
    ("storeys", Integer, DEFAULT_STOREYS, None, 1, MAX_STOREYS, f"number of storeys, 1..{MAX_STOREYS}", False),
    *((f"floor[{k}].m", Real, DEFAULT_FLOOR_M, "kg", 0.0, None, f"mass of floor {k} (> 0; ignored beyond storeys)",
       False) for k in FLOORS),
    *((f"storey[{k}].k", Real, DEFAULT_STOREY_K, "N/m", 0.0, None,
       f"stiffness of storey {k}, joining floor {k - 1} to floor {k} (> 0; ignored beyond storeys)", False)
      for k in FLOORS),
    ("zeta_s", Real, 0.0, "1", 0.0, 1.0, "damping ratio of every mode (classical modal damping), [0, 1)", False),
)

INPUTS = (
    ("a_g", 0.0, "m/s2", "ground acceleration, held over each step"),
    *((f"F[{k}]", 0.0, "N", f"horizontal force on floor {k}, held over each step") for k in FLOORS),
    *((f"J[{k}]", 0.0, "N.s", f"impulse on floor {k} at time t_J[{k}] inside the coming step (0: none)")
      for k in FLOORS),
    *((f"t_J[{k}]", 0.0, "s", f"time of the impulse J[{k}] (clamped into the coming step)") for k in FLOORS),
)

COMPUTED = (
    *((f"floor[{k}].x", Real, "m", f"displacement of floor {k} relative to the ground", True, ()) for k in FLOORS),
    *((f"floor[{k}].v", Real, "m/s", f"velocity of floor {k} relative to the ground", True, ()) for k in FLOORS),
    *((f"floor[{k}].a", Real, "m/s2", f"absolute acceleration of floor {k}, (M^-1 (F - C x' - K x))_{k}", True,
       (f"F[{k}]",)) for k in FLOORS),
    ("energy", Real, "J", "kinetic and strain energy of the floors (relative motion)", False, ()),
    ("base_shear", Real, "N", "force of the building on the ground (storey 1's spring and the dashpots' "
                              "ground reaction)", False, ()),
)

_ZEROS = (0.0,) * MAX_STOREYS


class ShearBuilding(ComponentSlave):
    """A linear shear building with classical modal damping, exact for held inputs."""

    PARAMETERS = PARAMETERS
    INPUTS = INPUTS
    COMPUTED = COMPUTED

    author = "pidamper developers"
    description = ("Linear shear building (lumped floor masses, storey stiffnesses, classical modal damping), "
                   "exact modal closed form for held forces, ground acceleration and floor impulses")
    version = f"{VERSION}+{SOURCE_HASH}"
    license = "MIT"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=10.0, step_size=0.001)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.guid = uuid.uuid5(uuid.NAMESPACE_URL, f"pidamper/{MODEL}/" + SOURCE_HASH)
        self._names = ([f"F[{k}]" for k in FLOORS], [f"J[{k}]" for k in FLOORS], [f"t_J[{k}]" for k in FLOORS])

    def _build_core(self):
        values = self._values
        n = values["storeys"]
        if type(n) is not int or not 1 <= n <= MAX_STOREYS:
            raise ParameterError("storeys", n, f"it must be an integer in 1..{MAX_STOREYS}")
        building = make_building(
            [values[f"floor[{k}].m"] for k in range(1, n + 1)], [values[f"storey[{k}].k"] for k in range(1, n + 1)],
            values["zeta_s"])
        return ShearMotion(building, t0=self._t0)

    def _forces(self, n):
        values = self._values
        return [values[name] for name in self._names[0][:n]]

    def _advance(self, core, t_end):
        values = self._values
        n = core.n
        names_j, names_t = self._names[1], self._names[2]
        impulses = [(values[names_t[k]], k, values[names_j[k]]) for k in range(n) if values[names_j[k]] != 0.0]
        core.advance(t_end, self._forces(n), values["a_g"], impulses)

    def _computed(self, core):
        n = core.n
        x, v = core.floors()
        a = core.absolute_accelerations(self._forces(n), x, v)
        pad = _ZEROS[n:]
        return (*x, *pad, *v, *pad, *a, *pad, core.b.energy(x, v), core.b.base_shear(x, v))
