"""The nonlinear level: the coupled double pendulum at any angle, integrated by DOP853 (rk.py).

Coordinates (the Damper's x, v, y, u at this level): theta, theta' of the primary and phi, phi'
of the particle's wire, both from the vertical [rad, rad/s].  The primary bob sits at
xb = L2 sin(theta), the particle at yp = xb + L1 sin(phi); the stops are at yp - xb = -+d, so
the gap is z = xb - yp = -L1 sin(phi) and contact is z = +-d (a particle on a wire shorter
than d never reaches a stop).  Per unit mass (cs = 2 zeta_s w2, cp = 2 zeta_p w1, fx, fy the
horizontal loads per mass of each body, a = F0/M the built-in harmonic, s_ = sin(theta - phi)):

    (1 + mu) L2 theta'' + mu L1 cos(theta - phi) phi'' = cos(theta) (fx + a sin + mu fy - cs xb')
                                                         - mu L1 s_ phi'^2 - (1 + mu) g sin(theta)
    L2 cos(theta - phi) theta'' + L1 phi'' = cos(phi) (fy - cp L1 cos(phi) phi') + L2 s_ theta'^2 - g sin(phi)

whose small-angle limit is the coupled level.  Riding stop s fixes phi (L1 sin(phi) = -s d); the
stop's force on the particle then follows from the second equation with phi'' = phi' = 0.

Each segment is one accepted DOP853 step (rtol RTOL) with its dense polynomial.  Guards are
exact functions of the dense state; their derivative bounds come from a degree-7 polynomial
through the guard at 8 Chebyshev points of the step, padded by 2x, so conservative advancement
(events.py) steps over no contact of the computed motion.  The harmonic work and the dashpot
losses ride along as two extra integrated states, so the energy balance measures the
integration error.
"""
import math

from .level_model import LevelModel
from .rk import dop853_dense, dop853_step, poly_deriv_bound, poly_derivs, poly_eval

RTOL = 1e-12   # relative tolerance of a step
ATOL = 1e-13   # absolute tolerance [rad, rad/s, J/kg]
NOISE = 64 * RTOL  # resolution of a guard, relative to its scale (the integration error, not rounding)
_PAD = 2.0     # safety factor on the guard's derivative bounds
_NODES = tuple(0.5 - 0.5 * math.cos((2 * k + 1) * math.pi / 16) for k in range(8))


def _power_basis(values):
    """Coefficients c0..c7 in theta of the polynomial through (_NODES[k], values[k])."""
    a = list(values)
    n = len(a)
    for j in range(1, n):  # Newton divided differences
        for k in range(n - 1, j - 1, -1):
            a[k] = (a[k] - a[k - 1]) / (_NODES[k] - _NODES[k - j])
    poly = [a[-1]]
    for k in range(n - 2, -1, -1):  # expand (theta - x_k) * poly + a_k
        x = _NODES[k]
        new = [0.0] * (len(poly) + 1)
        for i, c in enumerate(poly):
            new[i + 1] += c
            new[i] -= x * c
        new[0] += a[k]
        poly = new
    return poly


class _Step:
    """One accepted DOP853 step of `self.rhs` from state y0 over at most T; subclasses add guards."""

    reach = 0.0

    def _integrate(self, model, y0, T):
        h = min(model.hint, T)
        f0 = self.rhs(0.0, y0)
        while True:
            y1, f1, err, K = dop853_step(self.rhs, 0.0, y0, f0, h, RTOL, ATOL)
            factor = 0.9 * err ** (-1.0 / 8.0) if err > 0.0 else 5.0
            if err <= 1.0:
                break
            h *= max(0.2, factor)
        model.hint = h * min(5.0, max(0.2, factor))
        self.reach, self.h = h, h
        self.poly = dop853_dense(self.rhs, 0.0, y0, h, K, y1)
        self.end = y1

    def state(self, tau):
        if tau >= self.reach:
            return self.end
        th = tau / self.h
        return [poly_eval(c, th) for c in self.poly]

    def _guard_bounds(self, guards, scale):
        """bounds, noise, clear from polynomials through the guards g(tau, state) at the Chebyshev points."""
        h = self.h
        polys = [_power_basis([g(x * h, self.state(x * h)) for x in _NODES]) for g in guards]
        self.gpoly = polys
        self.bounds = tuple(_PAD * max(poly_deriv_bound(c, j, h) for c in polys) for j in (2, 3, 4))
        b1 = max(poly_deriv_bound(c, 1, h) for c in polys)
        self.noise = (NOISE * scale, NOISE * b1, NOISE * self.bounds[0], NOISE * self.bounds[1])
        self.growth = 0.0
        self.clear = all(c[0] - sum(abs(x) for x in c[1:]) > 2.0 * self.noise[0] for c in polys)

    def quad(self, tau):
        """(harmonic work, dashpot loss) per primary mass [J/kg] from the start to tau."""
        s = self.state(tau)
        return s[-2], s[-1]


