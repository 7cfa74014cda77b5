"""The storeys' variables every building FMU has (DampedShearBuilding<N> and ShearBuilding<N>):
parameters storey[k].Fy, storey[k].b, p_delta, collapse_drift (pidamper_physics.storeys), storey_law
and the deteriorating storeys' storey[k].<IMKBilin name> (pidamper_physics.imk_storeys), damping
(the model of the building's damping: pidamper_physics.building) and drift_limit
(pidamper_physics.validity.DriftMonitor); outputs storey[k].force,
storey[k].plastic_drift, energy_hysteretic, collapsed.
"""
import math

from pythonfmu import Integer, Real

from pidamper_physics import DriftMonitor, ParameterError
from pidamper_physics.imk_storeys import IMK_DEFAULTS
from pidamper_physics.storeys import COLLAPSE_DRIFT, HARDENING

#: (unit, minimum, what it is) of each IMKBilin parameter a storey's table takes (imk_storeys.IMK_DEFAULTS)
_IMK = {"Fy_neg": ("N", 0.0, "yield force on the negative side (0: storey[{k}].Fy, which is Fy_pos)"),
        "dp": ("m", 0.0, "pre-capping plastic drift, from yield to capping"),
        "dpc": ("m", 0.0, "post-capping drift, from capping down to zero force along the post-capping line"),
        "du": ("m", 0.0, "ultimate drift (absolute), where the side's strength goes to zero"),
        "FmaxFy": ("1", 1.0, "capping force over the yield force (>= 1)"),
        "FresFy": ("1", 0.0, "residual force over the yield force, [0, 1]"),
        "Lamda": ("m", 0.0, "reference energy over Fy_pos [J/N]"),
        "C": ("1", 0.0, "exponent of the cyclic deterioration"),
        "D": ("1", 0.0, "factor on the deterioration of the side's strength")}
_WHAT = {"S": "basic strength", "C": "post-capping strength", "K": "unloading stiffness"}


def _imk_row(k, name):
    """(name, type, start, unit, min, max, description) of storey k's IMKBilin parameter `name`."""
    base, side = name.rsplit("_", 1) if name.endswith(("_pos", "_neg")) and name != "Fy_neg" else (name, "")
    if base.startswith("Lamda") or base in ("Cs", "Cc", "Ck"):
        what = _WHAT[base[-1].upper()]
        base = "Lamda" if base.startswith("Lamda") else "C"
        text = f"{_IMK[base][2]} of the {what}"
    else:
        text = _IMK[base][2].format(k=k) + (f", {'positive' if side == 'pos' else 'negative'} side" if side else "")
    unit, least, _ = _IMK[base]
    return (f"storey[{k}].{name}", Real, IMK_DEFAULTS[name], unit, least, None,
            f"storey {k} with storey_law = 1 (IMKBilin's {name}): {text}")


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
                "building counts as collapsed, (0, 1]: every output holds from then (with storey_law = 1 a guard "
                "beyond the storeys' own collapse: set it past their sidesway drifts, say 0.2 to 0.3)"),
               ("storey_law", Integer, 0, None, 0, 1, "the storeys' law: 0 bilinear (as OpenSees Steel01: "
                "storey[k].Fy, storey[k].b), 1 deteriorating (as OpenSees IMKBilin: Ke = storey[k].k, Fy_pos = "
                "storey[k].Fy > 0 and storey[k].<IMKBilin name>; the building collapses by sidesway or past an "
                "ultimate drift)"),
               ("damping", Integer, 0, None, 0, 2, "damping model at the ratio zeta_s: 0 modal (every elastic mode, "
                "the matrix kept while storeys yield), 1 Rayleigh on the initial stiffness, 2 Rayleigh on the tangent "
                "stiffness of the storeys' current regime (Rayleigh: zeta_s at the first mode and the third, or the "
                "last of fewer storeys)"),
               ("drift_limit", Real, DriftMonitor.DEFAULT_LIMIT, "1", 0.0, None, "storey drift ratio beyond which "
                "the FMU warns, once per run, that the shear building describes no real one (0 = never)")]
            + [_imk_row(k, name) for k in floors for name in IMK_DEFAULTS])


def imk_entries(values, n):
    """Per storey the dict of IMKBilin values an FMU's variables give (imk_storeys.imk_tables)."""
    return [{name: values[f"storey[{k}].{name}"] for name in IMK_DEFAULTS} for k in range(1, n + 1)]


def drift_monitor(limit):
    """The DriftMonitor of a building FMU's drift_limit (None for 0), once it is checked."""
    if not (math.isfinite(limit) and limit >= 0.0):
        raise ParameterError("drift_limit", limit, "it must be finite and >= 0 (0 turns the warning off)")
    return DriftMonitor(limit) if limit > 0.0 else None


def yielding_outputs(n):
    """The yielding storeys' outputs of an n-storey building: (name, type, unit, description)."""
    floors = range(1, n + 1)
    return (tuple((f"storey[{k}].force", Real, "N", f"force of storey {k}'s spring, bilinear or IMKBilin (P-Delta "
                   "and dashpots not included)") for k in floors)
            + tuple((f"storey[{k}].plastic_drift", Real, "m", f"drift at which storey {k}'s spring force is zero")
                    for k in floors)
            + (("energy_hysteretic", Real, "J", "energy dissipated by the storeys' yielding so far"),
               ("collapsed", Integer, None, "1 once the building collapsed: a storey's drift ratio reached "
                "collapse_drift, or (storey_law = 1) a storey's force with P-Delta fell to zero on its way out "
                "(sidesway) or it passed its ultimate drift (every output holds from then)")))
