"""Parameters of the pendulum impact damper and their validation.

Conventions (SI): g [m/s2], M [kg], mu = m/M [1], L2 [m] primary pendulum length,
FR = w1/w2 [1] so that the particle pendulum has L1 = L2/FR**2, d [m] clearance
(displacement form), d_angle [rad] clearance (angle form), e [1] restitution,
contact_form 0 (displacement, gap x - y = +-d) or 1 (angle as printed,
theta - alpha = +-d_angle), F0 [N], Omega [rad/s], phi [rad] built-in harmonic
force F0 sin(Omega t + phi) on the primary; fidelity 0..3 (LEVELS) picks the model, zeta_s
and zeta_p [1] are the viscous damping ratios of the primary (dashpot 2 zeta_s M w2 on its
velocity) and of the particle (2 zeta_p m w1 on its velocity relative to its pivot), used
from the damped level on.
"""
import math

DISPLACEMENT = 0
ANGLE = 1

LINEAR, DAMPED, COUPLED, NONLINEAR = 0, 1, 2, 3
#: fidelity levels by number: each adds physics to the one before
LEVELS = ("linear", "damped", "coupled", "nonlinear")

#: default parameters (the FMU's start values): the paper's free-vibration case
DEFAULTS = {"g": 9.81, "M": 1.0, "mu": 0.1, "L2": 1.0, "FR": 5.0, "d": 0.1, "d_angle": 0.1, "e": 0.2,
            "contact_form": DISPLACEMENT, "F0": 0.0, "Omega": math.sqrt(9.81 / 1.0), "phi": 0.0, "fidelity": LINEAR,
            "zeta_s": 0.0, "zeta_p": 0.0}
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

    NAMES = ("g", "M", "mu", "L2", "FR", "d", "d_angle", "e", "contact_form", "F0", "Omega", "phi", "fidelity",
             "zeta_s", "zeta_p")

    def __init__(self, g=DEFAULTS["g"], M=DEFAULTS["M"], mu=DEFAULTS["mu"], L2=DEFAULTS["L2"],
                 FR=DEFAULTS["FR"], d=DEFAULTS["d"], d_angle=DEFAULTS["d_angle"], e=DEFAULTS["e"],
                 contact_form=DEFAULTS["contact_form"], F0=DEFAULTS["F0"], Omega=DEFAULTS["Omega"],
                 phi=DEFAULTS["phi"], fidelity=DEFAULTS["fidelity"], zeta_s=DEFAULTS["zeta_s"],
                 zeta_p=DEFAULTS["zeta_p"]):
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
        _check_level(fidelity, contact_form, zeta_s, zeta_p)
        self.g, self.M, self.mu, self.L2, self.FR = float(g), float(M), float(mu), float(L2), float(FR)
        self.d, self.d_angle, self.e = float(d), float(d_angle), float(e)
        self.contact_form = int(contact_form)
        self.F0, self.Omega, self.phi = float(F0), float(Omega), float(phi)
        self.fidelity, self.zeta_s, self.zeta_p = int(fidelity), float(zeta_s), float(zeta_p)
        self.m = self.mu * self.M
        self.L1 = self.L2 / (self.FR * self.FR)
        self._check_scale("L1 = L2/FR^2", self.L1)
        self.w2 = math.sqrt(self.g / self.L2)
        self.w1 = math.sqrt(self.g / self.L1)
        # the built-in harmonic's frequency where it acts (0 without it: a frequency that acts on
        # nothing sets no step size and no rounding allowance)
        self.Omega_acting = self.Omega if self.F0 else 0.0
        self._check_scales()
        if self.contact_form == DISPLACEMENT:
            self.cx, self.cy, self.D = 1.0, 1.0, self.d
        else:
            self.cx, self.cy, self.D = 1.0 / self.L2, 1.0 / self.L1, self.d_angle

    def _check_scales(self):
        """Refuse parameter sets whose derived quantities the float arithmetic cannot hold (they
        overflow to inf or underflow to 0): the motion could not be computed, and a step would
        make no progress."""
        for what, value in (("w1 = sqrt(g/L1)", self.w1), ("w2 = sqrt(g/L2)", self.w2),
                            ("w1^2 mu + w2^2", self.w1 * self.w1 * self.mu + self.w2 * self.w2),
                            ("m = mu M", self.m if self.mu > 0.0 else 1.0)):
            self._check_scale(what, value)

    def _check_scale(self, what, value):
        if not (math.isfinite(value) and value > 0.0):
            raise ParameterError("g, M, mu, L2, FR", (self.g, self.M, self.mu, self.L2, self.FR),
                                 f"together they make {what} = {value!r}, which float arithmetic cannot hold "
                                 "(choose scales whose products stay within about 1e-300 to 1e300)")

    def as_dict(self):
        return {name: getattr(self, name) for name in self.NAMES}


def check_restitution(e):
    value = check_finite("e", e)
    if not 0.0 <= value <= 1.0:
        raise ParameterError("e", e, "it must lie in [0, 1]")
    return value


def _check_level(fidelity, contact_form, zeta_s, zeta_p):
    if fidelity not in range(len(LEVELS)) or isinstance(fidelity, bool):
        raise ParameterError("fidelity", fidelity, "it must be one of " +
                             ", ".join(f"{i} ({name})" for i, name in enumerate(LEVELS)))
    for name, zeta in (("zeta_s", zeta_s), ("zeta_p", zeta_p)):
        if not 0.0 <= check_finite(name, zeta) < 1.0:
            raise ParameterError(name, zeta, "it must lie in [0, 1) (underdamped)")
        if zeta > 0.0 and fidelity == LINEAR:
            raise ParameterError(name, zeta, "the linear level has no viscous damping: set fidelity >= 1 (damped) "
                                 "or the ratio to 0")
    if contact_form == ANGLE and fidelity != LINEAR:
        raise ParameterError("contact_form", contact_form, f"the angle form as printed is a reading of the linear "
                             f"level only; fidelity {fidelity} ({LEVELS[fidelity]}) needs contact_form 0")
