"""PendulumImpactDamper: a pythonfmu Fmi2Slave that is a thin adapter over Damper.

Variables (names are a contract): inputs F [N] and a_g [m/s2] (ground acceleration of a
base excitation: it acts on both bodies, whose x and y are then measured from the ground); parameters g, M, mu, L2, FR, d,
d_angle, e (tunable), contact_form, F0, Omega, phi, fidelity, zeta_s, zeta_p, angle_limit and the initial state
theta_0, theta_dot_0, alpha_0, alpha_dot_0; outputs theta, theta_dot, alpha,
alpha_dot, x, y, z, a, impacts, contact, contact_force, energy,
energy_dissipated, energy_viscous, work_in.

Bad input (invalid parameter, non-finite input, inconsistent step) fails the call
with an exception naming the variable, its value and what is allowed; pythonfmu 0.7
logs its text through the FMI logger and returns fmi2Fatal, which makes every host
stop with an error.  A swing beyond angle_limit (the small-angle validity of the
linear model) is logged once per run at warning level.  Hosts show the model's
messages only with debug logging on.
"""
import math
import uuid
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.enums import Fmi2Status
from pythonfmu.default_experiment import DefaultExperiment

from pidamper_physics import DEFAULTS, INITIAL_DEFAULTS, Damper, ParameterError, Params, SmallAngleMonitor
from pidamper_physics.params import NONLINEAR, check_restitution

SOURCE_HASH = "development"  # replaced by build_fmu with a hash of the shipped sources
VERSION = "0.1.0"

_START = {**DEFAULTS, **INITIAL_DEFAULTS, "angle_limit": SmallAngleMonitor.DEFAULT_LIMIT}

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
))

# name, type, unit, description, direct feedthrough from F
OUTPUTS = (
    ("theta", Real, "rad", "primary angle", False),
    ("theta_dot", Real, "rad/s", "primary angular velocity", False),
    ("alpha", Real, "rad", "particle angle (of its wire from the vertical)", False),
    ("alpha_dot", Real, "rad/s", "particle angular velocity", False),
    ("x", Real, "m", "primary displacement (linear levels: L2*theta; nonlinear: L2 sin(theta))", False),
    ("y", Real, "m", "particle displacement (linear, damped: L1*alpha; coupled: x + L1*alpha; nonlinear: "
                     "x + L1 sin(alpha))", False),
    ("z", Real, "m", "gap x - y", False),
    ("a", Real, "m/s2", "primary acceleration between impacts", True),
    ("impacts", Integer, None, "impacts applied so far (chatter impacts included)", False),
    ("contact", Integer, None, "0 free, +1/-1 particle riding that stop", False),
    ("contact_force", Real, "N", "force of the stop on the particle while riding it, else 0", True),
    ("energy", Real, "J", "mechanical energy of the level's model (linear: 0.5 M (v^2 + w2^2 x^2) + 0.5 m (u^2 + w1^2 y^2))", False),
    ("energy_dissipated", Real, "J", "energy dissipated by impacts so far", False),
    ("energy_viscous", Real, "J", "energy taken by the viscous dashpots so far (fidelity >= 1)", False),
    ("work_in", Real, "J", "work done by the applied forces so far, integral of F v dt", False),
)

# per-step impact record: read after fmi2DoStep; slots beyond impacts_in_step hold zeros
IMPACT_SLOTS = 16
IMPACT_FIELDS = (
    ("t", Real, "s", "time"),
    ("side", Integer, None, "stop hit: +1 (z = +d) or -1 (z = -d)"),
    ("v_rel_before", Real, "m/s", "particle minus primary velocity before"),
    ("v_rel_after", Real, "m/s", "particle minus primary velocity after"),
    ("energy_lost", Real, "J", "energy lost"),
    ("theta", Real, "rad", "primary angle"),
)
RECORD_OUTPUTS = (
    ("impacts_in_step", Integer, None, "impacts applied during the last communication step", False),
    ("impacts_unrecorded", Integer, None,
     f"impacts of the last step beyond the {IMPACT_SLOTS} record slots (counted, not recorded)", False),
) + tuple((f"impact[{k + 1}].{field}", kind, unit, f"impact {k + 1} of the last step: {desc}", False)
          for k in range(IMPACT_SLOTS) for field, kind, unit, desc in IMPACT_FIELDS)

_UNITS = {"s": {"s": 1}, "m/s": {"m": 1, "s": -1}, "m": {"m": 1}, "m/s2": {"m": 1, "s": -2}, "kg": {"kg": 1}, "1": {},
          "rad": {"rad": 1}, "rad/s": {"rad": 1, "s": -1}, "N": {"kg": 1, "m": 1, "s": -2},
          "J": {"kg": 1, "m": 2, "s": -2}}

_TIME_TOLERANCE = 1e-9  # relative mismatch of a step's start time accepted from a host


