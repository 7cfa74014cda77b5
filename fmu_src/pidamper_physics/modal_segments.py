"""Segments of the damped and coupled levels: closed-form modal motion (modal.py) with guards.

Same protocol as segments.py (see events.py): values, derivs, bounds, noise, growth, clear,
positions.  The state is z = (x, y, v, u) in flight and (x, v) while the particle rides a
stop; x, y are the horizontal displacements of primary and particle [m] measured from the
ground, whatever the level.

- ModalFlight: guards D -+ (x - y), the gaps to the two stops.
- ModalStick: guard s N/m, the contact force per particle mass on stop s, an affine function
  N/m = kx x + kv v + k0 + kf sin(Omega tau + psi) of the riding pair's state.
"""
import math

from .modal import Motion
from .segments import TOLERANCE, noise_size

_ORDERS = 6  # derivative bounds up to the 5th: the stick guard needs x^(5) for its 4th


class ModalFlight:
    """Both bodies free; z = (x, y, v, u) follows the 2-DOF system of the level.  A building's
    segment (building_level.py) passes its (N+1)-DOF system and gap = (floor index, particle index)."""

    reach = math.inf  # the closed form holds over the whole span
    __slots__ = ("motion", "K", "C", "b", "f", "om", "D", "bounds", "noise", "growth", "clear", "gap")

    def __init__(self, system, z0, b, a, om, psi, T, D, always_bound=False, gap=(0, 1)):
        modes, K, C = system
        n = modes.n
        ix, iy = gap
        if a == 0.0:
            f = None
        else:
            f = [0.0] * n
            f[ix] = a
        self.motion = motion = Motion(modes, z0, b, f, om, psi)
        self.K, self.C, self.b, self.f, self.om, self.D, self.gap = K, C, b, a, om, D, gap
        self.growth = max(modes.fastest, om if a != 0.0 else 0.0)
        rows = (ix, iy, n + ix, n + iy)  # x, y, v, u: the components the gap needs
        B = motion.bounds(T, _ORDERS, rows)
        rx, ry, _, _ = motion.rest(rows)
        x, y, v, u = (z0[i] for i in rows)
        Bx, By, Bv, Bu = B
        # |x - y| and |x| + |y| over [0, T]: the tighter of the swing about the equilibrium and
        # the start's Taylor bound (a held load that dwarfs the restoring force puts the
        # equilibrium far beyond the motion)
        zmax = min(abs(rx - ry) + Bx[0] + By[0],
                   abs(x - y) + T * min(Bx[1] + By[1], abs(v - u) + T * (Bx[2] + By[2])))
        size = noise_size(abs(rx) + abs(ry) + Bx[0] + By[0],
                          abs(x) + abs(y) + T * min(Bx[1] + By[1], abs(v) + abs(u) + T * (Bx[2] + By[2])), D)
        n0 = TOLERANCE * (D + size)
        self.clear = zmax < D - n0 * (1.0 + self.growth * T)
        self.bounds = tuple(Bx[j] + By[j] for j in (2, 3, 4))
        self.noise = (n0,) + tuple(TOLERANCE * (Bx[j] + By[j] + Bv[j - 1] + Bu[j - 1]) for j in (1, 2, 3))

    def positions(self, tau):
        x, y, v, u = self.motion.state(tau)
        return x, v, y, u

    def values(self, tau):
        x, y, v, u = self.motion.state(tau)
        g, dg = x - y, v - u
        D = self.D
        return D - g, -dg, D + g, dg

    def derivs(self, tau, i):
        x, y, v, u = self.motion.state(tau)
        s, c = self.motion.load(tau)
        K, C, b, a, om = self.K, self.C, self.b, self.f, self.om
        ax = b[0] + a * s - K[0][0] * x - K[0][1] * y - C[0][0] * v - C[0][1] * u
        ay = b[1] - K[1][0] * x - K[1][1] * y - C[1][0] * v - C[1][1] * u
        jx = a * om * c - K[0][0] * v - K[0][1] * u - C[0][0] * ax - C[0][1] * ay
        jy = -K[1][0] * v - K[1][1] * u - C[1][0] * ax - C[1][1] * ay
        g, g1, g2, g3 = x - y, v - u, ax - ay, jx - jy
        if i == 0:
            return self.D - g, -g1, -g2, -g3
        return self.D + g, g1, g2, g3


