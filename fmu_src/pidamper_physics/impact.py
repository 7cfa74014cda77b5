"""The impact law of every particle model (Damper's levels, DamperUnit): Newton's, restitution e.

Between the primary (mass M, velocity v) and the particle (m = mu M, u):

Momentum M v + m u is conserved and u+ - v+ = -e (u - v):

    v+ = ((1 - mu e) v + mu (1 + e) u) / (1 + mu)
    u+ = ((1 + e) v + (mu - e) u) / (1 + mu)

The paper names the particle with index 1; with mu = m/M the law conserves
momentum only when v is the primary, as here.  Energy lost:
dE = 0.5 M mu / (1 + mu) (1 - e^2) (u - v)^2.

The restitution e is the model's constant (tunable) or, with the materials given (Contact below),
a function of each impact's approach speed: Equation 18 as printed, Johnson's elastic-plastic law
or Thornton's; Contact also gives each impact's peak force, peak contact pressure, duration and
whether the stop yielded.
"""
import math

from .refusals import ParameterError, check_finite


def collide(v, u, mu, e):
    """Velocities (v+, u+) of primary and particle after an impact."""
    q = 1.0 + mu
    w = u - v  # relative velocity before
    # centre-of-mass form: exact momentum to rounding, restitution to rounding
    vc = (v + mu * u) / q
    return vc + mu * e * w / q, vc - e * w / q


def impact_loss(M, mu, e, v, u):
    """Energy [J] lost in an impact with pre-impact velocities v (primary), u (particle)."""
    w = u - v
    return 0.5 * M * mu / (1.0 + mu) * (1.0 - e * e) * w * w



def relative(w, m, M_s, reduced, e, impulse_aware):
    """The same law in the unit's form (unit.py: particle m on a structure of mass M_s, reduced mass
    m M_s / (m + M_s), at approach velocity w = r' in the attachment's frame): (impulse J on the
    structure [N s], r' after [m/s], energy lost [J]).  Impulse-aware: the two-body law, r' -> -e w.
    Mean force: the attachment's velocity jump reaches the unit only through its next input, so
    r' -> w (m - e M_s) / (m + M_s); where that still approaches the stop (m > e M_s) the caller
    makes the impact plastic in the unit's frame (plastic_in_unit_frame)."""
    J = reduced * (1.0 + e) * w
    loss = 0.5 * reduced * (1.0 - e * e) * w * w
    if impulse_aware:
        return J, -e * w, loss
    return J, w * (m - e * M_s) / (m + M_s), loss


def plastic_in_unit_frame(w, m, M_s):
    """(J, r' after, loss) of the mean-force unit's plastic impact: J = m w, r' -> 0 (see relative)."""
    return m * w, 0.0, 0.5 * m * w * w * (M_s - m) / M_s


# ---- the materials: e from the impact, and the impact's force, pressure and duration -------------
#
# Every particle model hands each impact's normal approach speed w [m/s] and reduced mass m* [kg] to
# Tally.impact, which answers the restitution to apply (Contact.restitution) and books what the
# contact did (Contact.hit).  The contact is
# Hertz's (elastic sphere of radius R on a flat: Johnson 1985, 4.2 and 11.4) until the peak pressure
# reaches YIELD_ONSET S_y, then Thornton's (1997) elastic-perfectly-plastic law: the pressure is held
# at that limit while the contact grows (F = F_y + pi p_y R (delta - delta_y)) and the unloading is
# Hertzian from a flattened radius R_p.  The same contact serves every restitution law, so the
# forces of a constant-e run and of a material-law run are comparable.

