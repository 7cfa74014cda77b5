"""Step-by-step drivers with save/restore, for measures that need the continuous solution.

Both steppers share one protocol (t, advance, read, save, restore, discard,
close) so the measures run unchanged on the FMU (through fmpy's FMU2Slave) or
on the physics core directly.  The external force, if any, is sampled at the
start of each advance and held (as a co-simulation host does).
"""
import re

from pidamper_physics import INITIAL_DEFAULTS, Damper, Params

from .instance import FmuInstance


class FmuStepper(FmuInstance):
    """The damper FMU driven by fmpy's FMU2Slave (an FmuInstance), the external force sampled at
    the start of each advance and held."""

    def __init__(self, fmu_path, start_values=None, forcing=None, start_time=0.0, instance_name="pidamper",
                 logger=None):
        """logger(status, text): hears the model's messages (debug logging on), else they are dropped."""
        super().__init__(fmu_path, start_values, start_time, instance_name, logger)
        self.forcing = forcing
        self._vr_read = self.vr("theta", "theta_dot")

    def advance(self, t_end):
        if self.forcing is not None:
            self.set(self.forcing.target, float(self.forcing.value(self.t)))
        self.do_step(self.t, t_end - self.t)

    def read(self):
        """(theta, theta_dot) now."""
        theta, theta_dot = self.fmu.getReal(self._vr_read)
        return theta, theta_dot

    def save(self):
        return self.t, self.fmu.getFMUstate()

    def restore(self, saved):
        self.t, state = saved
        self.fmu.setFMUstate(state)

    def discard(self, saved):
        self.fmu.freeFMUstate(saved[1])


class CoreStepper:
    """The physics core (pidamper_physics.Damper) behind the same protocol; start values
    default as in the FMU."""

    def __init__(self, start_values=None, forcing=None, start_time=0.0):
        values = dict(start_values or {})
        initial = [float(values.pop(k, default)) for k, default in INITIAL_DEFAULTS.items()]
        known = [k for k in values if k in Params.NAMES or re.fullmatch(r"(floor\[\d+\]\.m|storey\[\d+\]\.(k|h|Fy|b))", k)]
        params = {k: values.pop(k) for k in known}
        if values:
            raise KeyError(f"unknown parameters {sorted(values)!r}")
        self.core = Damper(Params.from_variables(params), *initial, t0=start_time)
        self.core.bound_work()  # as the FMU: a step's work is capped
        self.forcing = forcing

    @property
    def t(self):
        return self.core.t

    def _input(self, target):
        """The input `target` (F or a_g) held over the last step: the forcing's value at its start."""
        if self.forcing is None or self.forcing.target != target:
            return 0.0
        return float(self.forcing.value(self._held_from))

    _held_from = 0.0

    def advance(self, t_end):
        self._held_from = self.core.t
        value = 0.0 if self.forcing is None else float(self.forcing.value(self.core.t))
        if self.forcing is not None and self.forcing.target == "a_g":
            self.core.advance(t_end, 0.0, value)
        else:
            self.core.advance(t_end, value)

    def read(self):
        return self.core.angles()[:2]

    def get(self, name):
        c = self.core
        found = re.fullmatch(r"(floor|storey)\[(\d+)\]\.(x|a|drift|drift_ratio|drift_ratio_max|v_abs_max|a_abs_max)",
                             name)
        if found or name == "base_shear":
            ground = self._input("a_g")
            xs, acc, drifts, shear = c.building_outputs(self._input("F"), ground)
            if not found:
                return shear
            ratios, drift_max, v_max, a_max = c.model.peak_outputs(drifts)
            return {"x": xs, "a": acc, "drift": drifts, "drift_ratio": ratios, "drift_ratio_max": drift_max,
                    "v_abs_max": v_max, "a_abs_max": a_max}[found.group(3)][int(found.group(2)) - 1]
        return {"impacts": c.impacts, "energy": c.energy, "energy_dissipated": c.dissipated,
                "energy_viscous": c.viscous, "work_in": c.work_in, "theta": c.angles()[0]}[name]

    def save(self):
        return self.core.get_state()

    def restore(self, saved):
        self.core.set_state(saved)

    def discard(self, saved):
        pass

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
