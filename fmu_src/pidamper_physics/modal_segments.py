"""Segments of the damped and coupled levels: closed-form modal motion (modal.py) with guards.

Same protocol as segments.py (see events.py): values, derivs, bounds, noise, growth, clear,
positions.  The state is z = (x, y, v, u) in flight and (x, v) while the particle rides a
stop; x, y are the horizontal displacements of primary and particle [m] measured from the
ground, whatever the level.

- ModalFlight: guards D -+ (x - y), the gaps to the two stops.
- ModalStick: guard s N/m, the contact force per particle mass on stop s, an affine function
  N/m = kx . x + kv . v + k0 + kf sin(Omega tau + psi) of the riding system's state (the pendulum
  levels' pair: one DOF; a building's floors: N).
"""
import math

from .modal import Motion, _dot_real
from .peaks import Piece
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
        # (_guard reads the bounds of x and y to the 4th order, of v and u to the 2nd)
        bounds = motion.bounds(T, 5, (ix, iy)) + motion.bounds(T, 3, (n + ix, n + iy))
        self._guard(bounds, motion.rest(rows), [z0[i] for i in rows], T, D)

    def _guard(self, B, rest, start, T, D):
        """clear, bounds and noise of the gap's guards from the bounds B of x, y, v, u over [0, T],
        their rest values and their start values."""
        rx, ry = rest[0], rest[1]
        x, y, v, u = start[0], start[1], start[2], start[3]
        Bx, By, Bv, Bu = B[0], B[1], B[2], B[3]
        x0, x1, x2, x3, x4 = Bx[0], Bx[1], Bx[2], Bx[3], Bx[4]  # the bounds of |x - rest|, |x'|, ..., |x^(4)|
        y0, y1, y2, y3, y4 = By[0], By[1], By[2], By[3], By[4]
        v0, v1, v2, u0, u1, u2 = Bv[0], Bv[1], Bv[2], Bu[0], Bu[1], Bu[2]
        # |x - y| and |x| + |y| over [0, T]: the tighter of the swing about the equilibrium and
        # the start's Taylor bound (a held load that dwarfs the restoring force puts the
        # equilibrium far beyond the motion)
        zmax = min(abs(rx - ry) + x0 + y0, abs(x - y) + T * min(x1 + y1, abs(v - u) + T * (x2 + y2)))
        size = noise_size(abs(rx) + abs(ry) + x0 + y0,
                          abs(x) + abs(y) + T * min(x1 + y1, abs(v) + abs(u) + T * (x2 + y2)), D)
        tol = TOLERANCE
        n0 = tol * (D + size)
        self.clear = zmax < D - n0 * (1.0 + self.growth * T)
        self.bounds = (x2 + y2, x3 + y3, x4 + y4)
        self.noise = (n0, tol * (x1 + y1 + v0 + u0), tol * (x2 + y2 + v1 + u1), tol * (x3 + y3 + v2 + u2))

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
    """The particle rides stop `sgn` of DOF j: z = (x_1..x_N, v_1..v_N) follows the riding system
    (the pendulum levels: N = 1, the primary; a building: its floors, j the damper's);
    guard = sgn N/m, N/m = kx . x + kv . v + k0 + a sin(Omega tau + psi) (kx, kv: rows of N)."""

    reach = math.inf
    __slots__ = ("motion", "j", "n", "sgn", "d", "a", "om", "kx", "kv", "k0", "K", "C", "b", "bounds", "noise",
                 "growth", "clear", "_tau", "_z", "start_floors", "z0")

    def __init__(self, system, z0, j, sgn, d, b, a, om, psi, T, contact):
        modes, K, C = system
        n = modes.n
        f = None
        if a != 0.0:
            f = [0.0] * n
            f[j] = a
        self.motion = motion = Motion(modes, z0, b, f, om, psi)
        self.j, self.n, self.sgn, self.d, self.a, self.om, self.K, self.C, self.b = j, n, sgn, d, a, om, K, C, b
        self.kx, self.kv, self.k0 = contact
        self._tau, self._z = 0.0, z0
        self.z0 = z0  # the start state (z at tau = 0)
        self.start_floors = z0[:n]
        self.growth = max(modes.fastest, om if a != 0.0 else 0.0)
        aa = abs(a)
        # the guard's linear part c . z = kx . x + kv . v, as a row over the modes, and its bounds
        V = modes.V
        row = [_mode_row(self.kx, self.kv, V, n, k) for k in range(len(modes.lam))]
        bound = motion.bounds(T, _ORDERS, None, [row])[0]  # (rows, vectors)
        rest = motion.rest(None, [row])[0]
        self.bounds = tuple(bound[o] + aa * om ** o for o in (2, 3, 4))
        size = _pair_dot_abs(self.kx, z0, self.kv, n)
        self.noise = (TOLERANCE * (abs(self.k0) + noise_size(abs(rest) + bound[0], size + T * bound[1], d) + aa),) + \
            tuple(TOLERANCE * (bound[o] + aa * om ** o) for o in (1, 2, 3))
        start = sgn * (_pair_dot(self.kx, z0, 0, self.kv, z0, n, n) + self.k0 + a * math.sin(psi))
        floor = max(sgn * (self.k0 + rest) - bound[0] - aa, start - T * (bound[1] + aa * om))  # least s N/m on [0, T]
        self.clear = floor > self.noise[0] * (1.0 + self.growth * T)

    def state(self, tau):
        if tau != self._tau:
            self._tau, self._z = tau, self.motion.state(tau)
        return self._z

    def floors_at(self, tau):
        return self.state(tau)[:self.n]

    def others(self, tau):
        z = self.state(tau)
        j, n = self.j, self.n
        return z[:j] + z[j + 1:n] + z[n:n + j] + z[n + j + 1:]

    def positions(self, tau):
        z = self.state(tau)
        x, v = z[self.j], z[self.n + self.j]
        return x, v, x - self.sgn * self.d, v

    def _chain(self, tau):
        """z, its acceleration and jerk vectors, and sin, cos of the load at tau."""
        s, c = self.motion.load(tau)
        return chain(self.state(tau), self.n, self.K, self.C, self.b, self.j, self.a, self.om, s, c) + (s, c)

    def take_peaks(self, peaks, tau, ground, guards=None):
        """Raise a building's running maxima (peaks.Peaks) over [0, tau] of this piece (guards: the
        yielding storeys' StoreyGuards on its motion, or None)."""
        take_peaks(self, peaks, tau, ground, self.n, self.j, self.a, guards)

    def values(self, tau):
        x, v, acc, _, _, s, c = self._chain(tau)
        sg, kx, kv, a, om, n = self.sgn, self.kx, self.kv, self.a, self.om, self.n
        return (sg * (_pair_dot(kx, x, 0, kv, v, 0, n) + self.k0 + a * s),
                sg * (_pair_dot(kx, v, 0, kv, acc, 0, n) + a * om * c))

    def derivs(self, tau, i=0):
        x, v, acc, jerk, snap, s, c = self._chain(tau)
        sg, kx, kv, a, om, n = self.sgn, self.kx, self.kv, self.a, self.om, self.n
        return (sg * (_pair_dot(kx, x, 0, kv, v, 0, n) + self.k0 + a * s),
                sg * (_pair_dot(kx, v, 0, kv, acc, 0, n) + a * om * c),
                sg * (_pair_dot(kx, acc, 0, kv, jerk, 0, n) - a * om * om * s),
                sg * (_pair_dot(kx, jerk, 0, kv, snap, 0, n) - a * om ** 3 * c))