CONSTANT, PRINTED, JOHNSON, THORNTON = 0, 1, 2, 3
#: the restitution laws by number (parameter `restitution`)
LAWS = ("constant e", "Eq. 18 as printed", "Johnson (1985) 11.5", "Thornton (1997)")
#: Hertz's peak pressure p0 at first yield over the yield strength (Johnson 1985, 6.2; nu = 0.3)
YIELD_ONSET = 1.6
#: Johnson's dynamic yield pressure p_d over the yield strength (the mean pressure of a fully
#: plastic indentation, about 3 Y: Johnson 1985, 6.4 and 11.5)
PLASTIC_PRESSURE = 3.0
#: Equation 18's constant as printed
PRINT_CONSTANT = 3.1
#: Johnson's e^2 = (3 pi^(5/4) 4^(3/4) / 10) (p_d/E*) (m* w^2 / (2 p_d R^3))^(-1/4): its root
JOHNSON_CONSTANT = math.sqrt(3.0 * math.pi ** 1.25 * 4.0 ** 0.75 / 10.0)
#: the integral of ds / sqrt(1 - s^(5/2)) over [0, 1]: Hertz's loading time = this * delta_max / w
_HERTZ_QUARTER = 0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
#: Hertz's contact time T = HERTZ_TIME (m*^2 / (R E*^2 w))^(1/5) (= 2.868266)
HERTZ_TIME = 2.0 * _HERTZ_QUARTER * (15.0 / 16.0) ** 0.4
#: a contact longer than this share of the primary's period is warned about: the instantaneous
#: impact the model applies then misplaces the impulse in the primary's cycle
SHORT_CONTACT = 0.05
#: the materials' parameters and their defaults: restitution 0 (the constant e); steel on steel;
#: R = 0: no contact model (no forces computed) unless a radius is given
MATERIAL_DEFAULTS = {"restitution": CONSTANT, "S_y": 300e6, "E1": 200e9, "nu1": 0.3, "E2": 200e9, "nu2": 0.3,
                     "R": 0.0, "e_max": 0.95}
MATERIAL_NAMES = tuple(MATERIAL_DEFAULTS)


def check_contact(restitution=CONSTANT, S_y=300e6, E1=200e9, nu1=0.3, E2=200e9, nu2=0.3, R=0.0, e_max=0.95):
    """The Contact of these materials, or None (R = 0 with the constant e: no contact model); a
    ParameterError names a value outside its range."""
    if type(restitution) is not int or restitution not in range(len(LAWS)):
        raise ParameterError("restitution", restitution, "it must be one of " +
                             ", ".join(f"{k} ({name})" for k, name in enumerate(LAWS)))
    for name, value in (("S_y", S_y), ("E1", E1), ("E2", E2)):
        if check_finite(name, value) <= 0.0:
            raise ParameterError(name, value, "it must be > 0 [Pa]")
    for name, value in (("nu1", nu1), ("nu2", nu2)):
        if not -1.0 < check_finite(name, value) < 0.5:
            raise ParameterError(name, value, "a Poisson's ratio must lie in (-1, 0.5)")
    if not 0.0 < check_finite("e_max", e_max) <= 1.0:
        raise ParameterError("e_max", e_max, "it must lie in (0, 1]")
    if check_finite("R", R) < 0.0 or (R == 0.0 and restitution != CONSTANT):
        raise ParameterError("R", R, "the radius of the particle's contact surface must be > 0 [m] (0, no contact "
                                     "model, only with restitution = 0)")
    if R == 0.0:
        return None
    return Contact(restitution, float(S_y), float(E1), float(nu1), float(E2), float(nu2), float(R), float(e_max))


def hertz_loading_time(s):
    """The integral of ds' / sqrt(1 - s'^(5/2)) over [0, s], 0 <= s <= 1 (Hertz's loading time to
    the indentation s delta_max is this times delta_max / w): binomial series in x = s^(5/2) for
    x <= 1/2, else in 1 - x from the complete integral, so each converges at least as 2^-k."""
    x = s ** 2.5
    if x <= 0.5:  # (2/5) sum_k C(-1/2, k) (-x)^k x^(2/5) / (k + 2/5)
        term, total, k = x ** 0.4, 0.0, 0
        while True:
            piece = term / (k + 0.4)
            total += piece
            if piece <= 1e-17 * total:
                return 0.4 * total
            k += 1
            term *= x * (k - 0.5) / k
    y = 1.0 - x  # (2/5) int_0^y z^(-1/2) (1 - z)^(-3/5) dz, subtracted from the complete integral
    term, total, k = math.sqrt(y), 0.0, 0
    while True:
        piece = term / (k + 0.5)
        total += piece
        if piece <= 1e-17 * total:
            return _HERTZ_QUARTER - 0.4 * total
        k += 1
        term *= y * (k - 0.4) / k


