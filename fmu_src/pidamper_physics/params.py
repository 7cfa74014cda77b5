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

Buildings (storeys >= 1): the pendulum primary is replaced by a linear shear building of that
many storeys (building.py) with floor masses floor_m [kg] and storey stiffnesses storey_k [N/m]
(sequences, floor / storey 1 first; entries beyond `storeys` are ignored), every mode damped at
zeta_s from the damped level on; the particle (m = mu * the building's mass, w1 = FR * the
building's first natural frequency w_1, L1 = g / w1^2) hangs from floor damper_floor (0 = the
top floor), whose mass is then M; M, L2 and the pendulum primary's w2 play no part.
"""
import math

from .building import ShearBuilding
from .impact import MATERIAL_DEFAULTS, MATERIAL_NAMES, check_contact
from .refusals import SCALE_RANGE, ParameterError, check_finite
from .imk_storeys import IMK_DEFAULTS, check_storey_law, imk_law, imk_tables
from .storeys import COLLAPSE_DRIFT, HARDENING, check_damping, check_storeys

DISPLACEMENT = 0
ANGLE = 1

LINEAR, DAMPED, COUPLED, NONLINEAR = 0, 1, 2, 3
#: fidelity levels by number: each adds physics to the one before
LEVELS = ("linear", "damped", "coupled", "nonlinear")

#: default parameters (the FMU's start values): the paper's free-vibration case
DEFAULTS = {"g": 9.81, "M": 1.0, "mu": 0.1, "L2": 1.0, "FR": 5.0, "d": 0.1, "d_angle": 0.1, "e": 0.2,
            "contact_form": DISPLACEMENT, "F0": 0.0, "Omega": math.sqrt(9.81 / 1.0), "phi": 0.0, "fidelity": LINEAR,
            "zeta_s": 0.0, "zeta_p": 0.0, "storeys": 0, "damper_floor": 0}
#: most storeys of a building (storeys >= 1); default floor masses [kg] and storey stiffnesses
#: [N/m] (of the FMUs with a building): a uniform building whose first period is about 0.16 s per
#: storey (0.50 s at 3, 1.5 s at 10)
MAX_STOREYS = 10
FLOOR_MASS = 1.0e5
STOREY_STIFFNESS = 8.0e7
#: default storey height [m] (storey[k].h: the drift ratio is the drift / h)
STOREY_HEIGHT = 3.0
#: default initial state [rad, rad/s]: particle at rest, primary started by a velocity
INITIAL_DEFAULTS = {"theta_0": 0.0, "theta_dot_0": 0.5, "alpha_0": 0.0, "alpha_dot_0": 0.0}




#: least 1 - zeta^2 of a dashpot: the eigenvalues -zeta w +- i w sqrt(1 - zeta^2) of its mode stay
#: 2e-6 w apart, so the modal closed form keeps about 10 of its 16 digits
ZETA_GAP = 1e-12


def _positive(name, value):
    if check_finite(name, value) <= 0.0:
        raise ParameterError(name, value, "it must be > 0")


class Params:
    """Validated physical parameters plus the derived quantities the solver uses."""

    NAMES = ("g", "M", "mu", "L2", "FR", "d", "d_angle", "e", "contact_form", "F0", "Omega", "phi", "fidelity",
             "zeta_s", "zeta_p", "storeys", "damper_floor", "floor_m", "storey_k", "storey_h", "storey_Fy", "storey_b",
             "p_delta", "collapse_drift", "damping", "storey_law", "storey_imk") + MATERIAL_NAMES

    def __init__(self, g=DEFAULTS["g"], M=DEFAULTS["M"], mu=DEFAULTS["mu"], L2=DEFAULTS["L2"],
                 FR=DEFAULTS["FR"], d=DEFAULTS["d"], d_angle=DEFAULTS["d_angle"], e=DEFAULTS["e"],
                 contact_form=DEFAULTS["contact_form"], F0=DEFAULTS["F0"], Omega=DEFAULTS["Omega"],
                 phi=DEFAULTS["phi"], fidelity=DEFAULTS["fidelity"], zeta_s=DEFAULTS["zeta_s"],
                 zeta_p=DEFAULTS["zeta_p"], storeys=0, damper_floor=0, floor_m=None, storey_k=None, storey_h=None,
                 storey_Fy=None, storey_b=None, p_delta=0, collapse_drift=COLLAPSE_DRIFT, damping=0, storey_law=0,
                 storey_imk=None, **materials):
        for name in ("g", "M", "L2", "FR", "d", "d_angle"):
            _positive(name, locals()[name])
        if check_finite("mu", mu) < 0.0:
            raise ParameterError("mu", mu, "it must be >= 0 (0 means no damper)")
        check_restitution(e)
        unknown = sorted(set(materials) - set(MATERIAL_NAMES))
        if unknown:
            raise TypeError(f"Params got unexpected keyword arguments {unknown}")
        materials = {**MATERIAL_DEFAULTS, **materials}
        #: the particle-stop materials (impact.Contact), or None: the constant e, no forces
        self.materials = check_contact(**materials)
        for name, value in materials.items():
            setattr(self, name, value)
        if contact_form not in (DISPLACEMENT, ANGLE) or isinstance(contact_form, bool):
            raise ParameterError("contact_form", contact_form, "it must be 0 (displacement) or 1 (angle as printed)")
        check_finite("F0", F0)
        if check_finite("Omega", Omega) < 0.0:
            raise ParameterError("Omega", Omega, "it must be >= 0")
        check_finite("phi", phi)
        _check_level(fidelity, contact_form, zeta_s, zeta_p)
        damping = check_damping_model(damping)
        self.g, self.M, self.mu, self.L2, self.FR = float(g), float(M), float(mu), float(L2), float(FR)
        self.d, self.d_angle, self.e = float(d), float(d_angle), float(e)
        self.contact_form = int(contact_form)
        self.F0, self.Omega, self.phi = float(F0), float(Omega), float(phi)
        self.fidelity, self.zeta_s, self.zeta_p = int(fidelity), float(zeta_s), float(zeta_p)
        self.storeys, self.damper_floor, self.building = _check_building(storeys, damper_floor, fidelity, contact_form)
        self.floor_m = _per_storey("floor_m", floor_m, FLOOR_MASS)
        self.storey_k = _per_storey("storey_k", storey_k, STOREY_STIFFNESS)
        self.storey_h = _per_storey("storey_h", storey_h, STOREY_HEIGHT)
        self.storey_Fy = _per_storey("storey_Fy", storey_Fy, 0.0)
        self.storey_b = _per_storey("storey_b", storey_b, HARDENING)
        self.p_delta, self.collapse_drift, self.damping = p_delta, collapse_drift, damping
        self.storey_law, self.storey_imk = check_storey_law(storey_law), storey_imk
        self.law = None  # the storeys' law (storeys.Storeys) of a building
        self.imk = None  # with storey_law 1: per storey the 21 IMKBilin values
        if self.storeys:
            self._set_building()
        else:
            self.m = self.mu * self.M
            self.L1 = self.L2 / (self.FR * self.FR)
            self.w2 = math.sqrt(self.g / self.L2)
            self.w1 = math.sqrt(self.g / self.L1) if self.L1 > 0.0 else math.inf  # FR^2 overflowed: refused below
        # the built-in harmonic's frequency where it acts (0 without it: a frequency that acts on
        # nothing sets no step size and no rounding allowance)
        self.Omega_acting = self.Omega if self.F0 else 0.0
        self._check_scales()
        if self.contact_form == DISPLACEMENT:
            self.cx, self.cy, self.D = 1.0, 1.0, self.d
        else:
            self.cx, self.cy, self.D = 1.0 / self.L2, 1.0 / self.L1, self.d_angle

    def _check_scales(self):
        """Refuse parameter sets whose scales the float arithmetic cannot honour: every length,
        mass, frequency and load per mass must lie within SCALE_RANGE (lengths and loads may also
        be 0 where allowed), so that their squares and pairwise products stay normal floats and the
        motion's energy, accelerations and trig arguments are computed to full precision."""
        lo, hi = SCALE_RANGE
        derived = "g, M, mu, L2, FR"
        for names, what, value in (("g", "g", self.g), ("M", "M", self.M), ("L2", "L2", self.L2),
                                   (derived, "L1 = L2/FR^2", self.L1), (derived, "w2 = sqrt(g/L2)", self.w2),
                                   (derived, "w1 = sqrt(g/L1)", self.w1), ("mu", "m = mu M", self.m or lo),
                                   ("d", "d", self.d), ("d_angle", "d_angle", self.d_angle),
                                   ("F0", "|F0|/M", abs(self.F0) / self.M or lo), ("Omega", "Omega", self.Omega or lo)):
            if not lo <= value <= hi:
                values = tuple(getattr(self, n) for n in names.split(", "))
                raise ParameterError(names, values if len(values) > 1 else values[0],
                                     f"{what} = {value!r} lies outside {lo:g} to {hi:g}: beyond, float arithmetic "
                                     "cannot hold its squares and products (choose units that bring it inside)")

    def _set_building(self):
        """Derived quantities of a building (storeys >= 1): the ShearBuilding, the particle's m, w1,
        L1, and M = the damper floor's mass (the force F acts on that floor)."""
        n = self.storeys
        self.building = check_building(self.floor_m[:n], self.storey_k[:n], self.zeta_s, self.storey_h[:n], None,
                                       self.damping)
        self.floor = (self.damper_floor or n) - 1  # index of the damper floor
        self.M = self.building.masses[self.floor]
        self.m = self.mu * self.building.total_mass
        fy, b = self.storey_Fy[:n], self.storey_b[:n]
        if self.storey_law:
            self.imk = imk_tables(self.storey_k[:n], fy, self.storey_imk)
            fy, b = [min(t[4], t[10]) for t in self.imk], [0.0] * n
        law = check_storeys(self.storey_k[:n], fy, b, self.storey_h[:n],
                            self.floor_m[:n], self.p_delta, self.g, self.collapse_drift, (self.floor, self.m))
        if self.p_delta:  # the building of K - K_G: its modes, damping and first frequency
            self.building = check_building(self.floor_m[:n], self.storey_k[:n], self.zeta_s, self.storey_h[:n],
                                           law.geometric, self.damping)
        if self.imk is not None:
            self.law = imk_law(self.imk, law.geometric)
        elif law.any_yield:
            check_damping(law, self.zeta_s if self.fidelity else 0.0, self.building.spread)
            self.law = law
        self.w2 = self.building.w_1
        self.w1 = self.FR * self.w2
        self.L1 = self.g / (self.w1 * self.w1) if self.w1 > 0.0 else math.inf
        self.L2 = self.g / (self.w2 * self.w2)

    def as_dict(self):
        return {name: getattr(self, name) for name in self.NAMES}

    @classmethod
    def from_variables(cls, values):
        """Params from FMU variable names: the NAMES plus floor[k].m, storey[k].k and storey[k].h
        (k = 1..10); other names are ignored."""
        kwargs = {k: v for k, v in values.items() if k in cls.NAMES}
        for key, pattern, default in (("floor_m", "floor[{}].m", FLOOR_MASS),
                                      ("storey_k", "storey[{}].k", STOREY_STIFFNESS),
                                      ("storey_h", "storey[{}].h", STOREY_HEIGHT),
                                      ("storey_Fy", "storey[{}].Fy", 0.0),
                                      ("storey_b", "storey[{}].b", HARDENING)):
            listed = [values.get(pattern.format(k)) for k in range(1, MAX_STOREYS + 1)]
            if any(v is not None for v in listed):
                kwargs[key] = [default if v is None else v for v in listed]
        if values.get("storey_law"):
            kwargs["storey_imk"] = [{name: values[f"storey[{k}].{name}"] for name in IMK_DEFAULTS
                                     if f"storey[{k}].{name}" in values} for k in range(1, MAX_STOREYS + 1)]
        return cls(**kwargs)


