"""PendulumImpactDamper: a pythonfmu Fmi2Slave that is a thin adapter over Damper.

Variables (names are a contract): inputs F [N] and a_g [m/s2] (ground acceleration of a
base excitation: it acts on both bodies, whose x and y are then measured from the ground); parameters
g, M, mu, L2, FR, d, d_angle, e (tunable), contact_form, F0, Omega, phi, fidelity, zeta_s, zeta_p,
angle_limit and the initial state theta_0, theta_dot_0, alpha_0, alpha_dot_0, and a building's
storeys, damper_floor, floor[k].m, storey[k].k (k = 1..10); outputs theta, theta_dot, alpha,
alpha_dot, a, contact_force, energy, energy_dissipated, impacts, contact, floor[k].x, floor[k].a,
storey[k].drift, base_shear; local variables x, y, z, energy_viscous, work_in, impacts_in_step,
impacts_unrecorded and impact[k].* (the impacts of the last step).  With storeys >= 1 the F input
acts on the damper floor and the building starts at rest (theta_0 and theta_dot_0 play no part).

The FMU's native layer (fmi2_entry.c, binaries/linux64/<id>.so) sits in front of pythonfmu's binary:
it enforces the calling sequence and answers reads from a buffer this class fills after each step
(_push; the buffer is the model's own, handed to the layer by a direct call: common.py).  Bad input (invalid
parameter, non-finite input, inconsistent step) is refused with a message naming the variable, its
value and what is allowed, logged at error level: the layer then answers fmi2Error.  No exception
reaches pythonfmu (it would answer fmi2Fatal and release Python objects it still uses); without the
layer (a build with no C compiler) the exception propagates as before.  A swing beyond angle_limit
(the small-angle validity of the linear model) is logged once per run at warning level.
"""
import math
import struct
import uuid

from pythonfmu import Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.enums import Fmi2Status
from pythonfmu.default_experiment import DefaultExperiment

from pidamper_physics import DEFAULTS, INITIAL_DEFAULTS, Damper, ParameterError, Params, SmallAngleMonitor
from pidamper_physics.params import (FLOOR_MASS, MAX_STOREYS, NONLINEAR, STOREY_STIFFNESS, check_finite,
                                     check_restitution)

from .common import FmiEntry, Refusal, describe, fmi_text, guarded

SOURCE_HASH = "development"  # replaced by build_fmu with a hash of the shipped sources
VERSION = "0.1.0"

_START = {**DEFAULTS, **INITIAL_DEFAULTS, "angle_limit": SmallAngleMonitor.DEFAULT_LIMIT,
          **{f"floor[{k}].m": FLOOR_MASS for k in range(1, MAX_STOREYS + 1)},
          **{f"storey[{k}].k": STOREY_STIFFNESS for k in range(1, MAX_STOREYS + 1)}}

# name, unit, description: held over each communication step
INPUTS = (("F", "N", "horizontal force on the primary mass (storeys >= 1: on the damper floor)"),
          ("a_g", "m/s2", "ground acceleration of a base excitation (acts on both bodies)"))

