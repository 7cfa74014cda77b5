"""Parameters of the pendulum impact damper and their validation.

Conventions (SI): g [m/s2], M [kg], mu = m/M [1], L2 [m] primary pendulum length,
FR = w1/w2 [1] so that the particle pendulum has L1 = L2/FR**2, d [m] clearance
(displacement form), d_angle [rad] clearance (angle form), e [1] restitution,
contact_form 0 (displacement, gap x - y = +-d) or 1 (angle as printed,
theta - alpha = +-d_angle), F0 [N], Omega [rad/s], phi [rad] built-in harmonic
force F0 sin(Omega t + phi) on the primary.
"""
import math

DISPLACEMENT = 0
ANGLE = 1

#: default parameters (the FMU's start values): the paper's free-vibration case
DEFAULTS = {"g": 9.81, "M": 1.0, "mu": 0.1, "L2": 1.0, "FR": 5.0, "d": 0.1, "d_angle": 0.1, "e": 0.2,
            "contact_form": DISPLACEMENT, "F0": 0.0, "Omega": math.sqrt(9.81 / 1.0), "phi": 0.0}
#: default initial state [rad, rad/s]: particle at rest, primary started by a velocity
INITIAL_DEFAULTS = {"theta_0": 0.0, "theta_dot_0": 0.5, "alpha_0": 0.0, "alpha_dot_0": 0.0}


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


def _positive(name, value):
    if check_finite(name, value) <= 0.0:
        raise ParameterError(name, value, "it must be > 0")


class Params:
    """Validated physical parameters plus the derived quantities the solver uses."""

    NAMES = ("g", "M", "mu", "L2", "FR", "d", "d_angle", "e", "contact_form", "F0", "Omega", "phi")

    def __init__(self, g=DEFAULTS["g"], M=DEFAULTS["M"], mu=DEFAULTS["mu"], L2=DEFAULTS["L2"],
                 FR=DEFAULTS["FR"], d=DEFAULTS["d"], d_angle=DEFAULTS["d_angle"], e=DEFAULTS["e"],
                 contact_form=DEFAULTS["contact_form"], F0=DEFAULTS["F0"], Omega=DEFAULTS["Omega"],
                 phi=DEFAULTS["phi"]):
        for name in ("g", "M", "L2", "FR", "d", "d_angle"):
            _positive(name, locals()[name])
        if check_finite("mu", mu) < 0.0:
            raise ParameterError("mu", mu, "it must be >= 0 (0 means no damper)")
        check_restitution(e)
        if contact_form not in (DISPLACEMENT, ANGLE) or isinstance(contact_form, bool):
            raise ParameterError("contact_form", contact_form, "it must be 0 (displacement) or 1 (angle as printed)")
        check_finite("F0", F0)
        if check_finite("Omega", Omega) < 0.0:
            raise ParameterError("Omega", Omega, "it must be >= 0")
        check_finite("phi", phi)
        self.g, self.M, self.mu, self.L2, self.FR = float(g), float(M), float(mu), float(L2), float(FR)
        self.d, self.d_angle, self.e = float(d), float(d_angle), float(e)
        self.contact_form = int(contact_form)
        self.F0, self.Omega, self.phi = float(F0), float(Omega), float(phi)
        self.m = self.mu * self.M
        self.L1 = self.L2 / (self.FR * self.FR)
        self.w2 = math.sqrt(self.g / self.L2)
        self.w1 = math.sqrt(self.g / self.L1)
        if self.contact_form == DISPLACEMENT:
            self.cx, self.cy, self.D = 1.0, 1.0, self.d
        else:
            self.cx, self.cy, self.D = 1.0 / self.L2, 1.0 / self.L1, self.d_angle

    def as_dict(self):
        return {name: getattr(self, name) for name in self.NAMES}


def check_restitution(e):
    value = check_finite("e", e)
    if not 0.0 <= value <= 1.0:
        raise ParameterError("e", e, "it must lie in [0, 1]")
    return value
