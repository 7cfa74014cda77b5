"""The three smooth motions between events, each with the guard that ends it.

- Flight: both pendulums swing freely; guards = gaps to the two stops,
  D -+ (cx x - cy y) (cx = cy = 1 in the displacement form, 1/L2 and 1/L1 in the
  angle form).
- Outside (angle form only): the pair passes through stop `side` after a
  non-separating impact; guard = side (cx x - cy y) - D, the overlap, which ends
  when the bodies re-enter the gap.
- Stick (displacement form): the particle rides stop `side`; the pair moves as one
  oscillator; guard = side * N / m, the contact force per particle mass.

Every segment is built at its start t0 for a horizon T (so its derivative bounds
hold on [0, T]) with the loads held over it: fx = F / M - a_g on the primary and
fy = -a_g on the particle (a_g the ground acceleration of a base excitation), and the
built-in harmonic at phase psi = Omega t0 + phi.  See events.py for the guard protocol.
"""
import math

from .oscillator import Oscillator

_EPS = 2.220446049250313e-16
_ULPS = 64.0  # rounding allowance of a computed guard, in units of eps * its scale


TOLERANCE = _ULPS * _EPS  # relative rounding level of a guard at tau = 0
# Trig arguments w tau lose eps * w tau absolute, so a segment's rounding levels grow as
# noise * (1 + growth * tau): events.locate scales them to the tau it classifies at.


def coast(p, x, v, y, u, fx, fy, T):
    """(x, v, y, u) after T of free flight without the built-in harmonic when no stop is within
    reach over [0, T], else None.  Flight's `clear` test and its positions, in the same operations,
    without building the segment: the event loop's fast path for the steps that cannot meet a stop."""
    w2, w1 = p.w2, p.w1
    xe = fx / (w2 * w2)
    a2, b2 = x - xe, v / w2
    ye = fy / (w1 * w1)
    a1, b1 = y - ye, u / w1
    D = p.D
    zmax = p.cx * (abs(xe) + math.hypot(a2, b2)) + p.cy * (abs(ye) + math.hypot(a1, b1))
    if not zmax < D - TOLERANCE * (D + zmax) * (1.0 + max(w1, w2, p.Omega_acting) * T):
        return None
    s2, c2 = math.sin(w2 * T), math.cos(w2 * T)
    s1, c1 = math.sin(w1 * T), math.cos(w1 * T)
    return xe + a2 * c2 + b2 * s2, w2 * (b2 * c2 - a2 * s2), ye + a1 * c1 + b1 * s1, w1 * (b1 * c1 - a1 * s1)


class Flight:
    """Free flight of both pendulums; guards = distances to the two stops.

    Without a built-in harmonic both motions are plain sinusoids about their equilibria,
    and the gap is evaluated inline (this is the solver's innermost loop).
    """

    reach = math.inf  # the closed form holds over the whole span
    __slots__ = ("px", "py", "cx", "cy", "D", "bounds", "noise", "growth", "clear", "sgn", "inline", "start",
                 "w2", "xe", "a2", "b2", "w1", "ye", "a1", "b1")

    def __init__(self, p, x, v, y, u, fx, fy, psi, T, always_bound=False):
        a = p.F0 / p.M
        self.px = px = Oscillator(p.w2, x, v, fx, a, p.Omega, psi)
        self.py = py = Oscillator(p.w1, y, u, fy)
        cx, cy, D = p.cx, p.cy, p.D
        self.cx, self.cy, self.D = cx, cy, D
        self.sgn = 0
        self.start = None  # gap derivatives at tau = 0, once computed
        self.inline = a == 0.0
        self.w2, self.xe, self.a2, self.b2 = px.w, px.xe, px.A, px.B
        self.w1, self.ye, self.a1, self.b1 = py.w, py.xe, py.A, py.B
        xh, vh = px.harmonic_bounds(T)
        zmax = cx * (abs(px.xe) + px.R + xh) + cy * (abs(py.xe) + py.R)
        tol = TOLERANCE
        self.growth = max(p.w1, p.w2, p.Omega_acting)
        n0 = tol * (D + zmax)
        self.clear = zmax < D - n0 * (1.0 + self.growth * T)
        if self.clear and not always_bound:  # no stop within reach: bounds and noise are not needed
            self.bounds = self.noise = None
            return
        bx = px.bounds(T)
        by = py.bounds(T)
        self.bounds = (cx * bx[2] + cy * by[2], cx * bx[3] + cy * by[3], cx * bx[4] + cy * by[4])
        self.noise = (n0, tol * (cx * bx[1] + cy * by[1]),
                      tol * (cx * (bx[2] + px.ww * abs(px.xe)) + cy * (by[2] + py.ww * abs(py.xe))),
                      tol * (cx * bx[3] + cy * by[3]))

    def positions(self, tau):
        """(x, v, y, u) at tau."""
        if self.inline:
            w2, w1 = self.w2, self.w1
            s2, c2 = math.sin(w2 * tau), math.cos(w2 * tau)
            s1, c1 = math.sin(w1 * tau), math.cos(w1 * tau)
            a2, b2, a1, b1 = self.a2, self.b2, self.a1, self.b1
            return (self.xe + a2 * c2 + b2 * s2, w2 * (b2 * c2 - a2 * s2),
                    self.ye + a1 * c1 + b1 * s1, w1 * (b1 * c1 - a1 * s1))
        x, v, _, _ = self.px.state(tau)
        y, u, _, _ = self.py.state(tau)
        return x, v, y, u

    def gap(self, tau):
        """Gap function cx x - cy y and its rate at tau."""
        g, dg, _, _ = Flight.values(self, tau)
        return self.D - g, -dg

    def gap_derivs(self, tau):
        """Gap function and its first three derivatives at tau."""
        x, v, x2, x3, _, _ = self.px.derivs(tau)
        y, u, y2, y3, _, _ = self.py.derivs(tau)
        cx, cy = self.cx, self.cy
        return cx * x - cy * y, cx * v - cy * u, cx * x2 - cy * y2, cx * x3 - cy * y3

    def values(self, tau):
        """(guard, rate) of stop +1 (D - z) then of stop -1 (D + z), flat; z = cx x - cy y."""
        cx, cy, D = self.cx, self.cy, self.D
        if self.inline:
            w2, w1 = self.w2, self.w1
            s2, c2 = math.sin(w2 * tau), math.cos(w2 * tau)
            s1, c1 = math.sin(w1 * tau), math.cos(w1 * tau)
            a2, b2, a1, b1 = self.a2, self.b2, self.a1, self.b1
            z = cx * (self.xe + a2 * c2 + b2 * s2) - cy * (self.ye + a1 * c1 + b1 * s1)
            dz = cx * w2 * (b2 * c2 - a2 * s2) - cy * w1 * (b1 * c1 - a1 * s1)
        else:
            x, v, _, _ = self.px.state(tau)
            y, u, _, _ = self.py.state(tau)
            z, dz = cx * x - cy * y, cx * v - cy * u
        return D - z, -dz, D + z, dz

    def derivs(self, tau, i):
        if tau == 0.0 and self.start is not None:  # asked again by locate after an event
            z, z1, z2, z3 = self.start
        else:
            z, z1, z2, z3 = self.gap_derivs(tau)
            if tau == 0.0:
                self.start = z, z1, z2, z3
        if i == 0:
            return self.D - z, -z1, -z2, -z3
        return self.D + z, z1, z2, z3


