"""FEMA P-695's static pushover (section 6.3) of a shear building of deteriorating storeys
(`pidamper_physics.imk`: OpenSees's IMKBilin exact in drift), exact and event-driven, with P-Delta.

Lateral loads proportional to m_i phi_i (the first mode of K - K_G with the storeys' elastic
stiffnesses), so storey k carries the share s_k of the base shear V; its resistance is its law's
force less P_k u_k / h_k (P_k the weight above it, h_k its height).  While V rises every storey
climbs its backbone.  V peaks when the first storey reaches the top of its resistance: its capping
point, or its yield point where P-Delta leaves its pre-capping tangent Kp - P/h at or below zero.
Beyond, that storey goes on along its backbone (past capping, along the residual, to its ultimate
drift) and every other storey unloads along its law's unloading line (the stiffness deteriorated at
the reversal, as the law says).  Every branch is linear, so the curve's corners are exact; it ends
where V has fallen by `drop` of its peak (FEMA P-695's ultimate displacement: 20 % strength loss),
or where the softening storey loses its strength, whichever comes first.
"""
from dataclasses import dataclass

import numpy as np

from pidamper_physics.imk import IMKStorey
from pidamper_physics.refusals import ParameterError

from .p695 import Pushover, carried_masses, first_mode, period_based_ductility


@dataclass
class DeterioratingPushover:
    roof: np.ndarray  # roof displacement at each corner of the curve [m]
    base_shear: np.ndarray  # N
    v_max: float  # N
    delta_u: float  # m: where the curve ends
    delta_y_eff: float  # m (FEMA P-695 Eq. 6-7)
    mu_t: float
    critical: int  # the storey that softens (1 = the first)
    limit: str  # what ended the curve


def of_params(params):
    """The pushover of pidamper_physics.Params of a building of deteriorating storeys (storey_law =
    1) as p695.Pushover, the assessment's."""
    n = params.storeys
    masses = carried_masses(params)
    po = pushover(list(masses), params.imk, params.storey_h[:n], bool(params.p_delta), params.g)
    return Pushover(po.roof, po.base_shear, po.v_max, po.delta_u, po.delta_y_eff, po.mu_t,
                    params.g * float(np.sum(masses)), po.limit)


def pushover(masses, laws, heights, p_delta=True, g=9.81, drop=0.2):
    """The pushover (module doc) of floors `masses` [kg] on storeys of IMKBilin `laws` (21 numbers
    each, in the command's order) and `heights` [m]."""
    n = len(masses)
    m, h = np.asarray(masses, float), np.asarray(heights, float)
    storeys = [IMKStorey(law, name=f"storey[{k + 1}]") for k, law in enumerate(laws)]
    geo = g * np.cumsum(m[::-1])[::-1] / h if p_delta else np.zeros(n)
    elastic = np.array([s.ke for s in storeys]) - geo
    for k in range(n):
        if elastic[k] <= 0.0:
            raise ParameterError(f"storey[{k + 1}].Ke", storeys[k].ke, f"the storey must stand under its gravity "
                                 f"load: Ke > P/h = {geo[k]!r} N/m")
    phi, omega = first_mode(m, elastic)
    share = np.cumsum((m * phi)[::-1])[::-1] / np.sum(m * phi)
    tops = [_top(s, geo[k]) for k, s in enumerate(storeys)]
    v_top = np.array([r / share[k] for k, (_, r) in enumerate(tops)])
    c = int(np.argmin(v_top))
    v_peak = float(v_top[c])
    roof, shear = _rising(storeys, geo, share, c, tops[c][0], v_peak)
    more_roof, more_shear, delta_u, limit = _softening(storeys, geo, share, c, v_peak, (1.0 - drop) * v_peak)
    roof, shear = np.array(roof + more_roof), np.array(shear + more_shear)
    delta_y, mu_t = period_based_ductility(g, m, phi, omega, v_peak, delta_u)
    return DeterioratingPushover(roof, shear, v_peak, delta_u, delta_y, mu_t, c + 1, limit)


def _top(storey, geo):
    """(drift, resistance) where a storey's resistance F - (P/h) u stops rising on its backbone."""
    side = storey.pos
    if side.kp - geo > 0.0:
        return side.ucap, side.fcap - geo * side.ucap
    uy = side.fy / storey.ke
    return uy, side.fy - geo * uy


def _rising(storeys, geo, share, c, top, v_peak):
    """The curve from rest to the peak: each storey on its elastic, then pre-capping line; corners
    where a storey yields."""
    yields = [s.pos.fy - geo[k] * s.pos.fy / s.ke for k, s in enumerate(storeys)]
    corners = sorted({0.0, v_peak} | {r / share[k] for k, r in enumerate(yields) if r / share[k] < v_peak})
    roof, shear = [], []
    for v in corners:
        total = 0.0
        for k, s in enumerate(storeys):
            r = share[k] * v
            if k == c and v == v_peak:
                u = top
            elif r <= yields[k]:
                u = r / (s.ke - geo[k])
            else:
                u = s.pos.fy / s.ke + (r - yields[k]) / (s.pos.kp - geo[k])
            s.move(u)
            total += u
        roof.append(total)
        shear.append(v)
    return roof, shear


def _softening(storeys, geo, share, c, v_peak, v_end):
    """Beyond the peak: storey c along its backbone, corner by corner, the others back along their
    unloading lines; (roofs, shears, the last roof, what ended it)."""
    soft = storeys[c]
    for k, s in enumerate(storeys):
        if k != c:
            s.turn(-1)  # the reversal: s.k is now the slope of its unloading line
    side, end = soft.pos, v_end * share[c]
    roof, shear = [], []
    u0, r0 = soft.u, soft.f - geo[c] * soft.u
    for u1 in sorted(u for u in side.corners() + [side.du] if u > soft.u):
        r1 = side.force(u1) - geo[c] * u1  # the backbone's (at the ultimate drift: just before the loss)
        if r1 <= end:  # the drop is reached on this piece
            u1, r1 = u0 + (end - r0) * (u1 - u0) / (r1 - r0), end
            limit = f"{(1.0 - v_end / v_peak) * 100:g} % of the peak lost"
        elif u1 >= side.du:
            limit = f"storey {c + 1} lost its strength at its ultimate drift"
        else:
            limit = None
        roof.append(_place(storeys, geo, share, c, u1, r1 / share[c]))
        shear.append(r1 / share[c])
        if limit is not None:
            return roof, shear, roof[-1], limit
        u0, r0 = u1, r1
    raise AssertionError("unreachable: the ultimate drift is a corner ahead")


def _place(storeys, geo, share, c, u_soft, v):
    """Put storey c at u_soft and every other storey where its unloading line carries s_k V; the
    roof displacement."""
    total = 0.0
    for k, s in enumerate(storeys):
        if k == c:
            u = u_soft
        else:
            r_now = s.f - geo[k] * s.u
            u = s.u + (share[k] * v - r_now) / (s.k - geo[k])
        s.move(u)
        total += u
    return total
