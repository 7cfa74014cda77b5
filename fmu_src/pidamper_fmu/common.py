"""What every pidamper FMU adapter shares (PendulumImpactDamper, PendulumImpactDamperUnit,
ShearBuilding): refusals through the FMI logger, the native layer's link, type-checked variable
access and the FMI entry points around the model's own `_step` and `_build_core`.

- Bad input is refused with `<instance>: <name> = <value> is not allowed: <rule>` at error level;
  with the native layer (fmi2_entry.c) no exception reaches pythonfmu (the layer answers
  fmi2Error); without it the exception propagates (pythonfmu answers fmi2Fatal).
- The native layer finds the model through the hidden String variable LINK (the last value
  reference, left out of modelDescription.xml, read only: the model's id()) and calls its
  `_native_attach` directly, which no FMI function reaches: the model makes its own buffer, writes
  its outputs there after each step, and the layer answers reads from it without entering Python.
  No host can make the model write anywhere else, with the layer or without it (pythonfmu's own
  binary passes every value reference to the model: set_string refuses them all).
- With the native layer, fmi2DoStep and fmi2SetReal of Real inputs reach the model by direct calls
  (`_native_step`, `_native_set_input`) after the layer's own checks; any other call goes through
  pythonfmu.
- Outputs are computed once per state: after a step the model packs them into the native layer's
  buffer in one pass (and skips even that when the physics says the step changed nothing the
  outputs read: `core.still`, no input set to other bits and no read through Python since); reads
  through Python (no native layer, or a read between fmi2SetReal and fmi2DoStep) are served from
  one flat tuple (`_flat_outputs`), computed at the first read after anything changed.
"""
import ctypes
import math
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Fmi2Causality, Fmi2Variability, Integer, Real, String
from pythonfmu.enums import Fmi2Status

from pidamper_physics import BUILD, ParameterError, same_bits

UNITS = {"s": {"s": 1}, "m/s": {"m": 1, "s": -1}, "m": {"m": 1}, "m/s2": {"m": 1, "s": -2}, "kg": {"kg": 1}, "1": {},
         "rad": {"rad": 1}, "rad/s": {"rad": 1, "s": -1}, "N": {"kg": 1, "m": 1, "s": -2},
         "J": {"kg": 1, "m": 2, "s": -2}, "N/m": {"kg": 1, "s": -2}, "N.s": {"kg": 1, "m": 1, "s": -1},
         "Pa": {"kg": 1, "m": -1, "s": -2}}

TIME_TOLERANCE = 1e-9  # relative mismatch of a step's start time accepted from a host

LINK = "_native_link"  # hidden read-only String: the model's id() (last value reference, not in modelDescription.xml)


class Refusal(ValueError):
    """A call the model refuses: the text names the variable, its value and what is allowed."""


def fmi_text(text, native):
    """A message for the FMI logger.  pythonfmu's binary passes it as a printf format (FMI 2.0,
    2.1.5), so a bare '%' would make the host read arguments that are not there (seen as a crash
    in fmpy); the native layer passes it as an argument, so the text goes as it is."""
    return text if native else text.replace("%", "%%")


def long_contact(t, duration, period):
    """The warning for a contact that is not short against the primary's period (impact.Tally)."""
    return (f"the impact at t = {t!r} s lasts {duration:.3g} s, {duration / period:.1%} of the primary's period "
            f"{period:.4g} s: the instantaneous impact the model applies then misplaces its impulse (a stiffer or "
            "larger contact surface, R, shortens it); warned once")


def guarded(default):
    """Run an FMI entry point so that no exception reaches pythonfmu: with the native layer the
    error is logged at error level (the layer answers fmi2Error) and `default(args)` returned;
    without it the exception propagates (pythonfmu answers fmi2Fatal)."""
    def wrap(method):
        def call(self, *args):
            try:
                return method(self, *args)
            except Exception as err:
                if not self._native:
                    raise
                self._report(err)
                return default(args)
        call.__name__, call.__doc__ = method.__name__, method.__doc__
        return call
    return wrap