class Outside(Flight):
    """Angle form: the bodies pass through stop `sgn`; guard = overlap past the stop."""

    __slots__ = ()

    def __init__(self, p, x, v, y, u, fx, fy, psi, T, sgn):
        Flight.__init__(self, p, x, v, y, u, fx, fy, psi, T, always_bound=True)
        self.sgn = sgn
        self.clear = False

    def values(self, tau):
        z, dz = self.gap(tau)
        s = self.sgn
        return s * z - self.D, s * dz

    def derivs(self, tau, i=0):
        z, z1, z2, z3 = self.gap_derivs(tau)
        s = self.sgn
        return s * z - self.D, s * z1, s * z2, s * z3


class Stick:
    """The particle rides stop `sgn`: y = x - sgn d, u = v; guard = sgn N / m."""

    reach = math.inf  # the closed form holds over the whole span
    __slots__ = ("osc", "sgn", "d", "k", "base", "a", "om", "bounds", "noise", "growth", "clear")

    def __init__(self, p, x, v, sgn, fx, fy, psi, T):
        mu, w1, w2, d = p.mu, p.w1, p.w2, p.d
        ww1 = w1 * w1
        big_w = math.sqrt((w2 * w2 + mu * ww1) / (1.0 + mu))
        a = p.F0 / p.M / (1.0 + mu)
        c = (mu * ww1 * sgn * d + fx + mu * fy) / (1.0 + mu)
        self.osc = osc = Oscillator(big_w, x, v, c, a, p.Omega, psi)
        self.sgn, self.d, self.a, self.om = sgn, d, a, p.Omega
        self.k = k = ww1 - osc.ww
        self.base = ww1 * (osc.xe - sgn * d) - fy  # N/m = x'' + w1^2 (x - sgn d) - fy
        P = osc.bounds(T)
        aa, om = abs(a), p.Omega
        self.bounds = tuple(abs(k) * P[j] + aa * om ** j for j in (2, 3, 4))
        tol = TOLERANCE
        self.growth = max(big_w, p.Omega_acting)
        self.noise = (tol * (abs(k) * (abs(osc.xe) + P[0]) + ww1 * (abs(osc.xe) + d) + aa + abs(fy)),
                      tol * (abs(k) * P[1] + aa * om),
                      tol * (abs(k) * (P[2] + osc.ww * abs(osc.xe)) + aa * om * om),
                      tol * (abs(k) * P[3] + aa * om ** 3))
        self.clear = sgn * self.base - abs(k) * P[0] - aa > self.noise[0] * (1.0 + self.growth * T)

    def positions(self, tau):
        x, v, _, _ = self.osc.state(tau)
        return x, v, x - self.sgn * self.d, v

    def values(self, tau):
        x, v, sf, cf = self.osc.state(tau)
        s = self.sgn
        return (s * (self.k * (x - self.osc.xe) + self.base + self.a * sf),
                s * (self.k * v + self.a * self.om * cf))

    def derivs(self, tau, i=0):
        x, v, x2, x3, sf, cf = self.osc.derivs(tau)
        s, k, a, om = self.sgn, self.k, self.a, self.om
        return (s * (k * (x - self.osc.xe) + self.base + a * sf), s * (k * v + a * om * cf),
                s * (k * x2 - a * om * om * sf), s * (k * x3 - a * om ** 3 * cf))
