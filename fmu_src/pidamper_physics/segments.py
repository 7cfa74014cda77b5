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
import math as _libm  # sin, cos, sqrt: in the compiled build libc's (segments.pxd: from libc cimport math as _libm), the
# very functions CPython's math.sin and math.cos call (math.hypot is CPython's own: kept from math)

from .oscillator import oscillator

_hypot = math.hypot  # CPython's own (not libm's), bound once: a module attribute costs a lookup per call

_EPS = 2.220446049250313e-16
_ULPS = 64.0  # rounding allowance of a computed guard, in units of eps * its scale


TOLERANCE = _ULPS * _EPS  # relative rounding level of a guard at tau = 0
#: a gap's rounding level must stay below the clearance / GAP_RESOLUTION for contacts to be resolved
#: (d = 1e-9 m under swings of 0.7 m is resolved: its rounding level is 1e-14 m)
GAP_RESOLUTION = 1e3
_TOL, _RESOLUTION = TOLERANCE, GAP_RESOLUTION  # the same, read by the closed forms (C doubles when compiled)
#: coast's amplitude bound sqrt(a a + b b) * _ABOVE + _UNDERFLOW is never below hypot(a, b): the root
#: of the rounded squares is within 1.25 ulp, _ABOVE adds 4, _UNDERFLOW what squares lose below the
#: normal range (< 3e-162); an overflowed square gives inf (not clear).  In the compiled build C
#: arithmetic, where CPython's hypot is a Python call
_ABOVE, _UNDERFLOW = 1.0 + 4.0 * _EPS, 1e-160


def noise_size(swing, reach, D):
    """Magnitude [m] that sets a gap's rounding level: the all-time swing about the equilibrium
    (independent of the piece's length, so event decisions do not depend on the step size),
    unless that is too large to resolve the clearance D (a held load that dwarfs the restoring
    force): then the motion's reach over the piece, which the start-relative closed form honours."""
    return swing if _TOL * (D + swing) * _RESOLUTION <= D else min(swing, reach)
# Trig arguments w tau lose eps * w tau absolute, so a segment's rounding levels grow as
# noise * (1 + growth * tau): events.locate scales them to the tau it classifies at.


class LinearParams:
    """The parameters the linear level's closed forms read (coast, Flight, Stick, levels' energy and
    outputs), taken from Params p once: the compiled build keeps them in C doubles, so building a
    segment reads no Python attributes.  p.e is not among them (set_restitution changes it)."""

    __slots__ = ("w2", "w1", "D", "cx", "cy", "Omega_acting", "F0", "M", "Omega", "mu", "d", "m", "L2", "L1")

    def __init__(self, p):
        self.w2, self.w1, self.D, self.cx, self.cy = p.w2, p.w1, p.D, p.cx, p.cy
        self.Omega_acting, self.F0, self.M, self.Omega = p.Omega_acting, p.F0, p.M, p.Omega
        self.mu, self.d, self.m, self.L2, self.L1 = p.mu, p.d, p.m, p.L2, p.L1


def coast(p, x, v, y, u, fx, fy, T):
    """(x, v, y, u) after T of free flight without the built-in harmonic when no stop is within
    reach over [0, T], else None; p = LinearParams(params).  A conservative `clear` test (the
    all-time swing, then the piece's Taylor reach) and Flight's positions in the same operations,
    without building the segment: the event loop's fast path for the steps that cannot meet a stop."""
    w2, w1 = p.w2, p.w1
    ww2, ww1 = w2 * w2, w1 * w1
    a2, b2 = x - fx / ww2, v / w2
    a1, b1 = y - fy / ww1, u / w1
    D = p.D
    r2 = _libm.sqrt(a2 * a2 + b2 * b2) * _ABOVE + _UNDERFLOW  # >= hypot(a2, b2)
    r1 = _libm.sqrt(a1 * a1 + b1 * b1) * _ABOVE + _UNDERFLOW
    swing = p.cx * (abs(x - a2) + r2) + p.cy * (abs(y - a1) + r1)
    growth = 1.0 + max(w1, w2, p.Omega_acting) * T
    if not swing < D - _TOL * (D + swing) * growth:  # the all-time swing may reach a stop: try the piece's reach
        zmax = (p.cx * min(abs(x - a2) + r2, abs(x) + abs(v) * T + 0.5 * ww2 * r2 * T * T) +
                p.cy * min(abs(y - a1) + r1, abs(y) + abs(u) * T + 0.5 * ww1 * r1 * T * T))
        if not zmax < D - _TOL * (D + noise_size(swing, zmax, D)) * growth:
            return None
    h2, h1 = 0.5 * w2 * T, 0.5 * w1 * T
    sh2, sh1 = _libm.sin(h2), _libm.sin(h1)
    s2, s1 = 2.0 * sh2 * _libm.cos(h2), 2.0 * sh1 * _libm.cos(h1)  # sin(w T)
    o2, o1 = 2.0 * sh2 * sh2, 2.0 * sh1 * sh1  # 1 - cos(w T)
    return x + b2 * s2 - a2 * o2, v - v * o2 - w2 * a2 * s2, y + b1 * s1 - a1 * o1, u - u * o1 - w1 * a1 * s1