# name, type, start, unit, min, max, description
PARAMETERS = tuple((name, kind, _START[name], unit, lo, hi, desc) for name, kind, unit, lo, hi, desc in (
    ("g", Real, "m/s2", 0.0, None, "gravitational acceleration (> 0)"),
    ("M", Real, "kg", 0.0, None, "primary mass (> 0)"),
    ("mu", Real, "1", 0.0, None, "mass ratio m/M (>= 0; 0 = no damper)"),
    ("L2", Real, "m", 0.0, None, "primary pendulum length (> 0)"),
    ("FR", Real, "1", 0.0, None, "frequency ratio w1/w2 (> 0); particle length L1 = L2/FR^2"),
    ("d", Real, "m", 0.0, None, "clearance, displacement form: contact at x - y = +-d (> 0)"),
    ("d_angle", Real, "rad", 0.0, None, "clearance, angle form: contact at theta - alpha = +-d_angle (> 0)"),
    ("e", Real, "1", 0.0, 1.0, "coefficient of restitution in [0, 1] (tunable)"),
    ("contact_form", Integer, None, 0, 1, "0 = displacement form (default), 1 = angle form as printed in the paper"),
    ("F0", Real, "N", None, None, "amplitude of the built-in harmonic force F0 sin(Omega t + phi)"),
    ("Omega", Real, "rad/s", 0.0, None, "frequency of the built-in harmonic force (>= 0)"),
    ("phi", Real, "rad", None, None, "phase of the built-in harmonic force"),
    ("theta_0", Real, "rad", None, None, "initial primary angle"),
    ("theta_dot_0", Real, "rad/s", None, None, "initial primary angular velocity"),
    ("alpha_0", Real, "rad", None, None, "initial particle angle"),
    ("alpha_dot_0", Real, "rad/s", None, None, "initial particle angular velocity"),
    ("fidelity", Integer, None, 0, 3, "model level: 0 linear (the paper), 1 damped (+ dashpots zeta_s, zeta_p), "
                                       "2 coupled (particle hung from the moving primary), 3 nonlinear (large angles)"),
    ("zeta_s", Real, "1", 0.0, 1.0, "viscous damping ratio of the primary, dashpot 2 zeta_s M w2 (fidelity >= 1; < 1)"),
    ("zeta_p", Real, "1", 0.0, 1.0, "viscous damping ratio of the particle relative to its pivot, dashpot "
                                    "2 zeta_p m w1 (fidelity >= 1; < 1)"),
    ("angle_limit", Real, "rad", 0.0, None, "swing beyond which the linear (small-angle) model warns, once per run "
                                            "(0.4 rad: its frequency is then 1 % off; 0 = never)"),
    ("storeys", Integer, None, 0, MAX_STOREYS, "0 = the pendulum primary; 1..10 = a linear shear building of that many "
                                               "storeys instead (floor[k].m, storey[k].k; M, L2 play no part)"),
    ("damper_floor", Integer, None, 0, MAX_STOREYS, "floor the particle hangs from (0 = the top floor; else 1..storeys)"),
) + tuple((f"floor[{k}].m", Real, "kg", 0.0, None, f"mass of floor {k} (storeys >= {k})")
          for k in range(1, MAX_STOREYS + 1)) + tuple(
    (f"storey[{k}].k", Real, "N/m", 0.0, None, f"stiffness of storey {k}, joining floor {k - 1} to floor {k} "
                                               f"(storeys >= {k})") for k in range(1, MAX_STOREYS + 1)))

# name, type, unit, description, direct feedthrough from F.  The outputs are the component's
# interface (what a host records by default and connects); the derived and bookkeeping values are
# local variables a host reads by name.  Both are computed together after each step and have
# consecutive value references in this order, so one pack fills them all.
OUTPUTS = (
    ("theta", Real, "rad", "primary angle (storeys >= 1: the damper floor's x / L2, L2 = g / w_1^2 the pendulum of "
                           "the building's first frequency w_1)", False),
    ("theta_dot", Real, "rad/s", "primary angular velocity (storeys >= 1: the damper floor's velocity / L2)", False),
    ("alpha", Real, "rad", "particle angle (of its wire from the vertical; storeys >= 1: (y - x) / L1, its pivot "
                           "on the damper floor)", False),
    ("alpha_dot", Real, "rad/s", "particle angular velocity", False),
    ("a", Real, "m/s2", "primary acceleration between impacts, relative to the ground (storeys >= 1: the damper "
                        "floor's)", True),
    ("contact_force", Real, "N", "force of the stop on the particle while riding it, else 0", True),
    ("energy", Real, "J", "mechanical energy of the level's model (linear: 0.5 M (v^2 + w2^2 x^2) + 0.5 m (u^2 + w1^2 y^2); "
                          "storeys >= 1: the floors' kinetic and strain energy + 0.5 m (u^2 + w1^2 (y - x)^2))", False),
    ("energy_dissipated", Real, "J", "energy dissipated by impacts so far", False),
    ("impacts", Integer, None, "impacts applied so far (chatter impacts included)", False),
    ("contact", Integer, None, "0 free, +1/-1 particle riding that stop", False),
)
# a building's outputs (storeys >= 1; zeros without a building): last, so that a step of the pendulum
# primary packs only OUTPUTS and DERIVED into the native layer's buffer
BUILDING = tuple((f"floor[{k}].x", Real, "m", f"displacement of floor {k} relative to the ground (0 beyond storeys)", False)
          for k in range(1, MAX_STOREYS + 1)) + tuple(
    (f"floor[{k}].a", Real, "m/s2", f"absolute acceleration of floor {k} (0 beyond storeys)", True)
    for k in range(1, MAX_STOREYS + 1)) + tuple(
    (f"storey[{k}].drift", Real, "m", f"drift of storey {k}: floor[{k}].x - floor[{k - 1}].x (0 beyond storeys)", False)
    for k in range(1, MAX_STOREYS + 1)) + (
    ("base_shear", Real, "N", "force of the building on the ground (sum of K x + C x'; 0 without a building)", False),)
