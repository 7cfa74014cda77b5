"""PendulumImpactDamperUnit: the particle and its stops alone, for a structure modelled elsewhere
(a thin adapter over pidamper_physics.unit.DamperUnit; conventions of adapter.py / slave.py).

Parameters m, M_s, L1, g, d, e (tunable), zeta_p, impulse_aware, r_0, r_dot_0 and the materials
(contact_tables.py); input a_s (absolute acceleration of the attachment, held over the step); outputs
F_s, J_s, t_J, r, r_dot, impacts, contact, energy_dissipated, impact_force_peak,
contact_pressure_peak, impacts_plastic; local impacts_in_step.  See the physics module for the
impact law and the two coupling modes.
"""
import uuid

from pythonfmu import Integer, Real
from pythonfmu.default_experiment import DefaultExperiment

from pidamper_physics.impact import step_outputs
from pidamper_physics.unit import DEFAULTS, DamperUnit

from .adapter import ComponentSlave
from .common import long_contact
from .contact_tables import CONTACT_OUTPUTS, MATERIALS

SOURCE_HASH = "development"  # replaced by build_fmu with a hash of the shipped sources
VERSION = "0.1.0"

MODEL = "PendulumImpactDamperUnit"

PARAMETERS = tuple((name, kind, DEFAULTS[name], unit, lo, hi, desc, name == "e")
                   for name, kind, unit, lo, hi, desc in (
    ("m", Real, "kg", 0.0, None, "particle mass (>= 0, < M_s)"),
    ("M_s", Real, "kg", 0.0, None, "mass of the structure at the attachment, used by the impact law (> 0)"),
    ("L1", Real, "m", 0.0, None, "particle pendulum length (> 0): w1 = sqrt(g/L1)"),
    ("g", Real, "m/s2", 0.0, None, "gravitational acceleration (> 0)"),
    ("d", Real, "m", 0.0, None, "clearance: stops at r = +-d (> 0)"),
    ("e", Real, "1", 0.0, 1.0, "coefficient of restitution of the two-body impact law, [0, 1] (tunable; the law "
                               "with restitution = 0)"),
    ("zeta_p", Real, "1", 0.0, 1.0, "damping ratio of the particle relative to the attachment, dashpot "
                                    "2 zeta_p m w1 ([0, 1))"),
    ("impulse_aware", Integer, None, 0, 1,
     "0: F_s carries the impacts' impulses (mean force), the unit jumps only the particle's velocity; "
     "1: J_s and t_J carry them to a structure that applies them at t_J, F_s is the smooth force and the "
     "unit jumps the attachment too (full two-body law in its frame)"),
    ("r_0", Real, "m", None, None, "initial particle position relative to the attachment (|r_0| <= d)"),
    ("r_dot_0", Real, "m/s", None, None, "initial particle velocity relative to the attachment"),
) + MATERIALS)

INPUTS = (("a_s", 0.0, "m/s2", "absolute acceleration of the attachment, held over each step"),)

COMPUTED = (
    ("F_s", Real, "N", "mean force of the unit on the structure over the last step (+ along the structure's x): "
                       "wire, dashpot and stop forces, plus the step's impulses / h when impulse_aware = 0", True, ()),
    ("J_s", Real, "N.s", "impulse of the last step's impacts on the structure", True, ()),
    ("t_J", Real, "s", "|J|-weighted time of the last step's impacts (the step's end without impacts)", True, ()),
    ("r", Real, "m", "particle position relative to the attachment, r = y - x_s", True, ()),
    ("r_dot", Real, "m/s", "particle velocity relative to the attachment", True, ()),
    ("impacts", Integer, None, "impacts so far (chatter impacts and collapses included)", True, ()),
    ("contact", Integer, None, "0 free, +1/-1 particle riding that stop", True, ()),
    ("energy_dissipated", Real, "J", "energy dissipated by the impacts so far (two-body law)", True, ()),
) + tuple((name, kind, unit, desc, True, ()) for name, kind, unit, desc, _ in CONTACT_OUTPUTS) + (
    ("impacts_in_step", Integer, None, "impacts of the last step", False, ()),
)


class PendulumImpactDamperUnit(ComponentSlave):
    """The particle and its stops, driven by the attachment's acceleration, exact event-driven."""

    PARAMETERS = PARAMETERS
    INPUTS = INPUTS
    COMPUTED = COMPUTED

    author = "pidamper developers"
    description = ("Pendulum impact damper unit: the particle and its stops alone, driven by the absolute "
                   "acceleration of its attachment; exact event-driven (impacts, chatter, sticking inside doStep)")
    version = f"{VERSION}+{SOURCE_HASH}"
    license = "MIT"
    default_experiment = DefaultExperiment(start_time=0.0, stop_time=10.0, step_size=0.001)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.guid = uuid.uuid5(uuid.NAMESPACE_URL, f"pidamper/{MODEL}/" + SOURCE_HASH)

    def _build_core(self):
        values = self._values
        core = DamperUnit(**{name: values[name] for name in DamperUnit.NAMES}, t0=self._t0)
        core.bound_work()
        return core

    def _advance(self, core, t_end):
        core.advance(t_end, self._values["a_s"])
        late = None if core.contacts is None else core.contacts.news()
        if late is not None:
            self._warn(long_contact(*late).replace("primary's", "particle's"))

    def _tune(self, core, name, value):
        core.set_restitution(value)

    def _computed(self, c):
        return (c.F_s, c.J_s, c.t_J, c.r, c.rd, c.impacts, c.contact, c.dissipated, *step_outputs(c.contacts),
                c.impacts_in_step)