def _pair_dot(p, x, ox, q, y, oy, n):
    """sum_i (p_i x_(ox+i) + q_i y_(oy+i)), i < n, of floats, added left to right from 0 (as sum()
    did before CPython 3.12 compensated it: one order for both builds on every Python)."""
    s = 0.0
    for i in range(n):
        a, b, c, d = p[i], x[ox + i], q[i], y[oy + i]
        s += a * b + c * d
    return s


def _pair_dot_abs(p, z, q, n):
    """sum_i (|p_i| |z_i| + |q_i| |z_(n+i)|), i < n, added left to right from 0."""
    s = 0.0
    for i in range(n):
        a, b, c, d = p[i], z[i], q[i], z[n + i]
        s += abs(a) * abs(b) + abs(c) * abs(d)
    return s


def _mode_row(p, q, V, n, k):
    """sum_i (p_i V_ik + q_i V_(n+i)k), i < n: mode k's entry of the row p . x + q . v (complex V),
    added left to right from 0."""
    s = 0j
    for i in range(n):
        a, b, c, d = p[i], V[i][k], q[i], V[n + i][k]
        s += a * b + c * d
    return s


def chain(z, n, K, C, b, j, a, om, s, c, full=True, first=-1):
    """(x, v, acc, jerk, snap) of q'' + C q' + K q = b + e_j a sin(Omega tau + psi) at the state
    z = (q, q') of n DOF, given s, c = sin, cos(Omega tau + psi); jerk and snap None unless full
    (and then acc of the `first` DOF only, if first >= 0)."""
    x, v = z[:n], z[n:]
    rows = len(K) if full or first < 0 else first
    # _dot_real forms and adds the products in the order of a sum over k (sum(map(mul, row, x)) did)
    acc = [0.0] * rows
    for r in range(rows):
        acc[r] = b[r] - _dot_real(K[r], x) - _dot_real(C[r], v)
    if j < rows:
        acc[j] += a * s
    if not full:
        return x, v, acc, None, None
    jerk = [0.0] * rows
    for r in range(rows):
        jerk[r] = -_dot_real(K[r], v) - _dot_real(C[r], acc)
    jerk[j] += a * om * c
    snap = [0.0] * rows
    for r in range(rows):
        snap[r] = -_dot_real(K[r], acc) - _dot_real(C[r], jerk)
    snap[j] -= a * om * om * s
    return x, v, acc, jerk, snap


