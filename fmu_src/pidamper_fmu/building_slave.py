"""ShearBuilding<N> (N = 1..10): a shear building alone, exact for held inputs (a thin adapter over
pidamper_physics.yielding.building_motion: ShearMotion, or YieldingMotion when a storey can yield;
conventions of adapter.py / slave.py).

Parameters floor[k].m, storey[k].k, storey[k].h (k = 1..N), zeta_s (classical modal damping: every
mode at this ratio), the storeys' yielding, P-Delta and collapse, and drift_limit (storey_tables.py:
a collapse and a drift ratio beyond drift_limit are warned about through the FMI logger, as in
DampedShearBuilding<N>).  Inputs a_g (ground acceleration), F[k] (force on floor k), and for an
impulse-aware host J[k], t_J[k]: an impulse J[k] on floor k at time t_J[k] inside the coming step
(ignored when J[k] = 0; a t_J[k] outside the step is clamped into it: a host that passes it a step
late, such as a Jacobi master, has it applied at the step's start).  Outputs floor[k].x, floor[k].v
(relative to the ground) and floor[k].a, the absolute acceleration x_k'' + a_g =
(M^-1 (F - C x' - K x))_k (direct feedthrough from F[k], none from a_g), storey[k].drift_ratio and
the running maxima storey[k].drift_ratio_max, floor[k].v_abs_max, floor[k].a_abs_max located
exactly inside fmi2DoStep (pidamper_physics.peaks; an impulse's velocity jump counts on both sides).
Locals: energy, base_shear.

Defaults: 1e5 kg floors and 8e7 N/m storeys of 3 m (three storeys: first period 0.4992 s, modes
0.499, 0.178, 0.123 s), no damping.  One class per storey count, each defined once here (see
damped_building_slave.py).
"""
import uuid
from pythonfmu import Real
from pythonfmu.default_experiment import DefaultExperiment

from pidamper_physics.imk_storeys import check_storey_law, imk_tables
from pidamper_physics.params import FLOOR_MASS, MAX_STOREYS, STOREY_HEIGHT, STOREY_STIFFNESS
from pidamper_physics.shear_motion import ShearMotion
from pidamper_physics.storeys import GRAVITY
from pidamper_physics.yielding import building_motion

from .adapter import ComponentSlave
from .common import Refusal
from .storey_tables import drift_monitor, imk_entries, yielding_outputs, yielding_parameters

SOURCE_HASH = "development"  # replaced by build_fmu with a hash of the shipped sources
VERSION = "0.1.0"

MODEL = "ShearBuilding"


def tables(n):
    """(PARAMETERS, INPUTS, COMPUTED) of the n-storey building (adapter.py's conventions)."""
    floors = range(1, n + 1)
    parameters = (
        *((f"floor[{k}].m", Real, FLOOR_MASS, "kg", 0.0, None, f"mass of floor {k} (> 0)", False) for k in floors),
        *((f"storey[{k}].k", Real, STOREY_STIFFNESS, "N/m", 0.0, None,
           f"stiffness of storey {k}, joining floor {k - 1} to floor {k} (> 0)", False) for k in floors),
        *((f"storey[{k}].h", Real, STOREY_HEIGHT, "m", 0.0, None,
           f"height of storey {k} (> 0): its drift ratio is its drift / h", False) for k in floors),
        ("zeta_s", Real, 0.0, "1", 0.0, 1.0, "damping ratio, [0, 1), of every elastic mode (P-Delta included) or of "
                                              "the two Rayleigh modes, as `damping` chooses", False),
        *(row + (False,) for row in yielding_parameters(n)),
        ("g", Real, GRAVITY, "m/s2", 0.0, None, "gravitational acceleration of P-Delta's gravity loads (> 0)", False),
    )
    inputs = (
        ("a_g", 0.0, "m/s2", "ground acceleration, held over each step"),
        *((f"F[{k}]", 0.0, "N", f"horizontal force on floor {k}, held over each step") for k in floors),
        *((f"J[{k}]", 0.0, "N.s", f"impulse on floor {k} at time t_J[{k}] inside the coming step (0: none)")
          for k in floors),
        *((f"t_J[{k}]", 0.0, "s", f"time of the impulse J[{k}] (clamped into the coming step)") for k in floors),
    )
    located = "since the start of the run, located exactly between the communication points"
    computed = (
        *((f"floor[{k}].x", Real, "m", f"displacement of floor {k} relative to the ground", True, ()) for k in floors),
        *((f"floor[{k}].v", Real, "m/s", f"velocity of floor {k} relative to the ground", True, ()) for k in floors),
        *((f"floor[{k}].a", Real, "m/s2", f"absolute acceleration of floor {k}, (M^-1 (F - C x' - K x))_{k}", True,
           (f"F[{k}]",)) for k in floors),
        *((f"storey[{k}].drift_ratio", Real, "1", f"drift ratio of storey {k}: its drift / storey[{k}].h", True, ())
          for k in floors),
        *((f"storey[{k}].drift_ratio_max", Real, "1", f"largest |drift ratio| of storey {k} {located}", True, ())
          for k in floors),
        *((f"floor[{k}].v_abs_max", Real, "m/s", f"largest |absolute velocity| of floor {k} {located} (both sides "
           "of an impulse)", True, ()) for k in floors),
        *((f"floor[{k}].a_abs_max", Real, "m/s2", f"largest |absolute acceleration| of floor {k} {located} (its "
           "regular part: an impulse's velocity jump is no acceleration)", True, ()) for k in floors),
        *((name, kind, unit, desc, True, ()) for name, kind, unit, desc in yielding_outputs(n)),
        ("energy", Real, "J", "kinetic and strain energy of the floors (relative motion; P-Delta potential "
                              "included)", False, ()),
        ("energy_viscous", Real, "J", "energy taken by the dashpots so far", False, ()),
        ("work_in", Real, "J", "work of the forces, the ground's inertia loads and the impulses so far (relative "
                               "motion)", False, ()),
        ("base_shear", Real, "N", "force of the building on the ground (storey 1's spring and the dashpots' "
                                  "ground reaction)", False, ()),
    )
    return parameters, inputs, computed


