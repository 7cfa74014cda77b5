"""Closed-form motion of one linear oscillator over one segment: the family's two closed forms.

`Oscillator`, undamped under a constant and a harmonic load (the pendulum's linear level):

    x'' + w**2 * x = c + a * sin(Omega * tau + psi),    tau = t - t0 >= 0,
    x(0) = x0,  x'(0) = v0.

`DampedOscillator`, damped under a held load (a building's modes, the damper unit's particle):

    q'' + 2 zeta w q' + w**2 q = p,    0 <= zeta < 1.

The complex modal form (modal.Motion) covers both in exact arithmetic, damping and harmonic
together, but for one degree of freedom it costs about 4 times as much per evaluation (0.33 against
1.43 us free, 1.05 against 4.12 us forced, 2-core AMD EPYC, CPython 3.11: `python -m
pidamper.benchmarks.closed_forms`), so these two stay as the innermost fast paths.

Units: x in metres (or radians: the formula does not care), w and Omega in
rad/s, c and a in m/s2.  The solution is written about the start, not about the
equilibrium xe = c / w**2:

    x = x0 + B sin(w tau) - A (1 - cos(w tau)) + a * (sin(psi) Dc(tau) + cos(psi) Ds(tau))

with A = x0 - xe, B = v0 / w, 1 - cos = 2 sin^2(w tau / 2), and Dc, Ds the
zero-initial-condition responses to cos(Omega tau) and sin(Omega tau).  Written so,
a held load that dwarfs the restoring force (xe >> the motion: a small g, a large
force) does not cancel: x - x0 is computed to full relative precision for every w > 0.
Dc and Ds are evaluated through half-sum and half-difference angles, so they are
exact for every Omega >= 0: at exact resonance (secular growth) and next to it (no
0/0 cancellation).
"""
import math
import math as _libm  # sin, cos, expm1: in the compiled build libc's (oscillator.pxd: from libc cimport math as _libm), the
# very functions CPython's math.sin and math.cos call (math.hypot is CPython's own: kept from math)

_hypot = math.hypot  # bound once: a module attribute costs a lookup per call


class Oscillator:
    """One segment of x'' + w^2 x = c + a sin(Omega tau + psi); see the module doc."""

    __slots__ = ("w", "ww", "xe", "A", "B", "R", "x0", "v0", "wa", "a", "om", "sp", "cp", "hs", "hd")

    def __init__(self, w, x0, v0, c=0.0, a=0.0, om=0.0, psi=0.0):
        self._init(w, x0, v0, c, a, om, psi)

    def _init(self, w, x0, v0, c, a, om, psi):
        """__init__'s body (typed in the compiled build: oscillator.pxd)."""
        ww = w * w
        self.w = w
        self.ww = ww
        self.xe = c / ww
        self.x0, self.v0 = x0, v0
        self.A = x0 - self.xe
        self.B = v0 / w
        self.wa = w * self.A
        self.R = _hypot(self.A, self.B)
        self.a = a
        self.om = om
        if a != 0.0:
            self.sp = _libm.sin(psi)
            self.cp = _libm.cos(psi)
            self.hs = 0.5 * (om + w)  # half sum of the frequencies
            self.hd = 0.5 * (om - w)  # half difference

    def state(self, tau):
        """(x, dx, sin, cos) at tau; sin and cos are those of Omega tau + psi (0 unforced)."""
        if self.a == 0.0:
            h = 0.5 * self.w * tau
            sh = _libm.sin(h)
            s = 2.0 * sh * _libm.cos(h)  # sin(w tau)
            omc = 2.0 * sh * sh  # 1 - cos(w tau)
            v0 = self.v0
            return self.x0 + self.B * s - self.A * omc, v0 - v0 * omc - self.wa * s, 0.0, 0.0
        return self._forced(tau)

    def reach(self, T):
        """(lo, hi): x stays within [lo, hi] over 0 <= tau <= T: the tighter of the swing about
        the equilibrium and the start's Taylor bound (|x''| <= w^2 R), plus the harmonic response."""
        xh, _ = self.harmonic_bounds(T)
        R, xe, x0 = self.R, self.xe, self.x0
        spread = abs(self.v0) * T + 0.5 * self.ww * R * T * T
        return max(xe - R, x0 - spread) - xh, min(xe + R, x0 + spread) + xh

    def derivs(self, tau):
        """(x, dx, d2x, d3x, sin, cos) at tau, sin and cos as in state()."""
        x, v, sf, cf = self.state(tau)
        ww = self.ww
        a = self.a
        return x, v, a * sf - ww * (x - self.xe), a * self.om * cf - ww * v, sf, cf

    def _forced(self, tau):
        w = self.w
        hs = self.hs
        u = self.hd * tau
        ss = _libm.sin(hs * tau)
        cs = _libm.cos(hs * tau)
        sd = _libm.sin(u)
        cd = _libm.cos(u)
        s = ss * cd - cs * sd  # sin(w tau)
        co = cs * cd + ss * sd  # cos(w tau)
        so = ss * cd + cs * sd  # sin(Omega tau)
        coo = cs * cd - ss * sd  # cos(Omega tau)
        sinc = sd / u if u != 0.0 else 1.0
        dc = tau * ss * sinc / (2.0 * hs)
        ds = (s - w * tau * cs * sinc) / (2.0 * w * hs)
        a = self.a
        sp = self.sp
        cp = self.cp
        om = self.om
        hw = _libm.sin(0.5 * w * tau)
        omc = 2.0 * hw * hw  # 1 - cos(w tau), without cancellation
        v0 = self.v0
        x = self.x0 + self.B * s - self.A * omc + a * (sp * dc + cp * ds)
        v = v0 - v0 * omc - self.wa * s + a * (sp * (s / w - om * ds) + cp * om * dc)
        return x, v, sp * coo + cp * so, cp * coo - sp * so

    def harmonic_bounds(self, T):
        """Bounds of |x_h| and |x_h'| over 0 <= tau <= T for the harmonic response (0, 0 unforced)."""
        a = abs(self.a)
        if a == 0.0:
            return 0.0, 0.0
        w, om = self.w, self.om
        gap = abs(self.ww - om * om)
        xh, vh = a * T / w, a * T
        if gap > 0.0:
            xh = min(xh, a * (1.0 + max(1.0, om / w)) / gap)
            vh = min(vh, a * (om + max(w, om)) / gap)
        return xh, vh

    def bounds(self, T):
        """Bounds P0..P6 of |x - xe|, |x'|, ..., |x^(6)| over 0 <= tau <= T."""
        w = self.w
        ww = self.ww
        a = abs(self.a)
        R = self.R
        if a == 0.0:
            return (R, min(w * R, abs(self.v0) + ww * R * T), ww * R, ww * w * R, ww * ww * R, ww * ww * w * R,
                    ww * ww * ww * R)
        om = self.om
        xh, vh = self.harmonic_bounds(T)
        # p[k + 2] = ww * p[k] + a * om ** k, written out (om ** 0 = 1.0, om ** 1 = om exactly)
        p0 = R + xh
        p1 = min(w * R, abs(self.v0) + ww * R * T) + vh
        p2 = ww * p0 + a * 1.0
        p3 = ww * p1 + a * om
        p4 = ww * p2 + a * om ** 2
        p5 = ww * p3 + a * om ** 3
        p6 = ww * p4 + a * om ** 4
        return p0, p1, p2, p3, p4, p5, p6


