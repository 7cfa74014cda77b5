"""Event location by conservative advancement: a zero of a guard cannot be missed.

A segment exposes guards g_i(tau) that are positive while its mode holds (the
gaps to the two stops in free flight, the contact force while riding a stop, the
overlap while the angle form passes through a stop), plus

    seg.values(tau)    -> (g_0, dg_0, g_1, dg_1, ...)  cheap, used while far from zero
    seg.guard(tau, i)  -> (g_i, dg_i)                 optional: guard i alone, where that costs less
    seg.derivs(tau, i) -> (g, dg, d2g, d3g)        of guard i, used only next to a zero
    seg.bounds         =  (B2, B3, B4)             bounds of the 2nd..4th derivatives (all guards)
    seg.noise          =  (n0, n1, n2, n3)         rounding level of g and its first 3 derivatives at tau = 0
    seg.growth         =  w                        ... which grows as noise * (1 + w tau)
    seg.clear          =  True when no guard can reach zero on the whole segment

Far from zero the solver steps by the smallest positive root of the Taylor lower
bound g + dg s - B2 s^2 / 2 of every guard, so all guards stay positive on every
step: no contact can be jumped over, grazing ones included.  Next to zero
(g <= n0) the point is classified by the first derivative that rises above its
rounding level:

- dg < -v_res: a transversal crossing, refined by Newton to machine precision
  (v_res = max(n1, sqrt(2 (|d2g| + n2) n0)) is the smallest approach speed whose
  crossing float64 positions can resolve);
- first significant derivative negative: the guard is pressed to zero at an
  approach speed below resolution (a touch that continues inward);
- positive, or nothing significant: the guard leaves zero; a departure step of
  the order of that derivative (never longer than the safe step of the other
  guards) lifts it above rounding level.

Every pass of the loop advances tau by at least one ulp or returns, so the
search terminates; a search that would take more than MAX_PASSES passes (a guard
that hovers just above its rounding level for that long) is refused with a
ParameterError instead of running on.  Right after a mode switch (``fresh``) the point tau = 0 is
never reported again, which rules out ping-pong between two modes at one
instant.
"""
import math
import math as _libm  # sqrt: in the compiled build libc's (events.pxd), correctly rounded as CPython's math.sqrt
import struct

from .params import ParameterError

CROSS = 1  # transversal zero crossing, found to machine precision
TOUCH = 2  # zero reached (or already passed) at an approach speed below resolution

_INF = math.inf

#: most passes one locate call makes (a few are typical: the safe steps grow geometrically)
MAX_PASSES = 10000


def next_up(x):
    """The next float above x >= 0 (math.nextafter needs Python 3.9; hosts may embed older ones)."""
    if x == 0.0:
        return 5e-324
    return struct.unpack("<d", struct.pack("<q", struct.unpack("<q", struct.pack("<d", x))[0] + 1))[0]


def safe_step(g, g1, b2):
    """Smallest positive root of g + g1 s - b2 s^2 / 2 (g > 0): g stays positive before it."""
    if b2 <= 0.0:
        return g / -g1 if g1 < 0.0 else _INF
    root = _libm.sqrt(g1 * g1 + 2.0 * b2 * g)
    if g1 <= 0.0:
        return 2.0 * g / (root - g1)
    return (g1 + root) / b2


def classify(g1, g2, g3, vres, n2, n3):
    """Order (1, 2, 3; 0 if none) and value of the first significant derivative."""
    if g1 > vres or g1 < -vres:
        return 1, g1
    if g2 > n2 or g2 < -n2:
        return 2, g2
    if g3 > n3 or g3 < -n3:
        return 3, g3
    return 0, 0.0


def resolution_speed(g2, n0, n1, n2):
    """Smallest approach speed whose crossing the position resolution n0 can resolve."""
    return max(n1, _libm.sqrt(2.0 * (abs(g2) + n2) * n0))