class NonlinearFlight(_Step):
    """Both bodies free: state (theta, theta', phi, phi', work, loss)."""

    def __init__(self, model, x, v, y, u, fc, psi, T):
        self.m, self.fx, self.fy, self.psi = model, fc[0], fc[1], psi
        self._integrate(model, [x, v, y, u, 0.0, 0.0], T)
        p = model.p
        self.D, self.L1 = p.d, p.L1
        self._guard_bounds((self._g0, self._g1), p.d + p.L1)

    def rhs(self, tau, s):
        m = self.m
        th, dth, ph, dph = s[0], s[1], s[2], s[3]
        load = m.load(self.fx, tau, self.psi)
        acc_th, acc_ph = m.free_accel(th, dth, ph, dph, load, self.fy)
        vb, vr = m.L2 * math.cos(th) * dth, m.L1 * math.cos(ph) * dph
        return [dth, acc_th, dph, acc_ph, (load - self.fx) * vb, m.cs * vb * vb + m.mu * m.cp * vr * vr]

    def _g0(self, tau, s):
        return self.D + self.L1 * math.sin(s[2])  # D - z, z = -L1 sin(phi)

    def _g1(self, tau, s):
        return self.D - self.L1 * math.sin(s[2])

    def positions(self, tau):
        s = self.state(tau)
        return s[0], s[1], s[2], s[3]

    def values(self, tau):
        s = self.state(tau)
        L1, ph = self.L1, s[2]
        z, dz = -L1 * math.sin(ph), -L1 * math.cos(ph) * s[3]
        return self.D - z, -dz, self.D + z, dz

    def derivs(self, tau, i):
        values = self.values(tau)
        g, g1 = values[2 * i], values[2 * i + 1]
        _, _, g2, g3 = poly_derivs(self.gpoly[i], min(tau / self.h, 1.0), self.h)
        return g, g1, g2, g3


class NonlinearStick(_Step):
    """The particle rides stop `sgn` at the fixed wire angle phi_s: state (theta, theta', work, loss);
    guard = sgn N/m."""

    def __init__(self, model, x, v, phi_s, sgn, fc, psi, T):
        self.m, self.fx, self.fy, self.psi = model, fc[0], fc[1], psi
        self.phi, self.sgn = phi_s, sgn
        self._integrate(model, [x, v, 0.0, 0.0], T)
        p = model.p
        self._guard_bounds((self._guard,), p.g + abs(self.fy) + abs(self.fx) + abs(model.a))

    def rhs(self, tau, s):
        m = self.m
        th, dth = s[0], s[1]
        load = m.load(self.fx, tau, self.psi)
        vb = m.L2 * math.cos(th) * dth
        return [dth, m.ride_accel(th, dth, load, self.fy), (load - self.fx) * vb, m.cs * vb * vb]

    def _guard(self, tau, s):
        m = self.m
        load = m.load(self.fx, tau, self.psi)
        return self.sgn * m.contact(s[0], s[1], self.phi, m.ride_accel(s[0], s[1], load, self.fy), self.fy)

    def positions(self, tau):
        s = self.state(tau)
        return s[0], s[1], self.phi, 0.0

    def values(self, tau):
        g = self._guard(tau, self.state(tau))
        _, g1, _, _ = poly_derivs(self.gpoly[0], min(tau / self.h, 1.0), self.h)
        return g, g1

    def derivs(self, tau, i=0):
        g, _ = self.values(tau)
        _, g1, g2, g3 = poly_derivs(self.gpoly[0], min(tau / self.h, 1.0), self.h)
        return g, g1, g2, g3


