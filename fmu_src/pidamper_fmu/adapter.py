"""A table-driven pythonfmu adapter for the pidamper component FMUs (PendulumImpactDamperUnit,
ShearBuilding), sharing the conventions and helpers of slave.py (PendulumImpactDamper):

- bad input (invalid parameter, non-finite input, inconsistent step) is refused with a message
  `<instance>: <name> = <value> is not allowed: <rule>` logged at error level; no exception reaches
  pythonfmu when the native layer is there (it answers fmi2Error), as in slave.py;
- the FMU's native layer (fmi2_entry.c, compiled per model from its modelDescription by build_fmu)
  sits in front of pythonfmu's binary: this class takes its buffer through the hidden String
  variable _native_link (the last value reference), writes every output and local variable into it
  after each step, and offers _native_step; the layer then answers reads without entering Python;
- fixed parameters may be set again after initialization to their current value only; `tunable`
  ones go to the core through `_tune`;
- the FMU state is a JSON-safe dict of every parameter and input, the start time, the
  initialization flag and the core's own state, refused naming the key if it is not one.

A model subclass declares PARAMETERS (name, type, start, unit, min, max, description, tunable),
INPUTS (name, start, unit, description), COMPUTED (name, type, unit, description, output?,
feedthrough input names) and implements _build_core(), _advance(core, t_end), _computed(core)
(the values of COMPUTED in order) and the core's get_state/set_state.
"""
import ctypes
import math
import struct
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer, Real, String
from pythonfmu.enums import Fmi2Status

from pidamper_physics import ParameterError
from pidamper_physics.params import check_finite

from .slave import _TIME_TOLERANCE, _UNITS, LINK, Refusal, _fmi_text, _guarded

UNITS = dict(_UNITS, **{"N.s": {"kg": 1, "m": 1, "s": -1}, "N/m": {"kg": 1, "s": -2}})