def check_damping_model(damping):
    """The building's damping model (building.DAMPING_MODELS) as an int, or a ParameterError naming it."""
    if damping not in (0, 1, 2) or isinstance(damping, bool) or isinstance(damping, float) and not damping.is_integer():
        raise ParameterError("damping", damping, "it must be 0 (modal: every elastic mode at zeta_s), 1 (Rayleigh on the "
                             "initial stiffness) or 2 (Rayleigh on the tangent stiffness), zeta_s at the first mode and "
                             "the third (the last of fewer)")
    return int(damping)


def check_building(masses, stiffnesses, zeta=0.0, heights=None, geometric=None, damping=0):
    """The ShearBuilding of floor masses [kg], storey stiffnesses [N/m] and storey heights [m]
    (floor / storey 1 first; heights default to STOREY_HEIGHT) damped at the ratio zeta by the
    model `damping` (building.DAMPING_MODELS: 0 every elastic mode, 1 / 2 Rayleigh on the initial /
    tangent stiffness), once they are checked: a ParameterError names the value (storeys,
    floor[k].m, storey[k].k, storey[k].h, zeta_s, damping) and the rule.  geometric: P-Delta's
    P_k / h_k [N/m] (storeys.check_storeys checks it)."""
    n = len(masses)
    heights = [STOREY_HEIGHT] * n if heights is None else list(heights)
    if not 1 <= n <= MAX_STOREYS or len(stiffnesses) != n or len(heights) != n:
        raise ParameterError("storeys", n, f"it must lie in 1..{MAX_STOREYS}, with a mass, a stiffness and a height "
                                           "per storey")
    lo, hi = SCALE_RANGE
    for pattern, values in (("floor[{}].m", masses), ("storey[{}].k", stiffnesses), ("storey[{}].h", heights)):
        for k, value in enumerate(values, start=1):
            if not lo <= check_finite(pattern.format(k), value) <= hi:
                raise ParameterError(pattern.format(k), value, f"it must lie in {lo:g} to {hi:g} (> 0)")
    zeta = check_finite("zeta_s", zeta)
    if not 0.0 <= zeta < 1.0 or 1.0 - zeta * zeta < ZETA_GAP:
        raise ParameterError("zeta_s", zeta, f"it must lie in [0, 1) with 1 - zeta_s^2 >= {ZETA_GAP:g}")
    building = ShearBuilding(masses, stiffnesses, zeta, heights, geometric, check_damping_model(damping))
    for r, z in enumerate(building.zetas):
        if not z < 1.0 or 1.0 - z * z < ZETA_GAP:
            raise ParameterError("zeta_s, damping", (zeta, damping), f"Rayleigh damping would give mode {r + 1} the "
                                 f"ratio {z:.6g} (w = {building.omegas[r]:.6g} rad/s): every mode must stay "
                                 f"underdamped, 1 - zeta^2 >= {ZETA_GAP:g}; lower zeta_s or use damping = 0")
    return building