DERIVED = (
    ("x", Real, "m", "primary displacement (linear levels: L2*theta; nonlinear: L2 sin(theta); storeys >= 1: the "
                     "damper floor's, relative to the ground)", False),
    ("y", Real, "m", "particle displacement (linear, damped: L1*alpha; coupled: x + L1*alpha; nonlinear: "
                     "x + L1 sin(alpha))", False),
    ("z", Real, "m", "gap x - y", False),
    ("energy_viscous", Real, "J", "energy taken by the viscous dashpots so far (fidelity >= 1)", False),
    ("work_in", Real, "J", "work done by the applied forces so far, integral of F v dt", False),
    ("impacts_in_step", Integer, None, "impacts applied during the last communication step", False),
    ("impacts_unrecorded", Integer, None,
     "impacts of the last step beyond the 16 record slots (counted, not recorded)", False),
)
COMPUTED = OUTPUTS + DERIVED + BUILDING
_NO_BUILDING = (0.0,) * len(BUILDING)  # the building's outputs without a building
_PAD = [(0.0,) * (MAX_STOREYS - n) for n in range(MAX_STOREYS + 1)]

# Per-step impact record: local variables (hosts do not record them by default; any host reads them
# by name after fmi2DoStep).  Slots beyond impacts_in_step hold zeros.  The Real fields of all slots
# come first (slot-major), then the sides.
IMPACT_SLOTS = 16
IMPACT_REALS = (
    ("t", "s", "time"),
    ("v_rel_before", "m/s", "particle minus primary velocity before"),
    ("v_rel_after", "m/s", "particle minus primary velocity after"),
    ("energy_lost", "J", "energy lost"),
    ("theta", "rad", "primary angle"),
)
RECORD = tuple((f"impact[{k + 1}].{field}", Real, unit, f"impact {k + 1} of the last step: {desc}")
               for k in range(IMPACT_SLOTS) for field, unit, desc in IMPACT_REALS) + tuple(
    (f"impact[{k + 1}].side", Integer, None, f"impact {k + 1} of the last step: stop hit, +1 (z = +d) or -1 (z = -d)")
    for k in range(IMPACT_SLOTS))
NR = len(IMPACT_REALS)

# the native layer's buffer is a double per value reference (Integer values too, the layer converts
# them): the outputs, and the record, each have consecutive value references, so one pack fills each
_PACK_COMPUTED = struct.Struct(f"={len(COMPUTED)}d")
_PACK_PENDULUM = struct.Struct(f"={len(OUTPUTS) + len(DERIVED)}d")
_PACK_BUILDING = struct.Struct(f"={len(BUILDING)}d")
_PACK_RECORD = struct.Struct(f"={len(RECORD)}d")
_ZERO_RECORD = (0.0,) * (NR * IMPACT_SLOTS) + (0,) * IMPACT_SLOTS
_STATE_KEYS = frozenset([name for name, *_ in PARAMETERS]
                        + ["F", "a_g", "_t0", "_initialized", "_core", "_in_step", "_record", "_monitor"])