class ComponentSlave(Fmi2Slave):
    """Base of the component FMUs (see the module doc)."""

    PARAMETERS = ()  # (name, Real | Integer, start, unit, min, max, description, tunable)
    INPUTS = ()      # (name, start, unit, description): Real, continuous, held over each step
    COMPUTED = ()    # (name, Real | Integer, unit, description, is_output, feedthrough input names)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._initialized = False
        self._core = None
        self._native = False
        self._buffer = None
        self._t0 = 0.0
        self._values = {}
        for name, start, *_ in self.INPUTS:
            self._values[name] = float(start)
            self.register_variable(Real(name, causality=Fmi2Causality.input, variability=Fmi2Variability.continuous,
                                        getter=self._getter(name), setter=self._input_setter(name)), nested=False)
        for name, kind, start, _, _, _, _, tunable in self.PARAMETERS:
            self._values[name] = start
            self.register_variable(kind(name, causality=Fmi2Causality.parameter,
                                        variability=Fmi2Variability.tunable if tunable else Fmi2Variability.fixed,
                                        getter=self._getter(name), setter=self._setter(name, tunable)), nested=False)
        first = len(self.vars)
        for k, (name, kind, _, _, is_output, _) in enumerate(self.COMPUTED):
            self.register_variable(kind(name, causality=Fmi2Causality.output if is_output else Fmi2Causality.local,
                                        initial=Fmi2Initial.calculated,
                                        variability=Fmi2Variability.continuous if kind is Real
                                        else Fmi2Variability.discrete,
                                        getter=self._computed_getter(k)), nested=False)
        self._native_link = ""
        self.register_variable(String(LINK, causality=Fmi2Causality.local, variability=Fmi2Variability.discrete,
                                      getter=lambda: self._native_link, setter=self._attach), nested=False)
        self._offset = 8 * first
        self._pack = struct.Struct(f"={len(self.COMPUTED)}d")
        self._state_keys = frozenset(list(self._values) + ["_t0", "_initialized", "_core"])

    # ---- variables ---------------------------------------------------------------------

    def _getter(self, name):
        return lambda: self._values[name]

    def _input_setter(self, name):
        def set_input(value):
            if value - value != 0.0:
                self._fail(name, value, "the input must be finite")
            self._values[name] = value
        return set_input

    def _setter(self, name, tunable):
        def set_value(value):
            if self._initialized and not tunable:
                if value == self._values[name]:
                    return  # the same value again (hosts that set every parameter after initialization)
                self._fail(name, value, f"it is a fixed parameter (now {self._values[name]!r}) and cannot change "
                                        "after initialization")
            if tunable and self._initialized:
                try:
                    self._tune(self._core, name, value)
                except ParameterError as err:
                    self._fail(err.name, err.value, err.allowed)
            self._values[name] = value
            if not self._initialized:
                self._core = None
        return set_value

    def _computed_getter(self, k):
        return lambda: self._computed(self._core_now())[k]

    # ---- to be provided by the model --------------------------------------------------------

    def _build_core(self):
        raise NotImplementedError

    def _advance(self, core, t_end):
        raise NotImplementedError

    def _computed(self, core):
        raise NotImplementedError

    def _tune(self, core, name, value):
        raise ParameterError(name, value, "it cannot change after initialization")

    # ---- the native layer's buffer ----------------------------------------------------------

    def _attach(self, text):
        """The native layer hands over its buffer: 'address n_vars' (see slave.py)."""
        try:
            address, count = text.split()
            count = int(count)
        except ValueError:
            raise Refusal(f"{LINK} = {text!r} is not allowed: it is set by the FMU's native layer only")
        if count != len(self.vars) - 1:
            raise Refusal(f"{LINK}: the native layer has {count} variables, the model {len(self.vars) - 1} "
                          "(binaries of another build)")
        self._buffer = memoryview((ctypes.c_double * (count + 1)).from_address(int(address, 16))).cast("B")
        struct.pack_into("=Q", self._buffer, 8 * count, id(self))
        self._native = True

    def _push(self, core):
        self._pack.pack_into(self._buffer, self._offset, *self._computed(core))

    # ---- refusals -----------------------------------------------------------------------------

    def _fail(self, name, value, allowed):
        raise Refusal(f"{name} = {value!r} is not allowed: {allowed}")

    def _report(self, err):
        text = str(err) if isinstance(err, (Refusal, ParameterError)) else f"{type(err).__name__}: {err}"
        self.log(_fmi_text(f"{self.instance_name}: {text}", self._native), Fmi2Status.error)

    def _core_now(self):
        if self._core is None:
            try:
                self._core = self._build_core()
            except ParameterError as err:
                self._fail(err.name, err.value, err.allowed)
        return self._core

    # ---- FMI calls --------------------------------------------------------------------------

    @_guarded(lambda args: None)
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        if not math.isfinite(start_time):
            self._fail("startTime", start_time, "it must be finite")
        self._t0 = float(start_time)
        self._core = None

    @_guarded(lambda args: None)
    def exit_initialization_mode(self):
        self._core = None
        self._core_now()
        self._initialized = True

    def do_step(self, current_time, step_size):
        try:
            self._step(current_time, step_size)
        except Exception as err:
            if not self._native:
                raise
            self._report(err)
            return False
        return True

    def _native_step(self, current_time, step_size):
        """fmi2DoStep from the native layer: 0 done, 1 done with messages queued, 2 refused."""
        try:
            self._step(current_time, step_size)
        except Exception as err:
            self._report(err)
            return 2
        return 1 if self.log_queue else 0

    def _step(self, current_time, step_size):
        core = self._core
        if core is None or not self._initialized:
            raise Refusal("fmi2DoStep is not allowed before fmi2ExitInitializationMode")
        total = current_time + step_size
        if total - total != 0.0 or step_size < 0.0:
            self._fail("communicationStepSize", step_size,
                       f"the step from {current_time!r} must be finite and >= 0 (no step back in time)")
        t = core.t
        lag = current_time - t
        if (lag > 0.0 or lag < 0.0) and abs(lag) > _TIME_TOLERANCE * max(abs(t), step_size):
            self._fail("currentCommunicationPoint", current_time,
                       f"it must equal the FMU time {t!r} (relative tolerance {_TIME_TOLERANCE})")
        try:
            self._advance(core, max(current_time + step_size, t))
        except ParameterError as err:
            self._fail(err.name, err.value, err.allowed)
        if self._native:
            self._push(core)

    @_guarded(lambda args: None)
    def terminate(self):
        pass

    def _checked(self, vrs, kind):
        out = []
        variables = self.vars
        for vr in vrs:
            var = variables.get(vr)
            if var is None or var.name == LINK:
                raise Refusal(f"value reference {vr} is not allowed: no such variable")
            if not isinstance(var, kind):
                raise Refusal(f"{var.name} (value reference {vr}) is not allowed here: it is not a "
                              f"{kind.__name__} variable")
            out.append(var)
        return out

    @_guarded(lambda args: [math.nan] * len(args[0]))
    def get_real(self, vrs):
        return [float(var.getter()) for var in self._checked(vrs, Real)]

    @_guarded(lambda args: [0] * len(args[0]))
    def get_integer(self, vrs):
        return [int(var.getter()) for var in self._checked(vrs, Integer)]

    @_guarded(lambda args: None)
    def set_real(self, vrs, values):
        for var, value in zip(self._checked(vrs, Real), values):
            var.setter(value)

    @_guarded(lambda args: None)
    def set_integer(self, vrs, values):
        for var, value in zip(self._checked(vrs, Integer), values):
            var.setter(value)

    def set_string(self, vrs, values):
        """Only the native layer sets a String (its link); a failure is logged, never raised."""
        try:
            for vr, value in zip(vrs, values):
                if self.vars.get(vr) is None or self.vars[vr].name != LINK:
                    raise Refusal(f"value reference {vr} is not allowed: the model has no String variable")
                self._attach(value)
        except Exception as err:
            self._report(err)

    # ---- FMU state ----------------------------------------------------------------------------

    @_guarded(lambda args: None)
    def _get_fmu_state(self):
        state = dict(self._values)
        state["_t0"] = self._t0
        state["_initialized"] = self._initialized
        state["_core"] = self._core.get_state() if self._initialized else None
        return state

    @_guarded(lambda args: None)
    def _set_fmu_state(self, state):
        previous = self._get_fmu_state()
        try:
            self._restore(state)
        except Exception:
            self._restore(previous)
            raise

    def _restore(self, state):
        if not isinstance(state, dict) or set(state) != self._state_keys:
            got = sorted(state) if isinstance(state, dict) else type(state).__name__
            raise Refusal(f"FMU state = {got!r} is not allowed: a state of this model has exactly the keys "
                          f"{sorted(self._state_keys)}")
        for name, *_ in self.INPUTS:
            check_finite(f"FMU state {name}", state[name])
        check_finite("FMU state _t0", state["_t0"])
        for name in self._values:
            self._values[name] = state[name]
        self._t0 = state["_t0"]
        self._initialized = bool(state["_initialized"])
        self._core = None
        if self._initialized:
            try:
                self._core_now().set_state(dict(state["_core"]) if isinstance(state["_core"], dict) else state["_core"])
            except ParameterError as err:
                self._fail(err.name, err.value, err.allowed)

    # ---- modelDescription ---------------------------------------------------------------------

    def to_xml(self, model_options=dict()):
        """pythonfmu's description plus units, ranges, descriptions and a full ModelStructure
        (outputs with their direct feedthrough inputs); the link variable is left out."""
        root = super().to_xml(model_options)
        info = {name: (unit, lo, hi, desc) for name, _, _, unit, lo, hi, desc, _ in self.PARAMETERS}
        info.update({name: (unit, None, None, desc) for name, _, unit, desc in self.INPUTS})
        info.update({name: (unit, None, None, desc) for name, _, unit, desc, _, _ in self.COMPUTED})
        variables = root.find("ModelVariables")
        for sv in list(variables):
            if sv.get("name") == LINK:
                variables.remove(sv)
        index = {}
        used = set()
        for i, sv in enumerate(variables, start=1):
            name = sv.get("name")
            index[name] = i
            unit, lo, hi, desc = info[name]
            sv.set("description", desc)
            typed = sv[0]
            for key, val in (("unit", unit), ("min", lo), ("max", hi)):
                if val is not None:
                    typed.set(key, val if key == "unit" else repr(val))
            if unit is not None:
                used.add(unit)
        units = Element("UnitDefinitions")
        for name, dims in UNITS.items():
            if name in used:
                SubElement(SubElement(units, "Unit", name=name), "BaseUnit", {k: str(v) for k, v in dims.items()})
        root.insert(list(root).index(root.find("CoSimulation")) + 1, units)
        structure = root.find("ModelStructure")
        for child in list(structure):
            structure.remove(child)
        outputs = SubElement(structure, "Outputs")
        initial = SubElement(structure, "InitialUnknowns")
        for name, _, _, _, is_output, feedthrough in self.COMPUTED:
            if not is_output:
                continue
            deps = " ".join(str(index[d]) for d in feedthrough)
            SubElement(outputs, "Unknown", index=str(index[name]), dependencies=deps)
            SubElement(initial, "Unknown", index=str(index[name]))
        return root
