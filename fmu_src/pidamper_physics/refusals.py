"""The refusal every check of the physics raises, and the finiteness check they all start with."""
import math

#: smallest and largest magnitude of a length [m], mass [kg], frequency [rad/s] or load per mass
#: [m/s2] the model accepts: their squares and pairwise products stay normal floats
SCALE_RANGE = (1e-150, 1e150)


class ParameterError(ValueError):
    """A parameter or input outside its allowed range; names the value and the rule."""

    def __init__(self, name, value, allowed):
        self.name = name
        self.value = value
        self.allowed = allowed
        super().__init__(f"{name} = {value!r} is not allowed: {allowed}")


def check_finite(name, value):
    if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
        raise ParameterError(name, value, "it must be a finite number")
    return float(value)


def check_step(t, t_end, forces, ground):
    """Refuse a step of a building to t_end [s] from t under held floor forces [N] and ground
    acceleration [m/s2] that is not finite or goes back in time, naming the value."""
    total = t_end + ground + sum(forces)
    if total - total != 0.0:  # some value is not finite (or the sum overflowed)
        check_finite("t_end", t_end)
        check_finite("a_g", ground)
        for k, f in enumerate(forces):
            check_finite(f"F[{k + 1}]", f)
    if t_end < t:
        raise ParameterError("t_end", t_end, f"it must be >= the current time {t!r}")
