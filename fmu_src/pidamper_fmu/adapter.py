"""A table-driven pythonfmu adapter for the pidamper component FMUs (PendulumImpactDamperUnit,
ShearBuilding), with the FMI entry points of common.py (shared with PendulumImpactDamper):

- bad input (invalid parameter, non-finite input, inconsistent step) is refused with a message
  `<instance>: <name> = <value> is not allowed: <rule>` logged at error level; no exception reaches
  pythonfmu when the native layer is there (it answers fmi2Error), as in slave.py;
- the FMU's native layer (fmi2_entry.c, compiled per model from its modelDescription by build_fmu)
  sits in front of pythonfmu's binary: this class makes its own buffer when the layer asks
  (common.py), writes every output and local variable into it after each step, and offers
  _native_step; the layer then answers reads without entering Python;
- fixed parameters may be set again after initialization to their current value only; `tunable`
  ones go to the core through `_tune`;
- the FMU state is a JSON-safe dict of every parameter and input, the start time, the
  initialization flag and the core's own state, refused naming the key if it is not one.

A model subclass declares PARAMETERS (name, type, start, unit, min, max, description, tunable),
INPUTS (name, start, unit, description), COMPUTED (name, type, unit, description, output?,
feedthrough input names) and implements _build_core(), _advance(core, t_end), _computed(core)
(the values of COMPUTED in order) and the core's get_state/set_state.
"""
import struct

from pythonfmu import Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Real

from pidamper_physics import ParameterError
from pidamper_physics.params import check_finite

from .common import FmiEntry, Refusal, describe, guarded


class ComponentSlave(FmiEntry, Fmi2Slave):
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
        self._register_link()
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
            self._input_changed(self._values[name], value)
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
        return lambda: self._flat_outputs()[k]

    def _outputs_now(self):
        return self._computed(self._core_now())

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

    def _push(self, core):
        self._pack.pack_into(self._buffer, self._offset, *self._computed(core))
        self._pushed = core

    # ---- FMI calls --------------------------------------------------------------------------

    def _step(self, current_time, step_size):
        core = self._core
        if core is None or not self._initialized:
            raise Refusal("fmi2DoStep is not allowed before fmi2ExitInitializationMode")
        total = current_time + step_size
        if total - total != 0.0 or step_size < 0.0:
            self._fail("communicationStepSize", step_size,
                       f"the step from {current_time!r} must be finite and >= 0 (no step back in time)")
        t = core.t
        if current_time != t:  # (a host's rounded time: within the tolerance, accepted)
            self._check_time(current_time, t, step_size)
        try:
            self._advance(core, max(current_time + step_size, t))
        except ParameterError as err:
            self._fail(err.name, err.value, err.allowed)
        if self._native and not self._buffer_holds(core):
            self._push(core)

    @guarded(lambda args: None)
    def terminate(self):
        pass

    # ---- FMU state ----------------------------------------------------------------------------

    @guarded(lambda args: None)
    def _get_fmu_state(self):
        state = dict(self._values)
        state["_t0"] = self._t0
        state["_initialized"] = self._initialized
        state["_core"] = self._core.get_state() if self._initialized else None
        return state

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
        return describe(root, info, [(name, feed) for name, _, _, _, out, feed in self.COMPUTED if out])