class NonlinearModel(LevelModel):
    """Level model (level_model.py) of the double pendulum at any angle."""

    piece_weight = 5  # an integrator step costs about five closed-form pieces (Damper.max_pieces)

    def __init__(self, p):
        super().__init__(p)
        self.mu, self.L1, self.L2, self.g = p.mu, p.L1, p.L2, p.g
        self.cs, self.cp = 2.0 * p.zeta_s * p.w2, 2.0 * p.zeta_p * p.w1
        self.a, self.om = p.F0 / p.M, p.Omega
        self.fastest = max(p.w1, p.w2, p.Omega_acting) * math.sqrt(1.0 + p.mu)
        self.hint = 0.05 / self.fastest

    def get_state(self):
        return {"step_hint": self.hint}  # the integrator's next step [s]

    def set_state(self, state):
        self.hint = state["step_hint"]

    def load(self, fx, tau, psi):
        """Horizontal load per primary mass [m/s2]: held fx plus the built-in harmonic at tau."""
        return fx + self.a * math.sin(self.om * tau + psi) if self.a else fx

    def free_accel(self, th, dth, ph, dph, load, fy):
        """(theta'', phi'') of the free double pendulum (the equations of the module doc)."""
        mu, L1, L2, g = self.mu, self.L1, self.L2, self.g
        ct, cf = math.cos(th), math.cos(ph)
        c, sn = math.cos(th - ph), math.sin(th - ph)
        vb, vr = L2 * ct * dth, L1 * cf * dph
        r1 = ct * (load + mu * fy - self.cs * vb) - mu * L1 * sn * dph * dph - (1.0 + mu) * g * math.sin(th)
        r2 = cf * (fy - self.cp * vr) + L2 * sn * dth * dth - g * math.sin(ph)
        det = 1.0 + mu * sn * sn
        return (r1 - mu * c * r2) / (L2 * det), ((1.0 + mu) * r2 - c * r1) / (L1 * det)

    def ride_accel(self, th, dth, load, fy):
        """theta'' while the particle rides a stop (phi fixed)."""
        ct = math.cos(th)
        vb = self.L2 * ct * dth
        return (ct * (load + self.mu * fy - self.cs * vb) / (1.0 + self.mu) - self.g * math.sin(th)) / self.L2

    def contact(self, th, dth, phi, acc, fy):
        """N/m [m/s2] of the stop on the particle riding at wire angle phi, theta'' = acc."""
        c, sn = math.cos(th - phi), math.sin(th - phi)
        return (self.L2 * (c * acc - sn * dth * dth) + self.g * math.sin(phi)) / math.cos(phi) - fy

    def flight(self, x, v, y, u, fc, psi, T, always_bound=False):
        return NonlinearFlight(self, x, v, y, u, fc, psi, T)

    def stick(self, x, v, side, fc, psi, T):
        return NonlinearStick(self, x, v, self._phi_stop(side), side, fc, psi, T)

    def _phi_stop(self, side):
        return math.asin(-side * self.p.d / self.L1)

    def displacements(self, x, v, y, u):
        """(xb, xb', yp, yp') horizontal positions and velocities of bob and particle [m, m/s]."""
        L1, L2 = self.L1, self.L2
        xb, vb = L2 * math.sin(x), L2 * math.cos(x) * v
        return xb, vb, xb + L1 * math.sin(y), vb + L1 * math.cos(y) * u

    def angles(self, x, v, y, u):
        return x, v, y, u

    def energy(self, x, v, y, u):
        p = self.p
        L1, L2 = self.L1, self.L2
        kin = 0.5 * p.M * (L2 * v) ** 2 + 0.5 * p.m * ((L2 * v) ** 2 + (L1 * u) ** 2 + 2 * L2 * L1 * math.cos(x - y) * v * u)
        pot = (p.M + p.m) * p.g * L2 * 2.0 * math.sin(0.5 * x) ** 2 + p.m * p.g * L1 * 2.0 * math.sin(0.5 * y) ** 2
        return kin + pot

    def acceleration(self, x, v, y, u, side, f, ground):
        """Horizontal acceleration of the primary bob [m/s2]."""
        dd = self.ride_accel(x, v, f - ground, -ground) if side else self.free_accel(x, v, y, u, f - ground, -ground)[0]
        return self.L2 * (math.cos(x) * dd - math.sin(x) * v * v)

    def from_angles(self, theta, theta_dot, alpha, alpha_dot):
        return theta, theta_dot, alpha, alpha_dot

    def particle_swing(self, x, v, y, u):
        return self.L1 * y, self.L1 * u

    def contact_accel(self, x, v, side, f, ground):
        return self.contact(x, v, self._phi_stop(side), self.ride_accel(x, v, f - ground, -ground), -ground)

    def work(self, seg, tau, before, after, fc, psi, e_change):
        p = self.p
        xb0, _, yp0, _ = self.displacements(*before)
        xb1, _, yp1, _ = self.displacements(*after)
        harmonic, loss = seg.quad(tau)
        held = p.M * fc[0] * (xb1 - xb0) + p.m * fc[1] * (yp1 - yp0)
        return held + p.M * harmonic, p.M * loss

    def snap(self, x, v, y, u, side):
        """Put the particle exactly on stop `side` (Newton on L1 sin(phi) = -side d, same branch)."""
        target = -side * self.p.d / self.L1
        for _ in range(3):
            y -= (math.sin(y) - target) / math.cos(y)
        return x, v, y, u

    def approach(self, x, v, y, u):
        """(yp' - xb' [m/s], the effective mass of the impact along the stop's normal [kg])."""
        p, mu = self.p, self.mu
        cf = math.cos(y)
        return self.L1 * cf * u, p.M * mu * (1.0 + mu * math.sin(x - y) ** 2) / ((1.0 + mu) * cf * cf)

    def collide(self, x, v, y, u, side, e):
        """Newton's law on the horizontal normal of the stop: (state after, loss [J], relative
        velocity yp' - xb' before and after [m/s])."""
        p, mu = self.p, self.mu
        cf, c = math.cos(y), math.cos(x - y)
        rel = self.L1 * cf * u  # yp' - xb' = -z'
        kick = (1.0 + e) * rel
        u_new = u - kick / (self.L1 * cf)
        v_new = v + kick * mu * c / ((1.0 + mu) * self.L2 * cf)
        m_eff = p.M * mu * (1.0 + mu * math.sin(x - y) ** 2) / ((1.0 + mu) * cf * cf)
        loss = 0.5 * (1.0 - e * e) * m_eff * rel * rel
        return (x, v_new, y, u_new), loss, rel, -e * rel