class ModalStick:
    """The particle rides stop `sgn`: the pair (x, v) follows the 1-DOF system of the level;
    guard = sgn N/m with N/m = kx x + kv v + k0 + kf sin (see the module doc)."""

    reach = math.inf  # the closed form holds over the whole span
    __slots__ = ("motion", "k", "c", "b", "a", "om", "sgn", "d", "kx", "kv", "k0", "bounds", "noise", "growth",
                 "clear")

    def __init__(self, system, x, v, sgn, d, b, a, om, psi, T, contact):
        modes, K, C = system
        self.motion = motion = Motion(modes, (x, v), (b,), (a,) if a != 0.0 else None, om, psi)
        self.k, self.c, self.b, self.a, self.om, self.sgn, self.d = K[0][0], C[0][0], b, a, om, sgn, d
        self.kx, self.kv, self.k0 = contact  # N/m = kx x + kv v + k0 + a sin (x'' folded in)
        self.growth = max(modes.fastest, om if a != 0.0 else 0.0)
        B = motion.bounds(T, _ORDERS)
        rest = motion.rest()[0]
        kx, kv, aa = abs(self.kx), abs(self.kv), abs(a)
        self.bounds = tuple(kx * B[0][j] + kv * B[0][j + 1] + aa * om ** j for j in (2, 3, 4))
        # |x|, |v| over [0, T]: the tighter of the swing about the equilibrium and the start's
        # Taylor bound (see ModalFlight)
        vmax = min(B[0][1], abs(v) + T * B[0][2])
        xmax = noise_size(abs(rest) + B[0][0], abs(x) + T * vmax, d)
        swing = abs(rest) + B[0][0]
        scale = abs(self.k0) + kx * xmax + kv * (B[0][1] if xmax == swing else vmax) + aa
        self.noise = (TOLERANCE * scale,) + tuple(TOLERANCE * (kx * B[0][j] + kv * B[0][j + 1] + aa * om ** j)
                                                  for j in (1, 2, 3))
        start = sgn * (self.kx * x + self.kv * v + self.k0 + a * math.sin(psi))
        floor = max(sgn * (self.k0 + self.kx * rest) - kx * B[0][0] - kv * B[0][1] - aa,
                    start - T * (kx * vmax + kv * B[0][2] + aa * om))  # least s N/m over [0, T]
        self.clear = floor > self.noise[0] * (1.0 + self.growth * T)

    def positions(self, tau):
        x, v = self.motion.state(tau)
        return x, v, x - self.sgn * self.d, v

    def _chain(self, tau):
        """x, v, x'', x''', x'''' and sin, cos of the load at tau."""
        x, v = self.motion.state(tau)
        s, c = self.motion.load(tau)
        k, cc, a, om = self.k, self.c, self.a, self.om
        x2 = self.b + a * s - k * x - cc * v
        x3 = a * om * c - k * v - cc * x2
        x4 = -a * om * om * s - k * x2 - cc * x3
        return x, v, x2, x3, x4, s, c

    def values(self, tau):
        x, v, x2, _, _, s, c = self._chain(tau)
        sg, a, om = self.sgn, self.a, self.om
        return (sg * (self.kx * x + self.kv * v + self.k0 + a * s),
                sg * (self.kx * v + self.kv * x2 + a * om * c))

    def derivs(self, tau, i=0):
        x, v, x2, x3, x4, s, c = self._chain(tau)
        sg, a, om, kx, kv = self.sgn, self.a, self.om, self.kx, self.kv
        return (sg * (kx * x + kv * v + self.k0 + a * s), sg * (kx * v + kv * x2 + a * om * c),
                sg * (kx * x2 + kv * x3 - a * om * om * s), sg * (kx * x3 + kv * x4 - a * om ** 3 * c))


def harmonic_work(seg, tau, amplitude, om, psi, velocity):
    """Integral of amplitude sin(om s + psi) velocity(s) ds over [0, tau] by Gauss-Legendre
    panels short enough (|lambda| h <= 0.5) that each is exact to rounding."""
    if tau <= 0.0 or amplitude == 0.0:
        return 0.0
    rate = seg.growth + om
    panels = max(1, int(math.ceil(rate * tau / 0.5)))
    h = tau / panels
    nodes, weights = _gauss(_GL_ORDER)
    total = 0.0
    for p in range(panels):
        mid = (p + 0.5) * h
        for xk, wk in zip(nodes, weights):
            s = mid + 0.5 * h * xk
            total += wk * math.sin(om * s + psi) * velocity(seg, s)
    return amplitude * 0.5 * h * total


_GL_ORDER = 8  # 8 nodes on a panel with |lambda| h <= 0.5: error below (0.5)^16 / 16! relative
_GL_CACHE = {}


def _gauss(n):
    """Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n, cached)."""
    if n not in _GL_CACHE:
        nodes, weights = [], []
        for i in range(n):
            x = math.cos(math.pi * (i + 0.75) / (n + 0.5))
            for _ in range(100):
                p0, p1 = 1.0, x
                for k in range(2, n + 1):
                    p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
                dp = n * (x * p1 - p0) / (x * x - 1.0)
                dx = p1 / dp
                x -= dx
                if abs(dx) < 1e-16:
                    break
            nodes.append(x)
            weights.append(2.0 / ((1.0 - x * x) * dp * dp))
        _GL_CACHE[n] = (tuple(nodes), tuple(weights))
    return _GL_CACHE[n]
