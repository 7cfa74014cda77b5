"""The classical tuned mass damper (TMD) as a configuration of the damper FMU: the particle with
its stops out of reach (clearance FAR) and its dashpot zeta_p is a linear TMD on its floor.

Tuning rules, for an undamped single-degree-of-freedom primary of mass M and frequency w_n with an
absorber of mass m = mu M, frequency w_a = f w_n and dashpot c = 2 zeta m w_a (zeta relative to the
absorber's own frequency, the FMU's zeta_p):

- Den Hartog (1956), harmonic force on the primary: f = 1 / (1 + mu),
  zeta = sqrt(3 mu / (8 (1 + mu))); the response at the two fixed points is sqrt(1 + 2 / mu) times
  the static one.
- Warburton (1982), white-noise ground acceleration, least variance of the primary's displacement:
  f = sqrt(1 - mu / 2) / (1 + mu), zeta = sqrt(mu (1 - mu / 4) / (4 (1 + mu) (1 - mu / 2))).

On a building the primary is its first mode seen from the damper floor: mu is the effective mass
ratio m / M1*, M1* = sum_i m_i phi_i^2 / phi_f^2 (the mode scaled to 1 at the damper floor f), and
f is the FMU's FR (w1 over the building's first frequency)."""
import math

from pidamper_physics import Params

#: the clearance [m] of a TMD: stops out of reach
FAR = 100.0


def den_hartog(mu):
    """(f, zeta) of Den Hartog's optimum for mass ratio mu > 0."""
    _check(mu)
    return 1.0 / (1.0 + mu), math.sqrt(3.0 * mu / (8.0 * (1.0 + mu)))


def warburton(mu):
    """(f, zeta) of Warburton's optimum for white-noise ground acceleration, mass ratio mu in (0, 2)."""
    _check(mu, 2.0)
    return (math.sqrt(1.0 - mu / 2.0) / (1.0 + mu),
            math.sqrt(mu * (1.0 - mu / 4.0) / (4.0 * (1.0 + mu) * (1.0 - mu / 2.0))))


#: the rules a study names (a configuration's `tmd`)
RULES = {"den-hartog": den_hartog, "warburton": warburton}


def _check(mu, top=math.inf):
    if not (isinstance(mu, (int, float)) and 0.0 < mu < top):
        raise ValueError(f"mu = {mu!r} is not allowed: a mass ratio in (0, {top:g})")


def effective_mass_ratio(values, mu):
    """m / M1* of a particle of mass ratio mu (of the building's mass) on the building whose FMU
    start values are `values` (storeys >= 1): the first mode scaled to 1 at the damper floor; mu
    itself for the pendulum primary (storeys = 0)."""
    bare = Params.from_variables({**values, "mu": 0.0})
    building = bare.building
    if building is None:
        return mu
    floor = bare.floor
    phi = [row[0] for row in building.shapes]
    modal = sum(m * (p / phi[floor]) ** 2 for m, p in zip(building.masses, phi))
    return mu * building.total_mass / modal


def configuration(values, mu, rule):
    """The FMU parameters of a TMD of mass ratio mu (of the building's mass) tuned by `rule` (a key
    of RULES) on the building of start values `values`: mu, FR, zeta_p and d = FAR."""
    if rule not in RULES:
        raise ValueError(f"tmd = {rule!r} is not allowed: one of {', '.join(RULES)}")
    f, zeta = RULES[rule](effective_mass_ratio(values, mu))
    return {"mu": mu, "FR": f, "zeta_p": zeta, "d": FAR}