def describe(root, info, outputs):
    """Complete pythonfmu's modelDescription `root`: each variable's (unit, min, max, description)
    from `info` by name, the UnitDefinitions it uses, and a ModelStructure listing `outputs`
    ((name, names of the inputs it depends on directly), in value-reference order); the native
    layer's LINK is left out (hosts never see it)."""
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
        used.add(unit)
    units = Element("UnitDefinitions")
    for name, dims in UNITS.items():
        if name in used:
            SubElement(SubElement(units, "Unit", name=name), "BaseUnit", {k: str(v) for k, v in dims.items()})
    root.insert(list(root).index(root.find("CoSimulation")) + 1, units)
    structure = root.find("ModelStructure")
    for child in list(structure):
        structure.remove(child)
    listed, initial = SubElement(structure, "Outputs"), SubElement(structure, "InitialUnknowns")
    for name, inputs in outputs:
        SubElement(listed, "Unknown", index=str(index[name]), dependencies=" ".join(str(index[d]) for d in inputs))
        SubElement(initial, "Unknown", index=str(index[name]))
    return root


class FmiEntry:
    """Mixin (before Fmi2Slave) of the FMI entry points every adapter shares.  The model keeps
    `_core`, `_initialized`, `_native`, `_t0` and provides `_build_core()` and `_step(t, h)`;
    it registers LINK last (`_register_link`); `_attached()` runs once its buffer for the native
    layer is in place."""

    _t0 = 0.0
    _flat = None  # the outputs of the current state, once read through Python (None: not yet)
    _pushed = None  # the core whose outputs the native layer's buffer holds under the current inputs, or None

    # ---- outputs served once per state ------------------------------------------------

    def _flat_outputs(self):
        """The values of the computed variables of the current state, in their order: computed at
        the first read after anything changed (every FMI call that may change something drops them)."""
        flat = self._flat
        if flat is None:
            flat = self._flat = self._outputs_now()
        return flat

    def _outputs_now(self):
        raise NotImplementedError

    def _buffer_holds(self, core):
        """True when the buffer already holds the outputs of this step: the physics changed
        nothing they read (core.still: a building at rest), the buffer was written for this core,
        and since then no input changed bit for bit (`_input_changed`) and no read through Python
        wrote it."""
        return self._pushed is core and getattr(core, "still", False)

    def _input_changed(self, old, value):
        """An input's setter, before it stores `value`: one that is not `old` bit for bit drops the
        buffer's claim to hold the current outputs (the outputs may read that input)."""
        if not same_bits(old, value):
            self._pushed = None

    # ---- refusals ---------------------------------------------------------------------

    def _fail(self, name, value, allowed):
        """Refuse the call, naming the variable, its value and the rule."""
        raise Refusal(f"{name} = {value!r} is not allowed: {allowed}")

    def _report(self, err):
        """Log a refused call at error level (the native layer then answers fmi2Error)."""
        text = str(err) if isinstance(err, (Refusal, ParameterError)) else f"{type(err).__name__}: {err}"
        self.log(fmi_text(f"{self.instance_name}: {text}", self._native), Fmi2Status.error)

    def _warn(self, text):
        """Log a warning through the FMI logger (the run goes on)."""
        self.log(fmi_text(f"{self.instance_name}: {text}", self._native), Fmi2Status.warning)

    def _collapsed(self, t, reason):
        """The core's collapse callback (a yielding building, either family): warn, naming the
        storey and the time (in `reason`); the core holds the state from then."""
        self._warn(f"the building collapsed at t = {t!r} s: {reason}; every output holds its value from then")

    def _core_now(self):
        if self._core is None:
            try:
                self._core = self._build_core()
            except ParameterError as err:
                self._fail(err.name, err.value, err.allowed)
        return self._core

    # ---- the native layer's buffer --------------------------------------------------------

    def _register_link(self):
        """LINK, after every other variable: read only, its value is the model's id() in hex."""
        self.register_variable(String(LINK, causality=Fmi2Causality.local, variability=Fmi2Variability.discrete,
                                      getter=lambda: f"{id(self):x}"), nested=False)

    def _native_attach(self, count):
        """Called by the native layer directly (no FMI function reaches it), with its number of
        variables: the model makes its buffer, a double per value reference that the model object
        keeps, writes its outputs there after each step from now on (the layer then calls
        _native_step), and returns the buffer's address; 0, with a message, if it refuses."""
        try:
            if count != len(self.vars) - 1:
                raise Refusal(f"{LINK}: the native layer has {count} variables, the model {len(self.vars) - 1} "
                              "(binaries of another build)")
            array = (ctypes.c_double * count)()
            self._buffer = memoryview(array).cast("B")
            self._pushed = None
            self._native = True
            self._attached()
            return ctypes.addressof(array)
        except Exception as err:
            self._report(err)
            return 0

    def _attached(self):
        pass

    # ---- FMI calls --------------------------------------------------------------------

    @guarded(lambda args: None)
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self._flat = None
        if not math.isfinite(start_time):
            self._fail("startTime", start_time, "it must be finite")
        self._t0 = float(start_time)
        self._core = None

    @guarded(lambda args: None)
    def exit_initialization_mode(self):
        self._flat = None
        self._core = None
        self._core_now()
        self._initialized = True
        self.log(fmi_text(f"{self.instance_name}: physics {BUILD}", self._native), Fmi2Status.ok)

    def do_step(self, current_time, step_size):
        self._flat = None
        try:
            self._step(current_time, step_size)
        except Exception as err:
            if not self._native:
                raise
            self._report(err)
            return False
        return True

    def _native_step(self, current_time, step_size):
        """fmi2DoStep called by the native layer directly: 0 done, 1 done with messages queued,
        2 refused (its message queued)."""
        self._flat = None
        try:
            self._step(current_time, step_size)
        except Exception as err:
            self._report(err)
            return 2
        return 1 if self.log_queue else 0

    def _native_set_input(self, vr, value):
        """fmi2SetReal of one Real input, called by the native layer directly (it checked the value
        reference and the calling sequence): 0 set, 1 set with messages queued, 2 refused (its
        message queued)."""
        self._flat = None
        try:
            self.vars[vr].setter(value)
        except Exception as err:
            self._report(err)
            return 2
        finally:
            self._flat = None
        return 1 if self.log_queue else 0

    def _check_time(self, current_time, t, step_size):
        """Refuse a step that does not start at the FMU's time t (to TIME_TOLERANCE)."""
        lag = current_time - t
        if (lag > 0.0 or lag < 0.0) and abs(lag) > TIME_TOLERANCE * max(abs(t), step_size):
            self._fail("currentCommunicationPoint", current_time,
                       f"it must equal the FMU time {t!r} (relative tolerance {TIME_TOLERANCE})")

    @guarded(lambda args: None)
    def _set_fmu_state(self, state):
        """Restore a state _get_fmu_state wrote (the model's `_restore`); one that does not come
        from this model is refused with a message naming the key, and the instance keeps the state
        it had."""
        self._flat = None
        previous = self._get_fmu_state()
        try:
            self._restore(state)
        except Exception:
            self._restore(previous)
            raise

    # ---- variable access: type-checked, one pass per call -----------------------------

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

    @guarded(lambda args: [math.nan] * len(args[0]))
    def get_real(self, vrs):
        self._pushed = None  # the native layer writes what it reads through Python into its buffer
        return [float(var.getter()) for var in self._checked(vrs, Real)]

    @guarded(lambda args: [0] * len(args[0]))
    def get_integer(self, vrs):
        self._pushed = None
        return [int(var.getter()) for var in self._checked(vrs, Integer)]

    @guarded(lambda args: None)
    def set_real(self, vrs, values):
        self._flat = None
        try:
            for var, value in zip(self._checked(vrs, Real), values):
                var.setter(value)
        finally:
            self._flat = None

    @guarded(lambda args: None)
    def set_integer(self, vrs, values):
        self._flat = None
        try:
            for var, value in zip(self._checked(vrs, Integer), values):
                var.setter(value)
        finally:
            self._flat = None

    def get_string(self, vrs):
        """LINK's value (the native layer reads it); any other value reference is refused at error
        level, never raised (as set_string)."""
        for vr in vrs:
            var = self.vars.get(vr)
            if var is None or var.name != LINK:
                self._report(Refusal(f"value reference {vr} is not allowed: the model has no other String variable"))
                return [""] * len(vrs)
        return [self.vars[vr].getter() for vr in vrs]

    def set_string(self, vrs, values):
        """The model has no String variable a host can set (LINK is read only; only pythonfmu's own
        binary lets a call get here): refused at error level, never raised (pythonfmu's binary
        answers an exception with fmi2Fatal, and its fmi2FreeInstance then crashes the host)."""
        if vrs:
            self._report(Refusal(f"value reference {vrs[0]} is not allowed: the model has no String variable "
                                 "that can be set"))
