"""The materials' variables every FMU with a particle has (PendulumImpactDamper,
DampedShearBuilding<N>, PendulumImpactDamperUnit): parameters restitution, S_y, E1, nu1, E2, nu2, R,
e_max; outputs impact_force_peak, contact_pressure_peak, impacts_plastic (pidamper_physics.impact).
"""
from pythonfmu import Integer, Real

from pidamper_physics.impact import MATERIAL_DEFAULTS

__all__ = ["CONTACT_OUTPUTS", "MATERIAL_DEFAULTS", "MATERIALS"]

# name, type, unit, min, max, description: the particle's and the stop's materials (every particle FMU)
MATERIALS = (
    ("restitution", Integer, None, 0, 3, "restitution law: 0 the constant e (default); from each impact's approach "
                                         "speed: 1 Eq. 18 as printed, 2 Johnson (1985), 3 Thornton (1997); at most "
                                         "e_max"),
    ("S_y", Real, "Pa", 0.0, None, "dynamic yield strength of the softer body (> 0)"),
    ("E1", Real, "Pa", 0.0, None, "Young's modulus of the particle (> 0)"),
    ("nu1", Real, "1", -1.0, 0.5, "Poisson's ratio of the particle, in (-1, 0.5)"),
    ("E2", Real, "Pa", 0.0, None, "Young's modulus of the stop (> 0)"),
    ("nu2", Real, "1", -1.0, 0.5, "Poisson's ratio of the stop, in (-1, 0.5)"),
    ("R", Real, "m", 0.0, None, "radius of the particle's contact surface on a flat stop (> 0; 0, the default: "
                                "no contact model, only with restitution = 0)"),
    ("e_max", Real, "1", 0.0, 1.0, "largest restitution a law from the materials may give, in (0, 1]"),
)
#: the outputs the materials give (after the other outputs)
CONTACT_OUTPUTS = (
    ("impact_force_peak", Real, "N", "largest peak contact force of the last step's impacts (0 without impact "
                                     "or without materials: R = 0)", False),
    ("contact_pressure_peak", Real, "Pa", "largest peak contact pressure of the last step's impacts (0 without "
                                          "impact or without materials)", False),
    ("impacts_plastic", Integer, None, "impacts so far whose contact yielded the softer body (materials given)",
     False),
)
