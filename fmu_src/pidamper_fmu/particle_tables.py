"""The variables of the FMUs with the particle on its primary: PendulumImpactDamper (n = 0) and
DampedShearBuilding<n> (n = 1..10), one table each, built by `tables(n)`.

A building keeps the pendulum's variable names for what it shares (its primary is the damper
floor), drops what only the pendulum primary has (PENDULUM_ONLY: its floors start at rest and it
has the displacement form only), and adds exactly n floors' and storeys' variables.
"""
from pythonfmu import Integer, Real

from pidamper_physics import DEFAULTS, INITIAL_DEFAULTS, SmallAngleMonitor
from pidamper_physics.params import FLOOR_MASS, STOREY_HEIGHT, STOREY_STIFFNESS

from .contact_tables import CONTACT_OUTPUTS, MATERIAL_DEFAULTS, MATERIALS
from .storey_tables import yielding_outputs, yielding_parameters

START = {**DEFAULTS, **INITIAL_DEFAULTS, **MATERIAL_DEFAULTS, "angle_limit": SmallAngleMonitor.DEFAULT_LIMIT}

# name, unit, description: held over each communication step
INPUTS = (("F", "N", "horizontal force on the primary mass (a building: on the damper floor)"),
          ("a_g", "m/s2", "ground acceleration of a base excitation (acts on both bodies)"))

# name, type, unit, min, max, description (start values: START)
_PARAMETERS = (
    ("g", Real, "m/s2", 0.0, None, "gravitational acceleration (> 0)"),
    ("M", Real, "kg", 0.0, None, "primary mass (> 0)"),
    ("mu", Real, "1", 0.0, None, "mass ratio m/M (>= 0; 0 = no damper)"),
    ("L2", Real, "m", 0.0, None, "primary pendulum length (> 0)"),
    ("FR", Real, "1", 0.0, None, "frequency ratio w1/w2 (> 0); particle length L1 = L2/FR^2"),
    ("d", Real, "m", 0.0, None, "clearance, displacement form: contact at x - y = +-d (> 0)"),
    ("d_angle", Real, "rad", 0.0, None, "clearance, angle form: contact at theta - alpha = +-d_angle (> 0)"),
    ("e", Real, "1", 0.0, 1.0, "coefficient of restitution in [0, 1] (tunable; the law with restitution = 0)"),
    ("contact_form", Integer, None, 0, 1, "0 = displacement form (default), 1 = angle form as printed in the paper"),
    ("F0", Real, "N", None, None, "amplitude of the built-in harmonic force F0 sin(Omega t + phi)"),
    ("Omega", Real, "rad/s", 0.0, None, "frequency of the built-in harmonic force (>= 0)"),
    ("phi", Real, "rad", None, None, "phase of the built-in harmonic force"),
    ("theta_0", Real, "rad", None, None, "initial primary angle"),
    ("theta_dot_0", Real, "rad/s", None, None, "initial primary angular velocity"),
    ("alpha_0", Real, "rad", None, None, "initial particle angle"),
    ("alpha_dot_0", Real, "rad/s", None, None, "initial particle angular velocity"),
    ("fidelity", Integer, None, 0, 3, "model level: 0 linear (the paper), 1 damped (+ dashpots zeta_s, zeta_p), "
                                       "2 coupled (particle hung from the moving primary), 3 nonlinear (large angles)"),
    ("zeta_s", Real, "1", 0.0, 1.0, "viscous damping ratio of the primary, dashpot 2 zeta_s M w2 (fidelity >= 1; < 1)"),
    ("zeta_p", Real, "1", 0.0, 1.0, "viscous damping ratio of the particle relative to its pivot, dashpot "
                                    "2 zeta_p m w1 (fidelity >= 1; < 1)"),
    ("angle_limit", Real, "rad", 0.0, None, "swing beyond which the linear (small-angle) model warns, once per run "
                                            "(0.4 rad: its frequency is then 1 % off; 0 = never)"),
) + MATERIALS
#: parameters of the pendulum primary only
PENDULUM_ONLY = ("M", "L2", "d_angle", "contact_form", "theta_0", "theta_dot_0")
#: a building's own wording (min, max, description) of the parameters it shares
_BUILDING_PARAMETERS = {
    "mu": (0.0, None, "mass ratio m / the building's total mass (>= 0; 0 = no damper)"),
    "FR": (0.0, None, "frequency ratio w1 / w_1 (> 0): the particle's pendulum frequency over the building's "
                      "first natural frequency; L1 = g / w1^2"),
    "d": (0.0, None, "clearance: the particle meets a stop at y - x_j = -+d (> 0)"),
    "F0": (None, None, "amplitude of the built-in harmonic force F0 sin(Omega t + phi) on the damper floor"),
    "fidelity": (0, 2, "model level: 0 linear, 1 damped (the building's damping zeta_s, particle dashpot zeta_p), "
                       "2 coupled "
                       "(the same: the particle always hangs from its moving floor)"),
    "zeta_s": (0.0, 1.0, "damping ratio of the building (fidelity >= 1; < 1): of every elastic mode, or of the two "
                         "Rayleigh modes, as `damping` chooses"),
    "alpha_0": (None, None, "initial particle angle (the building starts at rest)"),
    "angle_limit": (0.0, None, "the particle's swing beyond which the linear (small-angle) model warns, once per run "
                               "(0.4 rad: its frequency is then 1 % off; 0 = never); the floors: drift_limit"),
}