def oscillator(w, x0, v0, c, a, om, psi):
    """Oscillator(w, x0, v0, c, a, om, psi), every argument given: built without the call of
    __init__ (in the compiled build a C call)."""
    osc = Oscillator.__new__(Oscillator)
    osc._init(w, x0, v0, c, a, om, psi)
    return osc


class DampedOscillator:
    """One segment of q'' + 2 zeta w q' + w^2 q = p (p held), from (q0, v0); 0 <= zeta < 1.

    Written about the start, q = q0 + A (exp(-s tau) cos(wd tau) - 1) + B exp(-s tau) sin(wd tau)
    with A = q0 - p/w^2, B = (v0 + s A)/wd, s = zeta w, wd = w sqrt(1 - zeta^2), and
    exp(-s tau) cos - 1 = expm1(-s tau) cos - 2 sin^2(wd tau / 2): no cancellation for short
    steps, nor when the held load dwarfs the motion."""

    __slots__ = ("w", "ww", "s", "wd", "p", "q0", "v0", "a", "b", "k")

    def __init__(self, w, zeta, q0=0.0, v0=0.0, p=0.0):
        self.w, self.ww, self.s, self.wd = w, w * w, zeta * w, w * math.sqrt(1.0 - zeta * zeta)
        self.start(q0, v0, p)

    def start(self, q0, v0, p):
        """Restart the segment from (q0, v0) under the held load p (the oscillator kept)."""
        ww, s, wd = self.ww, self.s, self.wd
        a = q0 - p / ww
        self.p, self.q0, self.v0, self.a = p, q0, v0, a
        self.b = (v0 + s * a) / wd
        self.k = (ww * a + s * v0) / wd

    def at(self, tau):
        """(q, q') at tau >= 0."""
        s, v0 = self.s, self.v0
        half = 0.5 * self.wd * tau
        sh = _libm.sin(half)
        sn = 2.0 * sh * _libm.cos(half)  # sin(wd tau)
        omc = 2.0 * sh * sh  # 1 - cos(wd tau)
        if s == 0.0:
            ec_m1, es = -omc, sn
        else:
            em1 = _libm.expm1(-s * tau)
            ec_m1 = em1 * (1.0 - omc) - omc  # exp(-s tau) cos(wd tau) - 1
            es = (1.0 + em1) * sn
        return self.q0 + self.a * ec_m1 + self.b * es, v0 + v0 * ec_m1 - self.k * es
