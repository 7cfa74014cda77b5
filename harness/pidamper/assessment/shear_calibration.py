"""A shear building of deteriorating storeys (OpenSees IMKBilin's law, storey_law = 1) calibrated to a
frame's static pushover: each storey's shear against its drift, read off the frame at every step.

Storey k's resistance without P-Delta is r_k = V_k + P_k u_k / h_k (V_k its shear: the lateral load
above it; u_k its drift [m]; P_k the weight above it; h_k its height), since the shear building puts
P-Delta back itself (P_k / h_k on the drift).  Per storey:

- Ke: the slope of the line fitted to r_k against u_k while r_k is below ELASTIC of its peak; the
  drift where that line meets zero force is the storey's drift before the push (gravity's sway:
  subtracted, so that drifts are counted from the state the pushover starts from);
- the peak (u_m, r_m): where r_k is largest;
- Fy: the bilinear of initial stiffness Ke through the peak with the same area under it up to u_m as
  the storey's curve (FEMA 356, 3.3.3.2.5, equal areas, the initial stiffness kept); FmaxFy = r_m / Fy;
  dp = u_m - Fy / Ke, the drift from yield to capping;
- a storey that softens (at the end its resistance has fallen past the peak by more than SOFTENED
  of it and its drift has grown past the peak's by more than GROWN of it, never falling back by more
  than MONOTONE of it on the way) gives its post-capping
  slope Kpc and, where it reached one, its residual plateau F_res: the line through the peak, held
  at F_res, fitted to the path beyond the peak (least squares); dpc = r_m / |Kpc|, the drift from
  capping to zero force, FresFy = F_res / Fy.
A storey that unloads while another softens has not shown its capping: its FmaxFy and its plastic and
post-capping drift ratios (dp / h, dpc / h) are the softening storeys' (their median), its Fy its own
when it yielded (its secant at the peak below YIELDED Ke); a storey that stayed elastic keeps Fy = r_m,
the largest resistance it showed (a lower bound, said in `basis`).  The residual strength where the
pushover did not reach it, the ultimate drift and the cyclic deterioration are the hinges' (the
caller's), scaled to the storey: a drift ratio times h, an energy Lamda (hinge rotation [rad]) times
h [m]."""
from dataclasses import astuple, dataclass

import numpy as np

#: a storey has softened when, at the pushover's end, its resistance has fallen past its peak by more
#: than SOFTENED of it and its drift has grown past the peak's by more than GROWN of it (a storey that
#: unloads while its neighbours' joints turn creeps on a little, not this far)
SOFTENED = 0.05
GROWN = 0.5
#: ... and its drift never fell back past the peak by more than this share of the peak's drift (a
#: storey that unloads while a neighbour's mechanism drags its drift on, through the joints they
#: share, has not softened itself)
MONOTONE = 0.01
#: a storey has yielded when its secant at the peak is below this share of its initial stiffness
YIELDED = 0.9
#: the initial stiffness is fitted where the resistance is below this share of its peak
ELASTIC = 0.3
#: a residual plateau is read off a falling branch only where it holds this share of its points
PLATEAU = 0.1


@dataclass
class Storey:
    ke: float  # N/m
    fy: float  # N
    fmax_fy: float
    dp: float  # m: yield to capping
    dpc: float  # m: capping to zero force (nan: not seen, taken from the softening storeys)
    basis: str  # "softened", "yielded" or "elastic"
    fres_fy: float = np.nan  # the residual plateau over Fy (nan: not reached in the pushover)


def resistances(shear, drift, weights_above, heights):
    """r_k = V_k + P_k u_k / h_k per step and storey (arrays steps x storeys) [N]."""
    shear, drift = np.asarray(shear, float), np.asarray(drift, float)
    return shear + drift * (np.asarray(weights_above, float) / np.asarray(heights, float))[None, :]


def equal_area_yield(u, r, ke):
    """Fy of the bilinear (slope ke to Fy, then straight to the last point (u[-1], r[-1])) whose
    area over [0, u[-1]] equals the curve's (trapezoids); u, r from rest to the peak."""
    area = float(np.sum(0.5 * (r[1:] + r[:-1]) * np.diff(u)))
    um, rm = u[-1], r[-1]
    # the bilinear's area Fy^2 / (2 ke) + (um - Fy / ke) (Fy + rm) / 2 is linear in Fy: its squares cancel
    fy = (area - 0.5 * um * rm) / (0.5 * um - 0.5 * rm / ke)
    return float(min(max(fy, 0.0), rm))


def elastic_line(u, r):
    """(Ke, u0): the least-squares line r = Ke (u - u0) through the points below ELASTIC of the peak."""
    low = r <= ELASTIC * r.max()
    if np.count_nonzero(low) < 2:
        raise ValueError(f"the pushover has {np.count_nonzero(low)} step(s) below {ELASTIC:g} of a storey's peak: "
                         "take smaller steps so that its elastic stiffness can be read")
    ke, c = np.polyfit(u[low], r[low], 1)
    return float(ke), float(-c / ke)