# name, type, unit, description, direct feedthrough from F.  The outputs are the component's
# interface (what a host records by default and connects); the derived and bookkeeping values are
# local variables a host reads by name.  Both are computed together after each step and have
# consecutive value references in this order, so one pack fills them all.
OUTPUTS = (
    ("theta", Real, "rad", "primary angle", False),
    ("theta_dot", Real, "rad/s", "primary angular velocity", False),
    ("alpha", Real, "rad", "particle angle (of its wire from the vertical)", False),
    ("alpha_dot", Real, "rad/s", "particle angular velocity", False),
    ("a", Real, "m/s2", "primary acceleration between impacts, relative to the ground", True),
    ("contact_force", Real, "N", "force of the stop on the particle while riding it, else 0", True),
    ("energy", Real, "J", "mechanical energy of the level's model (linear: 0.5 M (v^2 + w2^2 x^2) + "
                          "0.5 m (u^2 + w1^2 y^2))", False),
    ("energy_dissipated", Real, "J", "energy dissipated by impacts so far", False),
    ("impacts", Integer, None, "impacts applied so far (chatter impacts included)", False),
    ("contact", Integer, None, "0 free, +1/-1 particle riding that stop", False),
) + CONTACT_OUTPUTS
DERIVED = (
    ("x", Real, "m", "primary displacement (linear levels: L2*theta; nonlinear: L2 sin(theta))", False),
    ("y", Real, "m", "particle displacement (linear, damped: L1*alpha; coupled: x + L1*alpha; nonlinear: "
                     "x + L1 sin(alpha))", False),
    ("z", Real, "m", "gap x - y", False),
    ("energy_viscous", Real, "J", "energy taken by the viscous dashpots so far (fidelity >= 1)", False),
    ("work_in", Real, "J", "work done by the applied forces so far, integral of F v dt", False),
    ("impacts_in_step", Integer, None, "impacts applied during the last communication step", False),
    ("impacts_unrecorded", Integer, None,
     "impacts of the last step beyond the 16 record slots (counted, not recorded)", False),
)
#: a building's own wording of the outputs it shares
_BUILDING_OUTPUTS = {
    "theta": "the damper floor's x / L2, L2 = g / w_1^2 the pendulum of the building's first frequency w_1",
    "theta_dot": "the damper floor's velocity / L2",
    "alpha": "particle angle: (y - x_j) / L1, its pivot on the damper floor",
    "a": "the damper floor's acceleration between impacts, relative to the ground",
    "energy": "the floors' kinetic and strain energy + 0.5 m (u^2 + w1^2 (y - x_j)^2)",
    "x": "the damper floor's displacement, relative to the ground",
    "y": "particle displacement, relative to the ground",
    "z": "gap x - y (the damper floor's displacement minus the particle's)",
}