class Flight:
    """Free flight of both pendulums; guards = distances to the two stops.

    Without a built-in harmonic both motions are plain sinusoids about their equilibria,
    and the gap is evaluated inline (this is the solver's innermost loop).
    """

    reach = math.inf  # the closed form holds over the whole span
    __slots__ = ("px", "py", "cx", "cy", "D", "bounds", "noise", "growth", "clear", "sgn", "inline", "start",
                 "w2", "x0", "v0", "a2", "b2", "w1", "y0", "u0", "a1", "b1")

    def __init__(self, p, x, v, y, u, fx, fy, psi, T, always_bound=False):
        self._init(p, x, v, y, u, fx, fy, psi, T, always_bound)

    def _init(self, p, x, v, y, u, fx, fy, psi, T, always_bound):
        """__init__'s body (typed in the compiled build: segments.pxd)."""
        a = p.F0 / p.M
        self.px = px = oscillator(p.w2, x, v, fx, a, p.Omega, psi)
        self.py = py = oscillator(p.w1, y, u, fy, 0.0, 0.0, 0.0)
        cx, cy, D = p.cx, p.cy, p.D
        self.cx, self.cy, self.D = cx, cy, D
        self.sgn = 0
        self.start = None  # gap derivatives at tau = 0, once computed
        self.inline = a == 0.0
        self.w2, self.x0, self.v0, self.a2, self.b2 = px.w, x, v, px.A, px.B
        self.w1, self.y0, self.u0, self.a1, self.b1 = py.w, y, u, py.A, py.B
        xh, _ = px.harmonic_bounds(T)
        x_lo, x_hi = px.reach(T)
        y_lo, y_hi = py.reach(T)
        zmax = cx * max(-x_lo, x_hi) + cy * max(-y_lo, y_hi)
        swing = cx * (abs(px.xe) + px.R + xh) + cy * (abs(py.xe) + py.R)
        tol = _TOL
        self.growth = max(p.w1, p.w2, p.Omega_acting)
        n0 = tol * (D + noise_size(swing, zmax, D))
        self.clear = zmax < D - n0 * (1.0 + self.growth * T)
        if self.clear and not always_bound:  # no stop within reach: bounds and noise are not needed
            self.bounds = self.noise = None
            return
        _, bx1, bx2, bx3, bx4, _, _ = px.bounds(T)
        _, by1, by2, by3, by4, _, _ = py.bounds(T)
        self.bounds = (cx * bx2 + cy * by2, cx * bx3 + cy * by3, cx * bx4 + cy * by4)
        self.noise = (n0, tol * (cx * bx1 + cy * by1),
                      tol * (cx * (bx2 + px.ww * abs(px.xe)) + cy * (by2 + py.ww * abs(py.xe))),
                      tol * (cx * bx3 + cy * by3))

    def positions(self, tau):
        """(x, v, y, u) at tau."""
        if self.inline:
            return self._inline(tau)
        x, v, _, _ = self.px.state(tau)
        y, u, _, _ = self.py.state(tau)
        return x, v, y, u

    def _inline(self, tau):
        """Oscillator.state of both bodies without the harmonic, inline: (x, v, y, u) at tau."""
        w2, w1 = self.w2, self.w1
        h2, h1 = 0.5 * w2 * tau, 0.5 * w1 * tau
        sh2, sh1 = _libm.sin(h2), _libm.sin(h1)
        s2, s1 = 2.0 * sh2 * _libm.cos(h2), 2.0 * sh1 * _libm.cos(h1)  # sin(w tau)
        o2, o1 = 2.0 * sh2 * sh2, 2.0 * sh1 * sh1  # 1 - cos(w tau)
        v, u, a2, a1 = self.v0, self.u0, self.a2, self.a1
        return (self.x0 + self.b2 * s2 - a2 * o2, v - v * o2 - w2 * a2 * s2,
                self.y0 + self.b1 * s1 - a1 * o1, u - u * o1 - w1 * a1 * s1)

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
            x, v, y, u = self._inline(tau)
            z, dz = cx * x - cy * y, cx * v - cy * u
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