def storey(u, r):
    """The calibration of one storey's (drift, resistance) path (module doc); dpc nan unless it
    softened."""
    ke, u0 = elastic_line(u, r)
    u, r = np.concatenate([[0.0], u - u0]), np.concatenate([[0.0], r])
    m = int(np.argmax(r))
    um, rm = u[m], r[m]
    back = float(np.max(np.maximum.accumulate(u[m:]) - u[m:]))
    softened = bool(u[-1] > (1.0 + GROWN) * um and r[-1] < (1.0 - SOFTENED) * rm and back <= MONOTONE * um)
    yielded = softened or rm / um < YIELDED * ke
    if not yielded:
        return Storey(ke, rm, 1.0, 0.0, np.nan, "elastic")
    fy = equal_area_yield(u[:m + 1], r[:m + 1], ke)
    if not softened:
        return Storey(ke, fy, rm / fy, um - fy / ke, np.nan, "yielded")
    kpc, fres = falling_branch(u[m:], r[m:])
    return Storey(ke, fy, rm / fy, um - fy / ke, rm / -kpc, "softened", fres / fy)


def falling_branch(u, r):
    """(Kpc [N/m], F_res [N]) of r = r_0 + Kpc min(u - u_0, u_b - u_0), the line through the path's
    peak (u_0, r_0) held from u_b on, fitted (least squares) to the path beyond the peak: for each
    break u_b at a point of the path Kpc has a closed form, and the break of the least squared error
    is taken.  F_res nan where the plateau would hold fewer than PLATEAU of the points (no residual
    reached: Kpc is then the line's through all of them)."""
    ahead = u > u[0]
    du, dr = u[ahead] - u[0], r[ahead] - r[0]
    best = None
    for ub in du:
        x = np.minimum(du, ub)
        kpc = float(np.dot(x, dr) / np.dot(x, x))
        sse = float(np.sum((kpc * x - dr) ** 2))
        if best is None or sse < best[0]:
            best = (sse, kpc, ub)
    _, kpc, ub = best
    if np.count_nonzero(du > ub) < PLATEAU * du.size:
        return float(np.dot(du, dr) / np.dot(du, du)), np.nan
    return kpc, float(r[0] + kpc * ub)


#: which pushover a storey is calibrated from: where it softened, else where it yielded, else where it
#: went furthest (the largest resistance among them)
RANK = {"softened": 2, "yielded": 1, "elastic": 0}


def calibrate(pushovers, weights_above, heights):
    """Per storey a Storey (module doc) from the pushovers [(shear, drift), ...] (steps x storeys
    each, N and m).  The first (the first mode's pattern) is the one the shear building is to
    reproduce: every storey's stiffness comes from it, and the rest too where the storey yielded in
    it; a storey it left elastic takes the rest from the pushover that took it furthest (RANK, then
    the larger peak), its yield force no lower than the largest resistance the first showed (it did
    not yield there).  The unseen capping and post-capping are the softening storeys' drift ratios."""
    h = np.asarray(heights, float)
    found = []
    for k in range(h.size):
        seen = []
        for shear, drift in pushovers:
            r = resistances(shear, drift, weights_above, heights)[:, k]
            u = np.asarray(drift, float)[:, k]
            s = storey(u, r)
            seen.append((RANK[s.basis], float(r.max()), s))
        first = seen[0][2]
        if first.basis == "elastic":
            best = max(seen, key=lambda x: x[:2])[2]
            first = Storey(first.ke, max(best.fy, first.fy), *astuple(best)[2:])
        found.append(first)
    soft = [(s, h[k]) for k, s in enumerate(found) if s.basis == "softened"]
    if not soft:
        raise ValueError("no storey softened in the pushover: push it past its peak so that the capping and "
                         "post-capping can be read")
    ratio_fmax = float(np.median([s.fmax_fy for s, _ in soft]))
    ratio_dp = float(np.median([s.dp / hk for s, hk in soft]))
    ratio_dpc = float(np.median([s.dpc / hk for s, hk in soft]))
    out = []
    for k, s in enumerate(found):
        if s.basis != "softened":
            s = Storey(s.ke, s.fy, max(ratio_fmax, s.fmax_fy), max(ratio_dp * h[k], s.dp), ratio_dpc * h[k],
                       s.basis)
        out.append(s)
    return out


def imk_fields(storeys, heights, residual=0.4, ultimate=0.15, lamda=1.0):
    """The study's [building] per-storey fields of `storeys` (lists, storey 1 first): storey_k,
    storey_Fy and the IMKBilin names, symmetric; the hinges' residual FresFy (where the storey's own
    was not seen), ultimate drift ratio and cyclic deterioration Lamda [rad] (per storey or one for
    all), scaled by h."""
    h = np.asarray(heights, float)
    lam = np.broadcast_to(np.asarray(lamda, float), h.shape)
    fields = {"storey_k": [s.ke for s in storeys], "storey_Fy": [s.fy for s in storeys]}
    fres = [s.fres_fy if np.isfinite(s.fres_fy) else residual for s in storeys]
    for side in ("pos", "neg"):
        fields[f"storey_dp_{side}"] = [s.dp for s in storeys]
        fields[f"storey_dpc_{side}"] = [s.dpc for s in storeys]
        fields[f"storey_du_{side}"] = (ultimate * h).tolist()
        fields[f"storey_FmaxFy_{side}"] = [s.fmax_fy for s in storeys]
        fields[f"storey_FresFy_{side}"] = fres
    for name in ("LamdaS", "LamdaC", "LamdaK"):
        fields[f"storey_{name}"] = (lam * h).tolist()
    return {k: [float(x) for x in v] for k, v in fields.items()}
