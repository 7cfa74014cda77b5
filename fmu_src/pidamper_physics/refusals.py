"""The refusal every check of the physics raises, and the finiteness check they all start with."""
import math


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
