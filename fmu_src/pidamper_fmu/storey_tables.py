"""The storeys' variables every building FMU has (DampedShearBuilding<N> and ShearBuilding<N>):
parameters storey[k].Fy, storey[k].b, p_delta, collapse_drift (pidamper_physics.storeys), damping
(the model of the building's damping: pidamper_physics.building) and drift_limit
(pidamper_physics.validity.DriftMonitor); outputs storey[k].force,
storey[k].plastic_drift, energy_hysteretic, collapsed.
"""
import math

from pythonfmu import Integer, Real

from pidamper_physics import DriftMonitor, ParameterError
from pidamper_physics.storeys import COLLAPSE_DRIFT, HARDENING


def yielding_parameters(n):
    """The yielding storeys' parameters of an n-storey building (both building families):
    (name, type, start, unit, min, max, description)."""
    floors = range(1, n + 1)
    return ([(f"storey[{k}].Fy", Real, 0.0, "N", 0.0, None, f"yield force of storey {k} (bilinear with kinematic "
              "hardening, as OpenSees Steel01; 0 = elastic)") for k in floors]
            + [(f"storey[{k}].b", Real, HARDENING, "1", 0.0, 1.0, f"post-yield stiffness ratio of storey {k}, [0, 1) "
                "(0 = elastic-perfectly-plastic)") for k in floors]
            + [("p_delta", Integer, 0, None, 0, 1, "P-Delta: 0 off, 1 on (geometric stiffness -P_k / h_k of the "
                "gravity load above each storey, the particle's on its floor included)"),
               ("collapse_drift", Real, COLLAPSE_DRIFT, "1", 0.0, 1.0, "storey drift ratio at which a yielding "
                "building counts as collapsed, (0, 1]: every output holds from then"),
               ("damping", Integer, 0, None, 0, 2, "damping model at the ratio zeta_s: 0 modal (every elastic mode, "
                "the matrix kept while storeys yield), 1 Rayleigh on the initial stiffness, 2 Rayleigh on the tangent "
                "stiffness of the storeys' current regime (Rayleigh: zeta_s at the first mode and the third, or the "
                "last of fewer storeys)"),
               ("drift_limit", Real, DriftMonitor.DEFAULT_LIMIT, "1", 0.0, None, "storey drift ratio beyond which "
                "the FMU warns, once per run, that the shear building describes no real one (0 = never)")])


def drift_monitor(limit):
    """The DriftMonitor of a building FMU's drift_limit (None for 0), once it is checked."""
    if not (math.isfinite(limit) and limit >= 0.0):
        raise ParameterError("drift_limit", limit, "it must be finite and >= 0 (0 turns the warning off)")
    return DriftMonitor(limit) if limit > 0.0 else None


def yielding_outputs(n):
    """The yielding storeys' outputs of an n-storey building: (name, type, unit, description)."""
    floors = range(1, n + 1)
    return (tuple((f"storey[{k}].force", Real, "N", f"force of storey {k}'s bilinear spring (P-Delta and "
                   "dashpots not included)") for k in floors)
            + tuple((f"storey[{k}].plastic_drift", Real, "m", f"drift at which storey {k}'s spring force is zero")
                    for k in floors)
            + (("energy_hysteretic", Real, "J", "energy dissipated by the storeys' yielding so far"),
               ("collapsed", Integer, None, "1 once a storey's drift ratio reached collapse_drift (every output "
                "holds from then)")))