def take_peaks(seg, peaks, tau, ground, n, j, a, guards=None):
    """Raise `peaks` (a building's running maxima, floors = the first DOF of the segment's system
    of n DOF, the harmonic a sin on DOF j) over [0, tau] of `seg`, under ground acceleration `ground`
    (guards: the yielding storeys' StoreyGuards on the segment's motion, or None)."""
    peaks.take(ModalPiece(seg, n, j, a, tau, peaks.n, guards), tau, ground)


class ModalPiece(Piece):
    """A closed-form piece [0, tau] of a modal segment as peaks.Peaks searches it: the floors are
    the first `floors` DOF of its n-DOF system; `guards`: the storeys' StoreyGuards on the same
    motion (their drifts' bounds over their span are this piece's when it has that length), or None."""

    __slots__ = ("seg", "n", "j", "a", "tau", "floors", "guards")

    def __init__(self, seg, n, j, a, tau, floors, guards=None):
        self.seg, self.n, self.j, self.a, self.tau, self.floors = seg, n, j, a, tau, floors
        self.guards = guards

    def start(self):
        """(x, v, acc, jerk, snap) of every DOF at tau = 0."""
        seg = self.seg
        s, c = seg.motion.load(0.0)
        return chain(seg.z0, self.n, seg.K, seg.C, seg.b, self.j, self.a, seg.om, s, c)

    def first(self):
        """(x, v, acc) of every DOF at tau = 0, as start() gives them."""
        seg = self.seg
        s, c = seg.motion.load(0.0)
        return chain(seg.z0, self.n, seg.K, seg.C, seg.b, self.j, self.a, seg.om, s, c, False, self.floors)[:3]

    def bounds(self, floor_order, drift_order):
        """(per floor the bounds of |x^(floor_order)| and |x^(floor_order + 1)|, per storey the bound
        of its drift's derivative of order drift_order) over the piece."""
        motion, floors, guards = self.seg.motion, self.floors, self.guards
        if guards is not None and self.tau == guards.span:  # the same sums over the same span
            drifts = [b[drift_order] for b in guards.drift_bounds]
        else:
            weighted = motion.modes.weighted_drifts(floors)
            drifts = [b[0] for b in motion.bounds(self.tau, drift_order + 1, None, None, weighted, drift_order)]
        return motion.bounds(self.tau, floor_order + 2, None, None, motion.modes.weighted_floors(floors), floor_order), drifts

    def derivatives(self, s, floors):
        """{floor: [x^(lo), ..., x^(hi-1)]} at s of the floors asked for ({floor: (lo, hi)}, hi <= 5)."""
        return self.seg.motion.derivatives(s, floors)


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