class Contact:
    """A particle-stop pair's materials: S_y [Pa] the dynamic yield strength of the softer body,
    E1, nu1 the particle's and E2, nu2 the stop's modulus [Pa] and Poisson's ratio, R [m] the
    radius of the particle's contact surface (a sphere on a flat stop), e_max the largest e a law
    may give; `law` one of CONSTANT, PRINTED, JOHNSON, THORNTON."""

    __slots__ = ("law", "S_y", "R", "e_max", "E", "E_print", "p_y", "delta_y", "F_y", "k_p", "W_y")

    def __init__(self, law, S_y, E1, nu1, E2, nu2, R, e_max):
        self.law, self.S_y, self.R, self.e_max = law, S_y, R, e_max
        #: Hertz's two-body modulus 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
        self.E = E = 1.0 / ((1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2)
        #: the print's E/(1 - nu^2) for one material; for two, their harmonic mean: 2 E*
        self.E_print = 2.0 * E
        self.p_y = p_y = YIELD_ONSET * S_y
        self.delta_y = delta_y = R * (math.pi * p_y / (2.0 * E)) ** 2  # Hertz: p0 = (2 E*/pi) sqrt(delta/R)
        self.F_y = F_y = 4.0 / 3.0 * E * math.sqrt(R) * delta_y ** 1.5
        self.k_p = math.pi * p_y * R
        self.W_y = 0.4 * F_y * delta_y  # the energy Hertz stores up to first yield

    def yield_speed(self, m):
        """The approach speed [m/s] at which an impact of reduced mass m [kg] starts to yield."""
        return math.sqrt(2.0 * self.W_y / m)

    def restitution(self, w, m, e):
        """The e the law gives at approach speed w > 0 [m/s] and reduced mass m [kg] (the constant
        e for CONSTANT), at most e_max."""
        law = self.law
        if law == CONSTANT:
            return e
        if law == PRINTED:
            rho = 3.0 * m / (4.0 * math.pi * self.R ** 3)
            value = PRINT_CONSTANT * self.S_y ** 0.625 / math.sqrt(self.E_print) / (w ** 0.25 * rho ** 0.125)
        elif law == JOHNSON:
            p_d = PLASTIC_PRESSURE * self.S_y
            value = JOHNSON_CONSTANT * math.sqrt(p_d / self.E) / (0.5 * m * w * w / (p_d * self.R ** 3)) ** 0.125
        else:
            value = self.hit(w, m)[4]
        return value if value < self.e_max else self.e_max

    def hit(self, w, m):
        """(peak force [N], peak pressure [Pa], duration [s], plastic, e of the contact law) of an
        impact at approach speed w > 0 [m/s] with reduced mass m [kg]."""
        E, R = self.E, self.R
        root_R = math.sqrt(R)
        delta_m = (15.0 * m * w * w / (16.0 * E * root_R)) ** 0.4  # Hertz's largest indentation
        W = 0.5 * m * w * w
        if W <= self.W_y:  # elastic: Hertz
            force = 4.0 / 3.0 * E * root_R * delta_m ** 1.5
            pressure = 2.0 * E / math.pi * math.sqrt(delta_m / R)
            return force, pressure, 2.0 * _HERTZ_QUARTER * delta_m / w, False, 1.0
        F_y, k_p, p_y = self.F_y, self.k_p, self.p_y
        q = W - self.W_y  # taken by the plastic stroke s: F_y s + k_p s^2 / 2 = q
        force = F_y + 2.0 * k_p * q / (F_y + math.sqrt(F_y * F_y + 2.0 * k_p * q))
        R_p = 4.0 * E / (3.0 * force) * ((2.0 * force + F_y) / (2.0 * math.pi * p_y)) ** 1.5
        delta_e = (3.0 * force / (4.0 * E * math.sqrt(R_p))) ** (2.0 / 3.0)  # recovered on unloading
        e = math.sqrt(0.4 * force * delta_e / W)
        loading = delta_m / w * hertz_loading_time((self.delta_y / delta_m))  # Hertz up to delta_y
        omega = math.sqrt(k_p / m)
        plastic = math.atan2(math.sqrt(w * w - 2.0 * self.W_y / m) / omega, F_y / k_p) / omega
        unloading = _HERTZ_QUARTER * delta_e / (e * w)  # Hertz from delta_e at rest to separation at e w
        return force, p_y, loading + plastic + unloading, True, e


class Tally:
    """What the contacts of a model's impacts did (its materials given): `hit`, the last impact's
    (e, peak force [N], peak pressure [Pa], duration [s], plastic); `plastic`, the impacts that
    yielded the softer body; the largest force and pressure since clear(); `long_contact`, the first
    (t, duration, period) of a contact longer than SHORT_CONTACT of the primary's `period` [s]."""

    __slots__ = ("materials", "period", "hit", "plastic", "force_peak", "pressure_peak", "long_contact", "_told")
    STATE_KEYS = ("impacts_plastic", "force_peak", "pressure_peak")

    def __init__(self, materials, period):
        self.materials, self.period = materials, period
        self.hit = None
        self.plastic = 0
        self.force_peak = self.pressure_peak = 0.0
        self.long_contact = None
        self._told = False

    def news(self):
        """The first long contact, once (for a warning), else None."""
        if self.long_contact is None or self._told:
            return None
        self._told = True
        return self.long_contact

    def impact(self, t, w, mass, e, by_law):
        """The restitution of an impact at time t [s], relative velocity w [m/s] and reduced mass
        `mass` [kg]: the law's (by_law; the constant law gives e) or e; books its contact."""
        w = abs(w)
        materials = self.materials
        if w == 0.0 or mass <= 0.0:  # no contact to speak of (a massless particle: mu = 0)
            if by_law and materials.law != CONSTANT:
                e = materials.e_max  # the laws' limit of a vanishing impact
            self.hit = (e, 0.0, 0.0, 0.0, False)
            return e
        if by_law:
            e = materials.restitution(w, mass, e)
        force, pressure, duration, plastic, _ = materials.hit(w, mass)
        self.hit = (e, force, pressure, duration, plastic)
        if plastic:
            self.plastic += 1
        if force > self.force_peak:
            self.force_peak = force
        if pressure > self.pressure_peak:
            self.pressure_peak = pressure
        if self.long_contact is None and duration > SHORT_CONTACT * self.period:
            self.long_contact = (t, duration, self.period)
        return e

    def clear(self):
        """Start a new communication step: no largest force or pressure yet."""
        self.force_peak = self.pressure_peak = 0.0

    def get_state(self):
        return {"impacts_plastic": self.plastic, "force_peak": self.force_peak, "pressure_peak": self.pressure_peak}

    @staticmethod
    def check_state(state):
        """get_state's values in a state (absent in states of older builds: 0), or a ParameterError."""
        plastic = state.get("impacts_plastic", 0)
        if type(plastic) is not int or plastic < 0:
            raise ParameterError("state impacts_plastic", plastic, "it must be an integer >= 0")
        return (plastic,) + tuple(check_finite(f"state {key}", state.get(key, 0.0))
                                  for key in ("force_peak", "pressure_peak"))

    def set_state(self, values):
        """Restore the values check_state gave."""
        self.plastic, self.force_peak, self.pressure_peak = values


def step_outputs(tally):
    """(largest force [N], largest pressure [Pa] since the step began, plastic impacts so far) of
    a Tally, zeros without one (no materials): the contact outputs of every particle FMU."""
    return (0.0, 0.0, 0) if tally is None else (tally.force_peak, tally.pressure_peak, tally.plastic)


def tally(materials, period):
    """A Tally of these materials (impact.Contact) against the primary's period [s], or None."""
    return None if materials is None else Tally(materials, period)