def _fmi_text(text):
    """A message for the FMI logger, which takes it as a printf format (FMI 2.0, 2.1.5): a bare
    '%' would make the host read arguments that are not there (seen as a crash in fmpy)."""
    return text.replace("%", "%%")


class PendulumImpactDamper(Fmi2Slave):
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
        self.F = 0.0
        self.a_g = 0.0
        self.register_variable(Real("F", causality=Fmi2Causality.input, variability=Fmi2Variability.continuous,
                                    description="horizontal force on the primary mass [N]"))
        self.register_variable(Real("a_g", causality=Fmi2Causality.input, variability=Fmi2Variability.continuous,
                                    description="ground acceleration of a base excitation [m/s2]"))
        for name, kind, start, *_ in PARAMETERS:
            setattr(self, name, start)
            tunable = name == "e"
            self.register_variable(kind(
                name, causality=Fmi2Causality.parameter,
                variability=Fmi2Variability.tunable if tunable else Fmi2Variability.fixed,
                setter=self._setter(name, tunable)))
        self._slots = [[0.0, 0, 0.0, 0.0, 0.0, 0.0] for _ in range(IMPACT_SLOTS)]
        self._in_step = 0
        getters = {name: getattr(self, "_out_" + name) for name, *_ in OUTPUTS}
        getters["impacts_in_step"] = lambda: self._in_step
        getters["impacts_unrecorded"] = lambda: max(0, self._in_step - IMPACT_SLOTS)
        for k in range(IMPACT_SLOTS):
            for j, (field, *_) in enumerate(IMPACT_FIELDS):
                getters[f"impact[{k + 1}].{field}"] = self._slot_getter(k, j)
        for name, kind, *_ in OUTPUTS + RECORD_OUTPUTS:
            self.register_variable(kind(name, causality=Fmi2Causality.output, initial=Fmi2Initial.calculated,
                                        variability=Fmi2Variability.continuous if kind is Real
                                        else Fmi2Variability.discrete,
                                        getter=getters[name]))

    # ---- per-step impact record -------------------------------------------------------

    def _slot_getter(self, k, j):
        return lambda: self._slots[k][j] if k < self._in_step else 0

    def _record(self, t, side, v_rel_before, v_rel_after, loss):
        """Core callback, once per impact: fill the next slot (the count goes on past the last)."""
        n = self._in_step
        if n < IMPACT_SLOTS:
            slot = self._slots[n]
            slot[0], slot[1], slot[2], slot[3], slot[4] = t, side, v_rel_before, v_rel_after, loss
            slot[5] = self._core.angles()[0]
        self._in_step = n + 1

    # ---- parameters -----------------------------------------------------------------

    def _setter(self, name, tunable):
        def set_value(value):
            if self._initialized and not tunable:
                self._fail(name, value, "it is a fixed parameter and cannot change after initialization")
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
        params = Params(**{name: getattr(self, name) for name in Params.NAMES})
        core = Damper(params, self.theta_0, self.theta_dot_0, self.alpha_0, self.alpha_dot_0, self._t0)
        core.on_impact = self._record
        limit = self.angle_limit
        if not (math.isfinite(limit) and limit >= 0.0):
            raise ParameterError("angle_limit", limit, "it must be finite and >= 0 (0 turns the warning off)")
        small_angles = params.fidelity != NONLINEAR  # the nonlinear level has no small-angle limit
        self._monitor = SmallAngleMonitor(params, limit) if limit > 0.0 and small_angles else None
        return core

    def _fail(self, name, value, allowed):
        """Refuse the call: the exception becomes fmi2Fatal, and pythonfmu logs its text
        (naming the variable, its value and the rule) through the FMI logger.  The message
        is deliberately not queued with self.log as well: pythonfmu 0.7 flushes that queue
        while the Python exception is still pending, which calls the host's logger in an
        invalid interpreter state (seen as heap corruption in fmpy hosts)."""
        raise ValueError(_fmi_text(f"{self.instance_name}: {name} = {value!r} is not allowed: {allowed}"))

    def _core_now(self):
        if self._core is None:
            try:
                self._core = self._build_core()
            except ParameterError as err:
                self._fail(err.name, err.value, err.allowed)
        return self._core

    # ---- FMI calls ------------------------------------------------------------------

    _t0 = 0.0

    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        if not math.isfinite(start_time):
            self._fail("startTime", start_time, "it must be finite")
        self._t0 = float(start_time)
        self._core = None

    def exit_initialization_mode(self):
        self._core = None
        self._core_now()
        self._initialized = True

    def do_step(self, current_time, step_size):
        core = self._core
        t = core.t
        if not (math.isfinite(current_time) and math.isfinite(step_size)) or step_size < 0.0:
            self._fail("communicationStepSize", step_size,
                       f"the step from {current_time!r} must be finite and >= 0 (no step back in time)")
        if abs(current_time - t) > _TIME_TOLERANCE * max(abs(t), step_size):
            self._fail("currentCommunicationPoint", current_time,
                       f"it must equal the FMU time {t!r} (relative tolerance {_TIME_TOLERANCE})")
        force, ground = self.F, self.a_g
        if not math.isfinite(force):
            self._fail("F", force, "the input must be finite")
        if not math.isfinite(ground):
            self._fail("a_g", ground, "the input must be finite")
        self._in_step = 0
        core.advance(max(current_time + step_size, t), force, ground)
        monitor = self._monitor
        if monitor is not None:
            warning = monitor.check(core)
            if warning:
                self._warn(warning)
        return True

    def terminate(self):
        summary = self._monitor.summary() if self._monitor is not None and self._initialized else None
        if summary:
            self._warn(summary)

    def _warn(self, text):
        self.log(_fmi_text(f"{self.instance_name}: {text}"), Fmi2Status.warning)

    # ---- outputs --------------------------------------------------------------------

    def _out_theta(self):
        c = self._core_now()
        return c.angles()[0]

    def _out_theta_dot(self):
        c = self._core_now()
        return c.angles()[1]

    def _out_alpha(self):
        c = self._core_now()
        return c.angles()[2]

    def _out_alpha_dot(self):
        c = self._core_now()
        return c.angles()[3]

    def _out_x(self):
        return self._core_now().displacements()[0]

    def _out_y(self):
        return self._core_now().displacements()[2]

    def _out_z(self):
        x, _, y, _ = self._core_now().displacements()
        return x - y

    def _out_a(self):
        return self._core_now().acceleration(self.F, self.a_g)

    def _out_impacts(self):
        return self._core_now().impacts

    def _out_contact(self):
        return self._core_now().contact

    def _out_contact_force(self):
        return self._core_now().contact_force(self.F, self.a_g)

    def _out_energy(self):
        return self._core_now().energy

    def _out_energy_dissipated(self):
        return self._core_now().dissipated

    def _out_energy_viscous(self):
        return self._core_now().viscous

    def _out_work_in(self):
        return self._core_now().work_in

    # ---- FMU state ------------------------------------------------------------------

    def _get_fmu_state(self):
        state = {name: getattr(self, name) for name, *_ in PARAMETERS}
        state["F"] = self.F
        state["a_g"] = self.a_g
        state["_t0"] = self._t0
        state["_initialized"] = self._initialized
        state["_core"] = self._core.get_state() if self._initialized else None
        state["_in_step"] = self._in_step
        state["_slots"] = [list(slot) for slot in self._slots]
        monitor = self._monitor if self._initialized else None
        state["_monitor"] = None if monitor is None else monitor.get_state()
        return state

    def _set_fmu_state(self, state):
        for name, *_ in PARAMETERS:
            setattr(self, name, state[name])
        self.F = state["F"]
        self.a_g = state["a_g"]
        self._t0 = state["_t0"]
        self._initialized = state["_initialized"]
        self._in_step = state["_in_step"]
        self._slots = [list(slot) for slot in state["_slots"]]
        self._core = None
        if self._initialized:
            core = self._build_core()
            core.set_state(dict(state["_core"]))
            self._core = core
            if state["_monitor"] is not None:
                self._monitor.set_state(state["_monitor"])

    # ---- modelDescription -----------------------------------------------------------

    def to_xml(self, model_options=dict()):
        """pythonfmu's description plus units, ranges, descriptions and a full ModelStructure."""
        root = super().to_xml(model_options)
        info = {name: (unit, lo, hi, desc) for name, _, _, unit, lo, hi, desc in PARAMETERS}
        info.update({name: (unit, None, None, desc) for name, _, unit, desc, _ in OUTPUTS + RECORD_OUTPUTS})
        info["F"] = ("N", None, None, "horizontal force on the primary mass")
        info["a_g"] = ("m/s2", None, None, "ground acceleration of a base excitation (acts on both bodies)")
        index = {}
        for i, sv in enumerate(root.find("ModelVariables"), start=1):
            name = sv.get("name")
            index[name] = i
            unit, lo, hi, desc = info[name]
            sv.set("description", desc)
            typed = sv[0]
            for key, val in (("unit", unit), ("min", lo), ("max", hi)):
                if val is not None:
                    typed.set(key, val if key == "unit" else repr(val))
        units = Element("UnitDefinitions")
        for name, dims in _UNITS.items():
            SubElement(SubElement(units, "Unit", name=name), "BaseUnit", {k: str(v) for k, v in dims.items()})
        root.insert(list(root).index(root.find("CoSimulation")) + 1, units)
        structure = root.find("ModelStructure")
        for child in list(structure):
            structure.remove(child)
        outputs = SubElement(structure, "Outputs")
        initial = SubElement(structure, "InitialUnknowns")
        for name, _, _, _, feedthrough in OUTPUTS + RECORD_OUTPUTS:
            deps = f"{index['F']} {index['a_g']}" if feedthrough else ""
            SubElement(outputs, "Unknown", index=str(index[name]), dependencies=deps)
            SubElement(initial, "Unknown", index=str(index[name]))
        return root