def _per_storey(name, values, default):
    """The MAX_STOREYS values of a per-storey parameter (missing ones take the default)."""
    values = list(values) if values is not None else []
    if len(values) > MAX_STOREYS:
        raise ParameterError(name, values, f"at most {MAX_STOREYS} values (one per storey)")
    return [float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else v for v in values] + \
        [default] * (MAX_STOREYS - len(values))


def _check_building(storeys, damper_floor, fidelity, contact_form):
    """(storeys, damper_floor, None) once the building's integers are checked (its masses and
    stiffnesses are checked by ShearBuilding)."""
    if type(storeys) is not int or not 0 <= storeys <= MAX_STOREYS:
        raise ParameterError("storeys", storeys, f"it must be an integer in 0..{MAX_STOREYS} (0 = the pendulum primary)")
    if type(damper_floor) is not int or not 0 <= damper_floor <= max(storeys, 0):
        raise ParameterError("damper_floor", damper_floor, f"it must be an integer in 0..storeys = {storeys} "
                             "(0 = the top floor)")
    if storeys:
        if fidelity == NONLINEAR:
            raise ParameterError("fidelity", fidelity, "a building (storeys >= 1) is linear: fidelity 0 (no dashpots), "
                                 "1 or 2 (modal damping zeta_s and the particle dashpot zeta_p); the nonlinear level "
                                 "(3) is for the pendulum primary only")
        if contact_form != DISPLACEMENT:
            raise ParameterError("contact_form", contact_form, "a building (storeys >= 1) needs the displacement form 0")
    return storeys, damper_floor, None


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
        if not 0.0 <= check_finite(name, zeta) < 1.0 or 1.0 - zeta * zeta < ZETA_GAP:
            raise ParameterError(name, zeta, f"it must lie in [0, 1) with 1 - {name}^2 >= {ZETA_GAP:g} (underdamped: "
                                 "closer to critical damping the two eigenvalues of the mode merge and the modal "
                                 "closed form loses its digits)")
        if zeta > 0.0 and fidelity == LINEAR:
            raise ParameterError(name, zeta, "the linear level has no viscous damping: set fidelity >= 1 (damped) "
                                 "or the ratio to 0")
    if contact_form == ANGLE and fidelity != LINEAR:
        raise ParameterError("contact_form", contact_form, f"the angle form as printed is a reading of the linear "
                             f"level only; fidelity {fidelity} ({LEVELS[fidelity]}) needs contact_form 0")