def flight(p, x, v, y, u, fx, fy, psi, T, always_bound):
    """Flight(p, x, v, y, u, fx, fy, psi, T, always_bound), built without the call of __init__ (in
    the compiled build a C call)."""
    seg = Flight.__new__(Flight)
    seg._init(p, x, v, y, u, fx, fy, psi, T, always_bound)
    return seg


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
        self._init(p, x, v, sgn, fx, fy, psi, T)

    def _init(self, p, x, v, sgn, fx, fy, psi, T):
        """__init__'s body (typed in the compiled build: segments.pxd)."""
        mu, w1, w2, d = p.mu, p.w1, p.w2, p.d
        ww1 = w1 * w1
        big_w = _libm.sqrt((w2 * w2 + mu * ww1) / (1.0 + mu))  # correctly rounded: libc's equals CPython's
        a = p.F0 / p.M / (1.0 + mu)
        c = (mu * ww1 * sgn * d + fx + mu * fy) / (1.0 + mu)
        self.osc = osc = oscillator(big_w, x, v, c, a, p.Omega, psi)
        self.sgn, self.d, self.a, self.om = sgn, d, a, p.Omega
        self.k = k = ww1 - osc.ww
        # N/m = x'' + w1^2 (x - sgn d) - fy = k x + base + a sin(...), base = c - w1^2 sgn d - fy
        # (written with c, not with the equilibrium c / W^2, so a held load that dwarfs the
        # restoring force does not cancel)
        self.base = c - ww1 * sgn * d - fy
        P0, P1, P2, P3, P4, _, _ = osc.bounds(T)
        aa, om = abs(a), p.Omega
        self.bounds = (abs(k) * P2 + aa * om ** 2, abs(k) * P3 + aa * om ** 3, abs(k) * P4 + aa * om ** 4)
        tol = _TOL
        self.growth = max(big_w, p.Omega_acting)
        lo, hi = osc.reach(T)
        size = noise_size(abs(osc.xe) + P0, max(-lo, hi), d)
        n0 = tol * (abs(k) * size + abs(c) + ww1 * d + aa + abs(fy))
        self.noise = (n0,
                      tol * (abs(k) * P1 + aa * om),
                      tol * (abs(k) * (P2 + abs(c)) + aa * om * om),
                      tol * (abs(k) * P3 + aa * om ** 3))
        floor = sgn * self.base + min(sgn * k * lo, sgn * k * hi) - aa  # least s N/m over [0, T]
        self.clear = floor > n0 * (1.0 + self.growth * T)

    def positions(self, tau):
        x, v, _, _ = self.osc.state(tau)
        return x, v, x - self.sgn * self.d, v

    def values(self, tau):
        x, v, sf, cf = self.osc.state(tau)
        s = self.sgn
        return (s * (self.k * x + self.base + self.a * sf),
                s * (self.k * v + self.a * self.om * cf))

    def derivs(self, tau, i=0):
        x, v, x2, x3, sf, cf = self.osc.derivs(tau)
        s, k, a, om = self.sgn, self.k, self.a, self.om
        return (s * (k * x + self.base + a * sf), s * (k * v + a * om * cf),
                s * (k * x2 - a * om * om * sf), s * (k * x3 - a * om ** 3 * cf))


def stick(p, x, v, sgn, fx, fy, psi, T):
    """Stick(p, x, v, sgn, fx, fy, psi, T), built without the call of __init__ (in the compiled build
    a C call)."""
    seg = Stick.__new__(Stick)
    seg._init(p, x, v, sgn, fx, fy, psi, T)
    return seg