def departure_step(order, dk, vres, bounds):
    """A step after which a guard leaving zero through derivative `order` is above rounding."""
    b2, b3, b4 = bounds
    if order == 1 and dk > 0.0:
        return dk / b2 if b2 > 0.0 else _INF
    if order == 2 and dk > 0.0:
        return 1.5 * dk / b3 if b3 > 0.0 else _INF
    if order == 3 and dk > 0.0:
        return 2.0 * dk / b4 if b4 > 0.0 else _INF
    # nothing significant (or a contradiction right after a switch): a window in which
    # the approach speed cannot exceed 2 v_res, i.e. no resolvable contact
    return vres / b2 if b2 > 0.0 else _INF


def locate(seg, tau_end, fresh=False):
    """First zero of a guard of seg in [0, tau_end]: (tau, CROSS or TOUCH, guard index), or None."""
    if tau_end <= 0.0 or seg.clear:
        return None
    base = seg.noise
    base0, growth = base[0], seg.growth
    b2 = seg.bounds[0]
    tau = 0.0
    for passes in range(MAX_PASSES):
        step = _INF
        near = -1
        others = None  # the guards next to zero besides `near` (two surfaces closer than rounding)
        n0 = base0 * (1.0 + growth * tau)  # rounding level of the guards at tau
        values = seg.values(tau)
        for i in range(0, len(values), 2):
            g = values[i]
            if g <= n0:
                if near >= 0:
                    others = [near] if others is None else others + [near]
                near = i >> 1
                continue
            g1 = values[i + 1]  # safe_step(g, g1, b2), inlined: this is the innermost loop
            if b2 > 0.0:
                root = _libm.sqrt(g1 * g1 + 2.0 * b2 * g)
                s = 2.0 * g / (root - g1) if g1 <= 0.0 else (g1 + root) / b2
            else:
                s = g / -g1 if g1 < 0.0 else _INF
            if s < step:
                step = s
        if near < 0:
            nxt = tau + step
            if nxt >= tau_end:
                return None
            if nxt > tau:
                tau = nxt
                continue
            near = 0  # the least guard: a zero within one ulp of tau
            for i in range(1, len(values) // 2):
                if values[2 * i] < values[2 * near]:
                    near = i
            step = _INF
        scale = 1.0 + growth * tau
        found = None
        for i in ([near] if others is None else others + [near]):
            hit, away = _near_zero(seg, i, tau, tau_end, n0, base, scale, fresh)
            if hit is not None and (found is None or hit[0] < found[0]):
                found = hit
            step = min(step, away)
        if found is not None:
            return found
        tau = max(tau + step, next_up(tau))
        if tau >= tau_end:
            return None
    raise ParameterError("step", tau_end, f"locating the next contact took more than {MAX_PASSES} passes (a guard "
                         f"hovering just above its rounding level {seg.noise[0]!r}): take shorter steps")


def _near_zero(seg, i, tau, tau_end, n0, base, scale, fresh):
    """Classify guard i next to zero at tau: ((tau, kind, i), _) if it crosses or is pressed to
    zero there (never at tau = 0 right after a switch), else (None, a departure step)."""
    g, g1, g2, g3 = seg.derivs(tau, i)
    n1, n2, n3 = base[1] * scale, base[2] * scale, base[3] * scale
    vres = resolution_speed(g2, n0, n1, n2)
    order, dk = classify(g1, g2, g3, vres, n2, n3)
    if not (fresh and tau == 0.0):
        if g < -n0:
            return (tau, TOUCH, i), 0.0  # already past zero: a jump of the guard at a step start
        if order == 1 and dk < 0.0:
            return (min(_newton(seg, i, tau, g, g1), tau_end), CROSS, i), 0.0
        if dk < 0.0:
            return (tau, TOUCH, i), 0.0
    # departing, flat, or a contradiction right after a switch: step away
    return None, departure_step(order, dk, vres, seg.bounds)


def _newton(seg, i, tau, g, g1):
    """Root of guard i next to tau (transversal, so Newton converges quadratically); the guard
    evaluated alone where the segment can (seg.guard), else taken from seg.values."""
    alone = getattr(seg, "guard", None)
    for _ in range(6):
        nxt = max(tau - g / g1, 0.0)
        if nxt == tau:
            break
        tau = nxt
        if alone is None:
            values = seg.values(tau)
            g, g1 = values[2 * i], values[2 * i + 1]
        else:
            g, g1 = alone(tau, i)
        if g1 >= 0.0:
            break
    return tau