class ShearBuildingSlave(ComponentSlave):
    """A linear shear building of STOREYS storeys with classical modal damping, exact for held inputs."""

    STOREYS = 1
    author = "pidamper developers"
    version = f"{VERSION}+{SOURCE_HASH}"
    license = "MIT"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=10.0, step_size=0.001)

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        cls.PARAMETERS, cls.INPUTS, cls.COMPUTED = tables(cls.STOREYS)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.guid = uuid.uuid5(uuid.NAMESPACE_URL, f"pidamper/{type(self).__name__}/" + SOURCE_HASH)
        n = self.STOREYS
        self._drift = None  # the DriftMonitor of drift_limit, made with the core
        self._names = ([f"F[{k}]" for k in range(1, n + 1)], [f"J[{k}]" for k in range(1, n + 1)],
                       [f"t_J[{k}]" for k in range(1, n + 1)])
        self._loads = None  # (forces, impulses) of the inputs as they are: _held_loads()

    def _build_core(self):
        values, n = self._values, self.STOREYS
        m, k, h, fy, b = ([values[pattern.format(i)] for i in range(1, n + 1)] for pattern in
                          ("floor[{}].m", "storey[{}].k", "storey[{}].h", "storey[{}].Fy", "storey[{}].b"))
        imk = imk_tables(k, fy, imk_entries(values, n)) if check_storey_law(values["storey_law"]) else None
        core = building_motion(m, k, h, values["zeta_s"], fy, b, values["p_delta"], values["g"],
                               values["collapse_drift"], t0=self._t0, damping=values["damping"], imk=imk)
        self._drift = drift_monitor(values["drift_limit"])
        if not isinstance(core, ShearMotion):  # yielding storeys: they may collapse
            core.on_collapse = self._collapsed
        return core

    def _get_fmu_state(self):
        state = super()._get_fmu_state()
        if state is not None:  # the drift warning, once per run
            state["_drift_warned"] = self._drift is not None and self._drift.warned
        return state

    def _restore(self, state):
        self._loads = None
        if isinstance(state, dict):
            state = dict(state)
            warned = state.pop("_drift_warned", None)
            if type(warned) is not bool:
                raise Refusal(f"FMU state _drift_warned = {warned!r} is not allowed: true or false")
        super()._restore(state)
        if self._initialized and self._drift is not None:
            self._drift.warned = warned

    def _input_changed(self, old, value):
        super()._input_changed(old, value)
        self._loads = None

    def _held_loads(self):
        """(the floor forces [N], the impulses (t_J [s], floor index, J [N s]) with J != 0) of the
        inputs as they are, made once until an input is set."""
        loads = self._loads
        if loads is None:
            values = self._values
            forces, impulses, times = ([values[name] for name in names] for names in self._names)
            loads = self._loads = (forces, [(times[k], k, j) for k, j in enumerate(impulses) if j != 0.0])
        return loads

    def _advance(self, core, t_end):
        forces, impulses = self._held_loads()
        core.advance(t_end, forces, self._values["a_g"], impulses)
        if self._drift is not None:
            warning = self._drift.check(core.t, core.peaks)
            if warning:
                self._warn(warning)

    def _computed(self, core):
        return core.observables(self._held_loads()[0])


def _model(n):
    return type(f"{MODEL}{n}", (ShearBuildingSlave,), {
        "STOREYS": n,
        "__doc__": f"A linear {n}-storey shear building with classical modal damping, exact for held inputs.",
        "__module__": __name__,
        "description": (f"Linear {n}-storey shear building (lumped floor masses, storey stiffnesses, classical modal "
                        "damping), exact modal closed form for held forces, ground acceleration and floor impulses, "
                        "with its peaks located inside doStep"),
    })


for _n in range(1, MAX_STOREYS + 1):
    globals()[f"{MODEL}{_n}"] = _model(_n)
del _n
