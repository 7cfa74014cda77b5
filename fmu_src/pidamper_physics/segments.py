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
hold on [0, T]) with the external force held at fc = F / M and the built-in
harmonic at phase psi = Omega t0 + phi.  See events.py for the guard protocol.
"""
import math

from .oscillator import Oscillator

_EPS = 2.220446049250313e-16
_ULPS = 64.0  # rounding allowance of a computed guard, in units of eps * its scale


def _tolerance(T, *freqs):
    """Relative rounding level: trig arguments up to w T lose eps * w T absolute."""
    return _ULPS * _EPS * (1.0 + max(freqs) * T)


class Flight:
    """Free flight of both pendulums; guard = distance to the nearer stop."""

    __slots__ = ("px", "py", "cx", "cy", "D", "bounds", "noise", "clear", "sgn")

    def __init__(self, p, x, v, y, u, fc, psi, T):
        a = p.F0 / p.M
        self.px = px = Oscillator(p.w2, x, v, fc, a, p.Omega, psi)
        self.py = py = Oscillator(p.w1, y, u)
        cx, cy, D = p.cx, p.cy, p.D
        self.cx, self.cy, self.D = cx, cy, D
        bx = px.bounds(T)
        by = py.bounds(T)
        self.bounds = (cx * bx[2] + cy * by[2], cx * bx[3] + cy * by[3], cx * bx[4] + cy * by[4])
        zmax = cx * (abs(px.xe) + bx[0]) + cy * by[0]
        tol = _tolerance(T, p.w1, p.w2, p.Omega)
        self.noise = (tol * (D + zmax), tol * (cx * bx[1] + cy * by[1]),
                      tol * (cx * (bx[2] + px.ww * abs(px.xe)) + cy * by[2]),
                      tol * (cx * bx[3] + cy * by[3]))
        self.clear = zmax < D - self.noise[0]
        self.sgn = 0

    def positions(self, tau):
        """(x, v, y, u) at tau."""
        x, v, _, _ = self.px.state(tau)
        y, u, _, _ = self.py.state(tau)
        return x, v, y, u

    def gap(self, tau):
        """Gap function cx x - cy y and its rate at tau."""
        x, v, _, _ = self.px.state(tau)
        y, u, _, _ = self.py.state(tau)
        return self.cx * x - self.cy * y, self.cx * v - self.cy * u

    def gap_derivs(self, tau):
        """Gap function and its first three derivatives at tau."""
        x, v, x2, x3, _, _ = self.px.derivs(tau)
        y, u, y2, y3, _, _ = self.py.derivs(tau)
        cx, cy = self.cx, self.cy
        return cx * x - cy * y, cx * v - cy * u, cx * x2 - cy * y2, cx * x3 - cy * y3

    def values(self, tau):
        """Guards of stop +1 (D - z) and stop -1 (D + z) with their rates."""
        z, dz = self.gap(tau)
        return (self.D - z, -dz), (self.D + z, dz)

    def derivs(self, tau, i):
        z, z1, z2, z3 = self.gap_derivs(tau)
        if i == 0:
            return self.D - z, -z1, -z2, -z3
        return self.D + z, z1, z2, z3


class Outside(Flight):
    """Angle form: the bodies pass through stop `sgn`; guard = overlap past the stop."""

    __slots__ = ()

    def __init__(self, p, x, v, y, u, fc, psi, T, sgn):
        Flight.__init__(self, p, x, v, y, u, fc, psi, T)
        self.sgn = sgn
        self.clear = False

    def values(self, tau):
        z, dz = self.gap(tau)
        s = self.sgn
        return ((s * z - self.D, s * dz),)

    def derivs(self, tau, i=0):
        z, z1, z2, z3 = self.gap_derivs(tau)
        s = self.sgn
        return s * z - self.D, s * z1, s * z2, s * z3


class Stick:
    """The particle rides stop `sgn`: y = x - sgn d, u = v; guard = sgn N / m."""

    __slots__ = ("osc", "sgn", "d", "k", "base", "a", "om", "bounds", "noise", "clear")

    def __init__(self, p, x, v, sgn, fc, psi, T):
        mu, w1, w2, d = p.mu, p.w1, p.w2, p.d
        ww1 = w1 * w1
        big_w = math.sqrt((w2 * w2 + mu * ww1) / (1.0 + mu))
        a = p.F0 / p.M / (1.0 + mu)
        c = (mu * ww1 * sgn * d + fc) / (1.0 + mu)
        self.osc = osc = Oscillator(big_w, x, v, c, a, p.Omega, psi)
        self.sgn, self.d, self.a, self.om = sgn, d, a, p.Omega
        self.k = k = ww1 - osc.ww
        self.base = ww1 * (osc.xe - sgn * d)
        P = osc.bounds(T)
        aa, om = abs(a), p.Omega
        self.bounds = tuple(abs(k) * P[j] + aa * om ** j for j in (2, 3, 4))
        tol = _tolerance(T, big_w, p.Omega)
        self.noise = (tol * (abs(k) * (abs(osc.xe) + P[0]) + ww1 * (abs(osc.xe) + d) + aa),
                      tol * (abs(k) * P[1] + aa * om),
                      tol * (abs(k) * (P[2] + osc.ww * abs(osc.xe)) + aa * om * om),
                      tol * (abs(k) * P[3] + aa * om ** 3))
        self.clear = sgn * self.base - abs(k) * P[0] - aa > self.noise[0]

    def positions(self, tau):
        x, v, _, _ = self.osc.state(tau)
        return x, v, x - self.sgn * self.d, v

    def values(self, tau):
        x, v, sf, cf = self.osc.state(tau)
        s = self.sgn
        return ((s * (self.k * (x - self.osc.xe) + self.base + self.a * sf),
                 s * (self.k * v + self.a * self.om * cf)),)

    def derivs(self, tau, i=0):
        x, v, x2, x3, sf, cf = self.osc.derivs(tau)
        s, k, a, om = self.sgn, self.k, self.a, self.om
        return (s * (k * (x - self.osc.xe) + self.base + a * sf), s * (k * v + a * om * cf),
                s * (k * x2 - a * om * om * sf), s * (k * x3 - a * om ** 3 * cf))