# Per-step impact record: local variables (hosts do not record them by default; any host reads them
# by name after fmi2DoStep).  Slots beyond impacts_in_step hold zeros.  The Real fields of all slots
# come first (slot-major), then the sides, then the plastic flags.
IMPACT_SLOTS = 16
IMPACT_REALS = (
    ("t", "s", "time"),
    ("v_rel_before", "m/s", "particle minus primary velocity before"),
    ("v_rel_after", "m/s", "particle minus primary velocity after"),
    ("energy_lost", "J", "energy lost"),
    ("theta", "rad", "primary angle"),
    ("e", "1", "restitution applied"),
    ("force_peak", "N", "peak contact force (0 without materials)"),
    ("pressure_peak", "Pa", "peak contact pressure (0 without materials)"),
    ("duration", "s", "contact duration (0 without materials)"),
)
RECORD = tuple((f"impact[{k + 1}].{field}", Real, unit, f"impact {k + 1} of the last step: {desc}")
               for k in range(IMPACT_SLOTS) for field, unit, desc in IMPACT_REALS) + tuple(
    (f"impact[{k + 1}].side", Integer, None, f"impact {k + 1} of the last step: stop hit, +1 (z = +d) or -1 (z = -d)")
    for k in range(IMPACT_SLOTS)) + tuple(
    (f"impact[{k + 1}].plastic", Integer, None, f"impact {k + 1} of the last step: 1 if its contact yielded the "
                                                "softer body, else 0")
    for k in range(IMPACT_SLOTS))


def building_outputs(n):
    """The outputs of an n-storey building, after OUTPUTS and DERIVED (name, type, unit,
    description, direct feedthrough from F)."""
    floors = range(1, n + 1)
    located = "since the start of the run, located exactly between the communication points"
    return (
        tuple((f"floor[{k}].x", Real, "m", f"displacement of floor {k} relative to the ground", False) for k in floors)
        + tuple((f"floor[{k}].a", Real, "m/s2", f"absolute acceleration of floor {k}", True) for k in floors)
        + tuple((f"storey[{k}].drift", Real, "m", f"drift of storey {k}: floor[{k}].x - floor[{k - 1}].x", False)
                for k in floors)
        + (("base_shear", Real, "N", "force of the building on the ground (sum of K x + C x')", False),)
        + tuple((f"storey[{k}].drift_ratio", Real, "1", f"drift ratio of storey {k}: its drift / storey[{k}].h", False)
                for k in floors)
        + tuple((f"storey[{k}].drift_ratio_max", Real, "1", f"largest |drift ratio| of storey {k} {located}", False)
                for k in floors)
        + tuple((f"floor[{k}].v_abs_max", Real, "m/s", f"largest |absolute velocity| of floor {k} {located} (both "
                 "sides of a velocity jump)", False) for k in floors)
        + tuple((f"floor[{k}].a_abs_max", Real, "m/s2", f"largest |absolute acceleration| of floor {k} {located} "
                 "(its regular part: an impact's velocity jump is an impulse)", False) for k in floors)
        + tuple((name, kind, unit, desc, False) for name, kind, unit, desc in yielding_outputs(n)))


def tables(n):
    """(PARAMETERS, COMPUTED) of the particle on the pendulum primary (n = 0) or on an n-storey
    building: PARAMETERS as (name, type, start, unit, min, max, description), COMPUTED as OUTPUTS
    + DERIVED (+ building_outputs(n))."""
    if n == 0:
        return tuple((name, kind, START[name], unit, lo, hi, desc)
                     for name, kind, unit, lo, hi, desc in _PARAMETERS), OUTPUTS + DERIVED
    params = [(name, kind, START[name], unit) + _BUILDING_PARAMETERS.get(name, (lo, hi, desc))
              for name, kind, unit, lo, hi, desc in _PARAMETERS if name not in PENDULUM_ONLY]
    floors = range(1, n + 1)
    params.append(("damper_floor", Integer, 0, None, 0, n, f"floor the particle hangs from (0 = the top floor; "
                                                            f"else 1..{n})"))
    params += [(f"floor[{k}].m", Real, FLOOR_MASS, "kg", 0.0, None, f"mass of floor {k} (> 0)") for k in floors]
    params += [(f"storey[{k}].k", Real, STOREY_STIFFNESS, "N/m", 0.0, None,
                f"stiffness of storey {k}, joining floor {k - 1} to floor {k} (> 0)") for k in floors]
    params += [(f"storey[{k}].h", Real, STOREY_HEIGHT, "m", 0.0, None,
                f"height of storey {k} (> 0): its drift ratio is its drift / h") for k in floors]
    params += yielding_parameters(n)
    shared = tuple((name, kind, unit, _BUILDING_OUTPUTS.get(name, desc), feed)
                   for name, kind, unit, desc, feed in OUTPUTS + DERIVED)
    return tuple(params), shared + building_outputs(n)
