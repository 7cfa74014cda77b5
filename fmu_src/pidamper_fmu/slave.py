"""PendulumImpactDamper, and the base of every FMU with the particle on its primary: a pythonfmu
Fmi2Slave that is a thin adapter over Damper.

PendulumImpactDamper is the paper's two-pendulum system: inputs F [N] and a_g [m/s2] (ground
acceleration of a base excitation: it acts on both bodies, whose x and y are then measured from the
ground); parameters g, M, mu, L2, FR, d, d_angle, e (tunable), contact_form, F0, Omega, phi,
fidelity, zeta_s, zeta_p, angle_limit, the initial state theta_0, theta_dot_0, alpha_0,
alpha_dot_0 and the materials (restitution, S_y, E1, nu1, E2, nu2, R, e_max: contact_tables.py);
outputs theta, theta_dot, alpha, alpha_dot, a, contact_force, energy, energy_dissipated, impacts,
contact, impact_force_peak, contact_pressure_peak, impacts_plastic; local variables x, y, z,
energy_viscous, work_in, impacts_in_step, impacts_unrecorded and impact[k].* (the impacts of the
last step, with each contact's e, peak force and pressure, duration and plastic flag).  A contact
not short against the primary's period is warned about once.  A subclass
with STOREYS = N >= 1 (damped_building_slave.py: DampedShearBuilding<N>) hangs the particle from a
floor of an N-storey shear building instead: the same names, exactly N floors' and storeys'
variables (particle_tables.py).

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

from pythonfmu import Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Real
from pythonfmu.default_experiment import DefaultExperiment

from pidamper_physics import Damper, ParameterError, Params, SmallAngleMonitor
from pidamper_physics.impact import step_outputs
from pidamper_physics.params import NONLINEAR, check_finite, check_restitution

from .common import FmiEntry, Refusal, describe, guarded, long_contact
from .particle_tables import DERIVED, IMPACT_REALS, IMPACT_SLOTS, INPUTS, OUTPUTS, RECORD, START, tables
from .storey_tables import drift_monitor

SOURCE_HASH = "development"  # replaced by build_fmu with a hash of the shipped sources
VERSION = "0.1.0"

NR = len(IMPACT_REALS)

# the native layer's buffer is a double per value reference (Integer values too, the layer converts
# them): the outputs, and the record, each have consecutive value references, so one pack fills each
_PACK_RECORD = struct.Struct(f"={len(RECORD)}d")
_ZERO_RECORD = (0.0,) * (NR * IMPACT_SLOTS) + (0,) * (2 * IMPACT_SLOTS)  # reals, sides, plastic flags
_STATE_EXTRA = ("F", "a_g", "_t0", "_initialized", "_core", "_in_step", "_record", "_monitor", "_drift_warned", "_held")


class ParticleSlave(FmiEntry, Fmi2Slave):
    """The particle on its primary (the pendulum, STOREYS = 0, or an N-storey building), exact
    event-driven co-simulation; a model class sets STOREYS and its tables (particle_tables.tables)."""

    STOREYS = 0
    PARAMETERS, COMPUTED = tables(0)
    author = "pidamper developers"
    version = f"{VERSION}+{SOURCE_HASH}"  # changes with the shipped sources, like the GUID
    license = "MIT"

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        cls.PARAMETERS, cls.COMPUTED = tables(cls.STOREYS)
        cls._PACK_COMPUTED = struct.Struct(f"={len(cls.COMPUTED)}d")
        cls._STATE_KEYS = frozenset([name for name, *_ in cls.PARAMETERS] + list(_STATE_EXTRA))

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.guid = uuid.uuid5(uuid.NAMESPACE_URL, f"pidamper/{type(self).__name__}/" + SOURCE_HASH)
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
        for name, kind, start, *_ in self.PARAMETERS:
            setattr(self, name, start)
            tunable = name == "e"
            self.register_variable(kind(
                name, causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.tunable if tunable else Fmi2Variability.fixed,
                getter=(lambda name=name: getattr(self, name)), setter=self._setter(name, tunable)), nested=False)
        for k, (name, kind, *_) in enumerate(self.COMPUTED):
            derived = len(OUTPUTS) <= k < len(OUTPUTS) + len(DERIVED)
            causality = Fmi2Causality.local if derived else Fmi2Causality.output
            self._register_computed(name, kind, causality, self._output_getter(k))
        self._record_values = list(_ZERO_RECORD)  # slot-major Real fields, then the sides and plastic flags
        self._held = None  # a collapsed building's outputs, held
        self._drift = None  # a building's DriftMonitor (drift_limit), made with the core
        self._in_step = 0
        self._validated = None  # the core whose state the validity monitors saw after its last step
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
            self._input_changed(getattr(self, name), value)
            setattr(self, name, value)
        return set_input

    def _register_computed(self, name, kind, causality, getter):
        self.register_variable(kind(name, causality=causality, initial=Fmi2Initial.calculated,
                                    variability=Fmi2Variability.continuous if kind is Real
                                    else Fmi2Variability.discrete, getter=getter))

    def _output_getter(self, k):
        return lambda: self._flat_outputs()[k]

    def _outputs_now(self):
        return self._outputs()

    # ---- the native layer's buffer ----------------------------------------------------

    def _attached(self):
        """The native layer's buffer is in place: the record goes in at the next push."""
        self._record_in_buffer = True

    def _push(self, core):
        """Write every output, and the impact record when it changed, into the native layer's buffer."""
        buffer = self._buffer
        off_outputs, off_record = self._offsets
        self._PACK_COMPUTED.pack_into(buffer, off_outputs, *self._outputs(core))
        self._pushed = core
        if self._in_step or self._record_in_buffer:
            _PACK_RECORD.pack_into(buffer, off_record, *self._record_values)
            self._record_in_buffer = self._in_step > 0

    def _outputs(self, c=None):
        """The values of COMPUTED in its order (of core `c`, default the current one); a collapsed
        building's as they were at the end of the step it collapsed in."""
        if c is None:
            c = self._core_now()
        if c.halted:
            if self._held is None:
                self._held = self._live_outputs(c)
            return self._held
        return self._live_outputs(c)

    def _live_outputs(self, c):
        force, ground = self.F, self.a_g
        theta, theta_dot, alpha, alpha_dot, x, y, a, contact_force = c.observables(force, ground)
        n = self._in_step
        out = [theta, theta_dot, alpha, alpha_dot, a, contact_force, c.energy, c.dissipated, c.impacts, c.contact,
               *step_outputs(c.contacts), x, y, x - y, c.viscous, c.work_in, n, n - IMPACT_SLOTS if n > IMPACT_SLOTS else 0]
        if self.STOREYS:  # floor[k].x, floor[k].a, storey[k].drift, base_shear, the drift ratios, the running
            out += c.building_observables(force, ground)  # maxima, the storeys' (particle_tables.building_outputs)
        return out

    # ---- per-step impact record -------------------------------------------------------

    def _record(self, t, side, v_rel_before, v_rel_after, loss):
        """Core callback, once per impact: fill the next slot (the count goes on past the last)."""
        n = self._in_step
        if n < IMPACT_SLOTS:
            j = NR * n
            core = self._core
            record = self._record_values
            if core.contacts is None:
                e, force, pressure, duration, plastic = core.e_applied, 0.0, 0.0, 0.0, False
            else:
                e, force, pressure, duration, plastic = core.contacts.hit
            record[j:j + NR] = (t, v_rel_before, v_rel_after, loss, core.angles()[0], e, force, pressure, duration)
            record[NR * IMPACT_SLOTS + n] = side
            record[(NR + 1) * IMPACT_SLOTS + n] = int(plastic)
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
        values = {name: getattr(self, name) for name, *_ in self.PARAMETERS}
        if self.STOREYS:
            values["storeys"] = self.STOREYS
        params = Params.from_variables(values)
        start = {**START, **values}  # a building has no theta_0, theta_dot_0: it starts at rest
        core = Damper(params, start["theta_0"], start["theta_dot_0"], start["alpha_0"], start["alpha_dot_0"], self._t0)
        core.on_impact = self._record
        core.on_collapse = self._collapsed
        self._held = None
        core.bound_work()  # fmi2DoStep cannot be interrupted: a step's work is capped
        limit = self.angle_limit
        if not (math.isfinite(limit) and limit >= 0.0):
            raise ParameterError("angle_limit", limit, "it must be finite and >= 0 (0 turns the warning off)")
        small_angles = params.fidelity != NONLINEAR  # the nonlinear level has no small-angle limit
        self._monitor = SmallAngleMonitor(params, limit) if limit > 0.0 and small_angles else None
        self._drift = drift_monitor(self.drift_limit) if self.STOREYS else None
        return core

    # ---- FMI calls ------------------------------------------------------------------

    def _step(self, current_time, step_size):
        core = self._core
        if core is None or not self._initialized:
            raise Refusal("fmi2DoStep is not allowed before fmi2ExitInitializationMode")
        t = core.t
        force, ground = self.F, self.a_g
        end = current_time + step_size
        total = end + force + ground
        if total - total != 0.0 or step_size < 0.0:  # some value is not finite (or a sum overflowed)
            self._check_step(current_time, step_size, force, ground)
        if current_time != t:  # (a host's rounded time: within the tolerance, accepted)
            self._check_time(current_time, t, step_size)
        if self._in_step:
            self._clear_record()
        contacts = core.contacts
        if contacts is not None:
            contacts.clear()
        validated, self._validated = self._validated, None
        core.advance(end if end >= t else t, force, ground)  # max(end, t) without the call
        if contacts is not None:
            late = contacts.news()
            if late is not None:
                self._warn(long_contact(*late))
        if core.halted and self._held is None:  # collapsed in this step: its outputs hold from here
            self._held = self._live_outputs(core)
        still = core.still  # the step changed no output (a building at rest)
        if not (still and validated is core):  # (a still step's state was checked after the last step)
            self._check_validity(core)
        self._validated = core
        if self._native and (self._record_in_buffer or not (still and self._pushed is core)):  # _buffer_holds
            self._push(core)  # (the buffer holds no impact record, the step had none: nothing to clear)

    def _check_validity(self, core):
        """Warn (once per run each) of a swing beyond angle_limit and a drift ratio beyond drift_limit."""
        monitor = self._monitor
        if monitor is not None:
            warning = monitor.check(core)
            if warning:
                self._warn(warning)
        if self._drift is not None:
            warning = self._drift.check(core.t, core.model.peaks)
            if warning:
                self._warn(warning)

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

    # ---- FMU state ------------------------------------------------------------------

    @guarded(lambda args: None)
    def _get_fmu_state(self):
        state = {name: getattr(self, name) for name, *_ in self.PARAMETERS}
        state["F"] = self.F
        state["a_g"] = self.a_g
        state["_t0"] = self._t0
        state["_initialized"] = self._initialized
        state["_core"] = self._core.get_state() if self._initialized else None
        state["_in_step"] = self._in_step
        state["_record"] = list(self._record_values)
        monitor = self._monitor if self._initialized else None
        state["_monitor"] = None if monitor is None else monitor.get_state()
        state["_drift_warned"] = self._initialized and self._drift is not None and self._drift.warned
        state["_held"] = None if self._held is None else list(self._held)  # a collapsed building's outputs
        return state

    def _restore(self, state):
        if not isinstance(state, dict) or set(state) != self._STATE_KEYS:
            got = sorted(state) if isinstance(state, dict) else type(state).__name__
            raise Refusal(f"FMU state = {got!r} is not allowed: a state of this model has exactly the keys "
                          f"{sorted(self._STATE_KEYS)}")
        for name in ("F", "a_g", "_t0"):
            check_finite(f"FMU state {name}", state[name])
        record = state["_record"]
        if (not isinstance(record, list) or len(record) != len(_ZERO_RECORD)
                or type(state["_in_step"]) is not int or state["_in_step"] < 0):
            raise Refusal(f"FMU state _record, _in_step = {record!r}, {state['_in_step']!r} is not allowed: "
                          f"{len(_ZERO_RECORD)} numbers and an integer >= 0")
        for k, value in enumerate(record):
            check_finite(f"FMU state _record[{k}]", value)
        if type(state["_drift_warned"]) is not bool:
            raise Refusal(f"FMU state _drift_warned = {state['_drift_warned']!r} is not allowed: true or false")
        held = state["_held"]
        if held is not None:
            if not isinstance(held, list) or len(held) != len(self.COMPUTED):
                raise Refusal(f"FMU state _held = {held!r} is not allowed: None or {len(self.COMPUTED)} numbers")
            for k, value in enumerate(held):
                check_finite(f"FMU state _held[{k}]", value)
        for name, *_ in self.PARAMETERS:
            setattr(self, name, state[name])
        self.F = state["F"]
        self.a_g = state["a_g"]
        self._t0 = state["_t0"]
        self._initialized = bool(state["_initialized"])
        self._in_step = state["_in_step"]
        self._record_values[:] = record
        self._record_in_buffer = True
        self._core = None
        self._held = None
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
            if held is not None:  # the outputs a collapsed building holds, as they were at its collapse
                self._held = tuple(held)
            if self._drift is not None:
                self._drift.warned = state["_drift_warned"]

    # ---- modelDescription -----------------------------------------------------------

    def to_xml(self, model_options=dict()):
        """pythonfmu's description plus units, ranges, descriptions and a full ModelStructure;
        the native layer's link variable is left out (hosts never see it)."""
        root = super().to_xml(model_options)
        info = {name: (unit, lo, hi, desc) for name, _, _, unit, lo, hi, desc in self.PARAMETERS}
        info.update({name: (unit, None, None, desc) for name, _, unit, desc, *_ in self.COMPUTED + RECORD})
        info.update({name: (unit, None, None, desc) for name, unit, desc in INPUTS})
        local = range(len(OUTPUTS), len(OUTPUTS) + len(DERIVED))
        outputs = [(name, ("F", "a_g") if feedthrough else ())
                   for k, (name, _, _, _, feedthrough) in enumerate(self.COMPUTED) if k not in local]
        return describe(root, info, outputs)


class PendulumImpactDamper(ParticleSlave):
    """Pendulum-type particle impact damper, exact event-driven co-simulation."""

    STOREYS = 0
    description = ("Pendulum-type particle impact damper: primary pendulum and hanging particle, "
                   "linearised, exact event-driven motion (impacts, chatter, sticking located inside doStep)")
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=20.0, step_size=0.01)