class PendulumImpactDamper(FmiEntry, Fmi2Slave):
    """Pendulum-type particle impact damper, exact event-driven co-simulation."""

    author = "pidamper developers"
    description = ("Pendulum-type particle impact damper: primary pendulum and hanging particle, "
                   "linearised, exact event-driven motion (impacts, chatter, sticking located inside doStep)")
    version = f"{VERSION}+{SOURCE_HASH}"  # changes with the shipped sources, like the GUID
    license = "MIT"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=20.0, step_size=0.01)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.guid = uuid.uuid5(uuid.NAMESPACE_URL, "pidamper/PendulumImpactDamper/" + SOURCE_HASH)
        self._initialized = False
        self._core = None
        self._monitor = None
        self._native = False  # the native layer attached its buffer (see _attach)
        self._buffer = None
        self.F = 0.0
        self.a_g = 0.0
        for name, unit, desc in INPUTS:
            self.register_variable(Real(name, causality=Fmi2Causality.input, variability=Fmi2Variability.continuous,
                                        description=desc, setter=self._input_setter(name)))
        for name, kind, start, *_ in PARAMETERS:
            setattr(self, name, start)
            tunable = name == "e"
            self.register_variable(kind(
                name, causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.tunable if tunable else Fmi2Variability.fixed,
                getter=(lambda name=name: getattr(self, name)), setter=self._setter(name, tunable)), nested=False)
        for k, (name, kind, *_) in enumerate(COMPUTED):
            derived = len(OUTPUTS) <= k < len(OUTPUTS) + len(DERIVED)
            causality = Fmi2Causality.local if derived else Fmi2Causality.output
            self._register_computed(name, kind, causality, self._output_getter(k))
        self._record_values = list(_ZERO_RECORD)  # slot-major Real fields, then the sides
        self._in_step = 0
        self._record_in_buffer = True  # the buffer may hold a non-zero record: write it at the next push
        for k, (name, kind, *_) in enumerate(RECORD):
            self._register_computed(name, kind, Fmi2Causality.local, (lambda k=k: self._record_values[k]))
        self._register_link()
        vr = {var.name: vr for vr, var in self.vars.items()}
        self._offsets = (8 * vr[OUTPUTS[0][0]], 8 * vr[RECORD[0][0]])

    def _input_setter(self, name):
        """fmi2SetReal of an input: a value that is not finite is refused there, before any step."""
        def set_input(value):
            if value - value != 0.0:
                self._fail(name, value, "the input must be finite")
            setattr(self, name, value)
        return set_input

    def _register_computed(self, name, kind, causality, getter):
        self.register_variable(kind(name, causality=causality, initial=Fmi2Initial.calculated,
                                    variability=Fmi2Variability.continuous if kind is Real
                                    else Fmi2Variability.discrete, getter=getter))

    def _output_getter(self, k):
        return lambda: self._outputs()[k]

    # ---- the native layer's buffer ----------------------------------------------------

    def _attached(self):
        """The native layer's buffer is in place: the record and the building's zeros go in."""
        self._record_in_buffer = True
        self._clear_building()

    def _push(self, core):
        """Write every output, and the impact record when it changed, into the native layer's buffer."""
        buffer = self._buffer
        off_outputs, off_record = self._offsets
        if core.p.storeys:
            _PACK_COMPUTED.pack_into(buffer, off_outputs, *self._outputs(core))
        else:  # the building's zeros are in the buffer already (_clear_building)
            _PACK_PENDULUM.pack_into(buffer, off_outputs, *self._pendulum_outputs(core))
        if self._in_step or self._record_in_buffer:
            _PACK_RECORD.pack_into(buffer, off_record, *self._record_values)
            self._record_in_buffer = self._in_step > 0

    def _outputs(self, c=None):
        """The values of COMPUTED in its order (of core `c`, default the current one)."""
        if c is None:
            c = self._core_now()
        return self._pendulum_outputs(c) + (self._building_outputs(c) if c.p.storeys else _NO_BUILDING)

    def _pendulum_outputs(self, c):
        """The values of OUTPUTS and DERIVED in their order."""
        theta, theta_dot, alpha, alpha_dot, x, y, a, contact_force = c.observables(self.F, self.a_g)
        n = self._in_step
        return (theta, theta_dot, alpha, alpha_dot, a, contact_force, c.energy, c.dissipated, c.impacts, c.contact,
                x, y, x - y, c.viscous, c.work_in, n, n - IMPACT_SLOTS if n > IMPACT_SLOTS else 0)

    def _clear_building(self):
        """Zeros for the building's outputs in the native layer's buffer (a step packs them only
        when there is a building)."""
        if self._native:
            _PACK_BUILDING.pack_into(self._buffer, self._offsets[0] + 8 * (len(OUTPUTS) + len(DERIVED)), *_NO_BUILDING)

    def _building_outputs(self, c):
        """floor[k].x, floor[k].a, storey[k].drift (zeros beyond storeys) and base_shear."""
        xs, accs, drifts, shear = c.building_outputs(self.F, self.a_g)
        pad = _PAD[len(xs)]
        return tuple(xs) + pad + tuple(accs) + pad + tuple(drifts) + pad + (shear,)

    # ---- per-step impact record -------------------------------------------------------

    def _record(self, t, side, v_rel_before, v_rel_after, loss):
        """Core callback, once per impact: fill the next slot (the count goes on past the last)."""
        n = self._in_step
        if n < IMPACT_SLOTS:
            j = NR * n
            record = self._record_values
            record[j:j + NR] = (t, v_rel_before, v_rel_after, loss, self._core.angles()[0])
            record[NR * IMPACT_SLOTS + n] = side
        self._in_step = n + 1

    def _clear_record(self):
        if self._in_step:
            self._record_values[:] = _ZERO_RECORD
            self._in_step = 0

    # ---- parameters -----------------------------------------------------------------

    def _setter(self, name, tunable):
        def set_value(value):
            if self._initialized and not tunable:
                if value == getattr(self, name):
                    return  # the same value again (hosts that set every parameter after initialization)
                self._fail(name, value, f"it is a fixed parameter (now {getattr(self, name)!r}) and cannot "
                                        "change after initialization")
            if tunable and self._initialized:
                try:
                    value = check_restitution(value)
                except ParameterError as err:
                    self._fail(err.name, err.value, err.allowed)
                self._core.set_restitution(value)
            setattr(self, name, value)
            if not self._initialized:
                self._core = None
        return set_value

    def _build_core(self):
        params = Params.from_variables({name: getattr(self, name) for name, *_ in PARAMETERS})
        core = Damper(params, self.theta_0, self.theta_dot_0, self.alpha_0, self.alpha_dot_0, self._t0)
        core.on_impact = self._record
        core.bound_work()  # fmi2DoStep cannot be interrupted: a step's work is capped
        self._clear_building()
        limit = self.angle_limit
        if not (math.isfinite(limit) and limit >= 0.0):
            raise ParameterError("angle_limit", limit, "it must be finite and >= 0 (0 turns the warning off)")
        small_angles = params.fidelity != NONLINEAR  # the nonlinear level has no small-angle limit
        self._monitor = SmallAngleMonitor(params, limit) if limit > 0.0 and small_angles else None
        return core

    # ---- FMI calls ------------------------------------------------------------------

    def _step(self, current_time, step_size):
        core = self._core
        if core is None or not self._initialized:
            raise Refusal("fmi2DoStep is not allowed before fmi2ExitInitializationMode")
        t = core.t
        force, ground = self.F, self.a_g
        total = current_time + step_size + force + ground
        if total - total != 0.0 or step_size < 0.0:  # some value is not finite (or a sum overflowed)
            self._check_step(current_time, step_size, force, ground)
        self._check_time(current_time, t, step_size)
        if self._in_step:
            self._clear_record()
        core.advance(max(current_time + step_size, t), force, ground)
        monitor = self._monitor
        if monitor is not None:
            warning = monitor.check(core)
            if warning:
                self._warn(warning)
        if self._native:
            self._push(core)

    def _check_step(self, current_time, step_size, force, ground):
        """Refuse a step that is not finite or goes back, or a non-finite input, naming it."""
        if not (math.isfinite(current_time) and math.isfinite(step_size)) or step_size < 0.0:
            self._fail("communicationStepSize", step_size,
                       f"the step from {current_time!r} must be finite and >= 0 (no step back in time)")
        if not math.isfinite(force):
            self._fail("F", force, "the input must be finite")
        if not math.isfinite(ground):
            self._fail("a_g", ground, "the input must be finite")

    @guarded(lambda args: None)
    def terminate(self):
        summary = self._monitor.summary() if self._monitor is not None and self._initialized else None
        if summary:
            self._warn(summary)

    def _warn(self, text):
        self.log(fmi_text(f"{self.instance_name}: {text}", self._native), Fmi2Status.warning)

    # ---- FMU state ------------------------------------------------------------------

    @guarded(lambda args: None)
    def _get_fmu_state(self):
        state = {name: getattr(self, name) for name, *_ in PARAMETERS}
        state["F"] = self.F
        state["a_g"] = self.a_g
        state["_t0"] = self._t0
        state["_initialized"] = self._initialized
        state["_core"] = self._core.get_state() if self._initialized else None
        state["_in_step"] = self._in_step
        state["_record"] = list(self._record_values)
        monitor = self._monitor if self._initialized else None
        state["_monitor"] = None if monitor is None else monitor.get_state()
        return state

    def _restore(self, state):
        if not isinstance(state, dict) or set(state) != _STATE_KEYS:
            got = sorted(state) if isinstance(state, dict) else type(state).__name__
            raise Refusal(f"FMU state = {got!r} is not allowed: a state of this model has exactly the keys "
                          f"{sorted(_STATE_KEYS)}")
        for name in ("F", "a_g", "_t0"):
            check_finite(f"FMU state {name}", state[name])
        record = state["_record"]
        if (not isinstance(record, list) or len(record) != len(_ZERO_RECORD)
                or type(state["_in_step"]) is not int or state["_in_step"] < 0):
            raise Refusal(f"FMU state _record, _in_step = {record!r}, {state['_in_step']!r} is not allowed: "
                          f"{len(_ZERO_RECORD)} numbers and an integer >= 0")
        for k, value in enumerate(record):
            check_finite(f"FMU state _record[{k}]", value)
        for name, *_ in PARAMETERS:
            setattr(self, name, state[name])
        self.F = state["F"]
        self.a_g = state["a_g"]
        self._t0 = state["_t0"]
        self._initialized = bool(state["_initialized"])
        self._in_step = state["_in_step"]
        self._record_values[:] = record
        self._record_in_buffer = True
        self._core = None
        if self._initialized:
            core = self._core_now()
            core.set_state(dict(state["_core"]))
            monitor = state["_monitor"]
            if self._monitor is not None and monitor is not None:
                if not (isinstance(monitor, list) and len(monitor) == 3):
                    raise Refusal(f"FMU state _monitor = {monitor!r} is not allowed: [warned, bar, bar]")
                bars = monitor[1:]  # squared swings; inf stands for "never" (a particle without mass)
                if not all(isinstance(v, (int, float)) and not isinstance(v, bool) and v == v for v in bars):
                    raise Refusal(f"FMU state _monitor = {monitor!r} is not allowed: two numbers after the flag")
                self._monitor.set_state([bool(monitor[0])] + [float(v) for v in bars])

    # ---- modelDescription -----------------------------------------------------------

    def to_xml(self, model_options=dict()):
        """pythonfmu's description plus units, ranges, descriptions and a full ModelStructure;
        the native layer's link variable is left out (hosts never see it)."""
        root = super().to_xml(model_options)
        info = {name: (unit, lo, hi, desc) for name, _, _, unit, lo, hi, desc in PARAMETERS}
        info.update({name: (unit, None, None, desc) for name, _, unit, desc, *_ in COMPUTED + RECORD})
        info.update({name: (unit, None, None, desc) for name, unit, desc in INPUTS})
        outputs = [(name, ("F", "a_g") if feedthrough else ()) for name, _, _, _, feedthrough in OUTPUTS + BUILDING]
        return describe(root, info, outputs)
