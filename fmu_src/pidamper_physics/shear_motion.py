"""Exact motion of a shear building (building.ShearBuilding) under held loads and floor impulses.

With x the floor displacements relative to the ground [m] and classical modal damping,

    M x'' + C x' + K x = f - M 1 a_g,        f = (F_1, ..., F_N) [N], a_g [m/s2] held over a step,

decouples into the modes x = Phi q (Phi mass-normalised: Phi^T M Phi = I, Phi^T K Phi = diag(w_r^2),
Phi^T C Phi = diag(2 zeta w_r)):

    q_r'' + 2 zeta w_r q_r' + w_r^2 q_r = p_r,      p_r = sum_k Phi[k][r] (F_k - m_k a_g),

each a damped oscillator under a constant load, solved in closed form (`oscillator.DampedOscillator`).  An impulse J
[N s] on floor k at an instant changes floor k's velocity by J / m_k and no displacement; in
modal terms q_r' jumps by `Phi[k][r] J`.  A step with impulses at instants inside it is solved
piece by piece between them, so it is exact for held loads and instantaneous impulses.

The state is kept in modal coordinates (q, q'), so stepping never re-projects; floor values are
derived from it.  A building at rest (q, q' +0.0) under no load or impulse stays there: such a
step moves only the clock and the ground's velocity (`still` then says that no output changed).
The running maxima of the drift ratios and of the floors' absolute velocity and
acceleration (peaks.Peaks) are raised along every piece, the impulses' one-sided values included.
Plain Python (math): this ships inside the FMU.
"""
import math

from .building import ShearBuilding
from .modal import _matrix_sum
from .oscillator import DampedOscillator
from .params import ParameterError, check_building, check_finite
from .refusals import check_step
from .peaks import Peaks, Piece
from .stepping import at_rest, rest_peaks, unsigned

#: the building of floor masses and storey stiffnesses, checked (params.check_building)
make_building = check_building


class ShearMotion:
    """A shear building stepped exactly under held loads and impulses (see the module doc).

    building: a ShearBuilding (masses, stiffnesses, zeta).  State: floor displacements and
    velocities relative to the ground, zero at the start unless x0, v0 are given."""

    def __init__(self, building, x0=None, v0=None, t0=0.0):
        if not isinstance(building, ShearBuilding):
            raise TypeError("building must be a ShearBuilding")
        self.b = building
        n = building.n
        self.n = n
        x0 = [0.0] * n if x0 is None else [check_finite(f"floor[{k + 1}].x_0", x) for k, x in enumerate(x0)]
        v0 = [0.0] * n if v0 is None else [check_finite(f"floor[{k + 1}].v_0", v) for k, v in enumerate(v0)]
        if len(x0) != n or len(v0) != n:
            raise ParameterError("x0, v0", (x0, v0), f"they need {n} entries, one per floor")
        self.t = check_finite("start time", t0)
        self.modes = [DampedOscillator(w, z) for w, z in zip(building.omegas, building.zetas)]
        self.powers = [[mode.w ** j for j in range(6)] for mode in self.modes]  # w^j of each mode (bounds)
        self.set_floors(x0, v0)
        self.peaks = Peaks(building.heights)
        self.still = False  # the last step found the building at rest and changed no output
        self.work_in = 0.0  # work of the held loads (relative frame) and the impulses [J]; the
        # dashpots took E(0) + work_in - E (nothing else dissipates)
        self.energy0 = self.energy()

    def set_floors(self, x, v):
        """Set the state to floor displacements x [m] and velocities v [m/s] (relative to the
        ground): the modal projections q = Phi^T M x, q' = Phi^T M x'."""
        phi, m, n = self.b.shapes, self.b.masses, self.n
        self.q = project(phi, m, x, n)
        self.qd = project(phi, m, v, n)

    # ---- floor values ------------------------------------------------------------------

    def floors(self):
        """(x, v): floor displacements and velocities relative to the ground [m, m/s]."""
        phi, n = self.b.shapes, self.n
        return combine(phi, self.q, n), combine(phi, self.qd, n)

    def absolute_accelerations(self, forces, x=None, v=None):
        """x_k'' + a_g = (M^-1 (F - C x' - K x))_k [m/s2] of every floor under the forces F [N]
        (the ground acceleration cancels: it moves the frame, not the floors' absolute motion)."""
        if x is None:
            x, v = self.floors()
        b = self.b
        return accelerations(forces, b.K, b.C, b.masses, x, v, self.n)

    def energy(self):
        """Kinetic plus strain energy of the floors [J] (relative motion)."""
        return self.b.energy(*self.floors())

    def observables(self, forces):
        """Every observable of the state in one flat list (YieldingMotion.observables's order):
        per floor or storey, floor 1 first, x [m], v [m/s], the absolute accelerations under the
        floor forces `forces` [m/s2], the drift ratios [1], the running maxima of |drift ratio|,
        |absolute velocity| and |absolute acceleration|, the storey springs' forces [N] and their
        plastic drifts [m] (0.0); then the hysteretic energy (0.0), collapsed (0), the energy, the
        dashpots' energy, the work in [J] and the base shear [N]."""
        return elastic_observables(self.b, self.q, self.qd, forces, self.peaks, self.energy0, self.work_in, self.n)

    # ---- stepping -------------------------------------------------------------------------

    def advance(self, t_end, forces, ground=0.0, impulses=()):
        """Move to t_end [s] under the held floor forces `forces` [N] (N entries) and ground
        acceleration `ground` [m/s2]; `impulses`: (time, floor index 0..N-1, J [N s]) applied at
        those times (clamped into [t, t_end])."""
        b, n = self.b, self.n
        check_step(self.t, t_end, forces, ground)
        kicks = _kicks(impulses, self.t, t_end) if impulses else ()
        if not kicks and self._resting(forces, ground):
            # from q = q' = +0.0 under zero loads each mode's closed form gives +0.0 again
            # (oscillator.DampedOscillator.at: +0.0 plus zeros) and the loads' work adds a zero
            self.still = not rest_peaks(self.peaks, max(t_end - self.t, 0.0), ground)
            self.t = t_end
            return
        self.still = False
        phi, m = b.shapes, b.masses
        loads = modal_loads(phi, m, forces, ground, n)
        t = self.t
        q0 = list(self.q)
        for t_k, k, j in kicks:
            self._free(t_k - t, loads, ground)
            t = t_k
            before = combine(phi, self.qd, n)[k]  # floor k's velocity
            for r in range(n):
                self.qd[r] += phi[k][r] * j
            self.work_in += 0.5 * j * (before + before + j / m[k])
        self._free(t_end - t, loads, ground)
        self.t = t_end
        # the held loads' work: sum_k f_k dx_k = sum_r (Phi^T f)_r dq_r
        self.work_in += load_work(loads, q0, self.q, n)

    def _resting(self, forces, ground):
        """No load, the modes at +0.0 (stepping.at_rest) and the work not -0.0 (stepping.unsigned)."""
        if ground != 0.0:
            return False
        for f in forces:
            if f != 0.0:
                return False
        return at_rest(self.q) and at_rest(self.qd) and unsigned(self.work_in)

    def drift_reach(self, t_end, forces, ground=0.0, impulses=()):
        """Per storey a bound of |drift| [m] over the step that advance(t_end, forces, ground,
        impulses) would take, and the bound of |x| that rounds it (its scale).

        About the held load's equilibrium q_e = p / w^2 each mode swings as exp(-s tau)
        (a cos + b sin), so |q - q_e| <= A = hypot(a, b) and |q'| <= A w for all tau >= 0; an
        impulse J on floor k raises A by at most |Phi_kr J| / w_d.  A drift is then bounded
        by its equilibrium plus its modes' swings, or by its start plus the step times its rate."""
        b, n = self.b, self.n
        phi, m = b.shapes, b.masses
        T = t_end - self.t
        centre, swing = [], []
        for r, mode in enumerate(self.modes):
            p = sum(phi[k][r] * (forces[k] - m[k] * ground) for k in range(n))
            a = self.q[r] - p / mode.ww
            amp = math.hypot(a, (self.qd[r] + mode.s * a) / mode.wd)
            for _, k, j in impulses:
                amp += abs(phi[k][r] * j) / mode.wd
            centre.append(p / mode.ww)
            swing.append(amp)
        x0, _ = self.floors()
        out, scale = [], 0.0
        for k in range(n):
            below = phi[k - 1] if k else None
            shape = [phi[k][r] - (below[r] if k else 0.0) for r in range(n)]
            middle = abs(sum(s * c for s, c in zip(shape, centre)))
            spread = sum(abs(s) * a for s, a in zip(shape, swing))
            rate = sum(abs(s) * a * mode.w for s, a, mode in zip(shape, swing, self.modes))
            start = abs(x0[k] - (x0[k - 1] if k else 0.0))
            out.append(min(middle + spread, start + T * rate))
            scale = max(scale, sum(abs(phi[k][r]) * (abs(centre[r]) + swing[r]) for r in range(n)))
        return out, scale

    def _free(self, tau, loads, ground):
        """Move the modes over a piece of tau [s] under the modal loads, raising the running maxima
        along it."""
        q, qd = self.q, self.qd
        for r, mode in enumerate(self.modes):
            mode.start(q[r], qd[r], loads[r])
        tau = max(tau, 0.0)
        self.peaks.take(ShearPiece(self, tau), tau, ground)
        if tau == 0.0:
            return
        for r, mode in enumerate(self.modes):
            q[r], qd[r] = mode.at(tau)

    # ---- state ----------------------------------------------------------------------------

    def get_state(self):
        return {"t": self.t, "q": list(self.q), "qd": list(self.qd), "peaks": self.peaks.get_state(),
                "work_in": self.work_in}

    def set_state(self, state):
        if not isinstance(state, dict) or set(state) != {"t", "q", "qd", "peaks", "work_in"}:
            raise ParameterError("state", state if not isinstance(state, dict) else sorted(state),
                                 "it must be the dict ShearMotion.get_state writes (keys t, q, qd, peaks, work_in)")
        check_finite("state t", state["t"])
        work_in = check_finite("state work_in", state["work_in"])
        for key in ("q", "qd"):
            values = state[key]
            if not isinstance(values, list) or len(values) != self.n:
                raise ParameterError(f"state {key}", values, f"it must be a list of {self.n} numbers")
            for k, value in enumerate(values):
                check_finite(f"state {key}[{k}]", value)
        self.peaks.set_state(state["peaks"])
        self.work_in = work_in
        self.t = float(state["t"])
        self.q = [float(v) for v in state["q"]]
        self.qd = [float(v) for v in state["qd"]]


def elastic_observables(b, q, qd, forces, peaks, energy0, work_in, n):
    """ShearMotion.observables: the floors from the modes once, then every output from them (the
    same operations, in the same order, as floors(), absolute_accelerations(), the building's
    drift_ratios(), energy() and base_shear())."""
    phi = b.shapes
    x = combine(phi, q, n)
    v = combine(phi, qd, n)
    out = x + v + accelerations(forces, b.K, b.C, b.masses, x, v, n)
    heights, stiffnesses, net, masses = b.heights, b.stiffnesses, b.net, b.masses
    springs = []
    kinetic = strain = 0.0
    for k in range(n):
        xk, vk, mk, nk, hk, sk = x[k], v[k], masses[k], net[k], heights[k], stiffnesses[k]
        d = xk - (x[k - 1] if k else 0.0)
        out.append(d / hk)
        springs.append(sk * d)
        kinetic += mk * vk * vk
        strain += nk * d * d
    energy = 0.5 * kinetic + 0.5 * strain
    out += peaks.drift
    out += peaks.velocity
    out += peaks.acceleration
    out += springs
    out += [0.0] * n
    out += [0.0, 0, energy, energy0 + work_in - energy, work_in, _matrix_sum(b.K, x, b.C, v, n)]
    return out


def _kicks(impulses, t0, t_end):
    """The impulses (t, floor index, J) with J != 0, their times clamped into [t0, t_end], in time order."""
    return sorted((min(max(t, t0), t_end), k, j) for t, k, j in impulses if j != 0.0)


# ---- the sums of the hot loops (typed in shear_motion.pxd): each sum from 0.0 left to right, as
# CPython's sum() adds its floats, so both builds give the same bits ------------------------------

def combine(phi, q, n):
    """`[sum_r phi[k][r] q[r] for each floor k]`: floor values from modal ones."""
    out = []
    for k in range(n):
        row = phi[k]
        total = 0.0
        for r in range(n):
            a = row[r]
            b = q[r]
            total += a * b
        out.append(total)
    return out


def project(phi, m, x, n):
    """`[sum_k phi[k][r] m[k] x[k] for each mode r]`: modal coordinates of floor values x."""
    out = []
    for r in range(n):
        total = 0.0
        for k in range(n):
            row = phi[k]
            p, mk, xk = row[r], m[k], x[k]
            total += p * mk * xk
        out.append(total)
    return out


def accelerations(forces, K, C, m, x, v, n):
    """`[(F_k - sum_j (C[k][j] v_j + K[k][j] x_j)) / m_k for each floor k]`."""
    out = []
    for k in range(n):
        Ck, Kk = C[k], K[k]
        total = 0.0
        for j in range(n):
            c, vj, kk, xj = Ck[j], v[j], Kk[j], x[j]
            total += c * vj + kk * xj
        f, mk = forces[k], m[k]
        out.append((f - total) / mk)
    return out


def load_work(loads, q0, q1, n):
    """`sum_r loads[r] (q1[r] - q0[r])`: the held modal loads' work over a step."""
    total = 0.0
    for r in range(n):
        p, a, b = loads[r], q0[r], q1[r]
        total += p * (b - a)
    return total


def modal_loads(phi, m, forces, ground, n):
    """`[sum_k phi[k][r] (F_k - m_k a_g) for each mode r]`: the modal loads."""
    out = []
    for r in range(n):
        total = 0.0
        for k in range(n):
            p, f, mk = phi[k][r], forces[k], m[k]
            total += p * (f - mk * ground)
        out.append(total)
    return out


def piece_bounds(phi, amps, powers, n, floor_order, drift_order):
    """ShearPiece.bounds(floor_order, drift_order) (4, 3 or 2, 1) from the modes' amplitudes
    and powers w^j (j = 0..5)."""
    floors = []
    drifts = []
    below = None
    for k in range(n):
        row = phi[k]
        bounds = []
        for j in range(floor_order, floor_order + 2):
            total = 0.0
            for r in range(n):
                w_r = powers[r]
                p, a, w = row[r], amps[r], w_r[j]
                total += abs(p) * a * w
            bounds.append(total)
        floors.append(bounds)
        total = 0.0
        for r in range(n):
            w_r = powers[r]
            p, a, w = row[r] - (below[r] if k else 0.0), amps[r], w_r[drift_order]
            total += abs(p) * a * w
        drifts.append(total)
        below = row
    return floors, drifts


def floor_derivatives(row, q, lo, hi):
    """`[sum_r row[r] q[r][j] for j in lo..hi-1]`: a floor's derivatives from the modes' (q: per
    mode its derivatives)."""
    out = []
    for j in range(lo, hi):
        total = 0.0
        for r in range(len(q)):
            p, d = row[r], q[r][j]
            total += p * d
        out.append(total)
    return out


class ShearPiece(Piece):
    """A piece [0, tau] of a ShearMotion (its modes started) as peaks.Peaks searches it: each mode
    is a damped oscillator under a held load, q'' = p - 2 zeta w q' - w^2 q, so its derivatives
    follow from (q, q') by that recursion."""

    __slots__ = ("motion", "tau")

    def __init__(self, motion, tau):
        self.motion, self.tau = motion, tau

    def _modal(self, s, orders):
        out = []
        for mode in self.motion.modes:
            q, q1 = mode.at(s)
            levels = [q, q1]
            c, k = 2.0 * mode.s, mode.ww
            levels.append(mode.p - c * q1 - k * q)
            for _ in range(3, orders):
                levels.append(-c * levels[-1] - k * levels[-2])
            out.append(levels)
        return out

    def start(self):
        n = self.motion.n
        d = self.derivatives(0.0, {k: (0, 5) for k in range(n)})
        out = []
        for j in range(5):
            out.append([d[k][j] for k in range(n)])
        return tuple(out)

    def first(self):
        """(x, v, acc) of the floors at the piece's start, as start() gives them."""
        m = self.motion
        q0, q1, q2 = [], [], []
        for mode in m.modes:  # _modal(0.0, 3), by order
            q, qd = mode.at(0.0)
            c, k = 2.0 * mode.s, mode.ww
            q0.append(q)
            q1.append(qd)
            q2.append(mode.p - c * qd - k * q)
        phi, n = m.b.shapes, m.n
        return combine(phi, q0, n), combine(phi, q1, n), combine(phi, q2, n)

    def bounds(self, floor_order, drift_order):
        """(per floor the bounds of |x^(floor_order)| and |x^(floor_order + 1)|, per storey the bound
        of its drift's derivative of order drift_order) over the piece."""
        m = self.motion
        phi, n, modes = m.b.shapes, m.n, m.modes
        # each mode's free part is exp(-s tau) (A cos + B sin): |d^j| <= sqrt(A^2 + B^2) w^j
        amps = []
        for mode in modes:
            amps.append(math.hypot(mode.a, mode.b))
        return piece_bounds(phi, amps, m.powers, n, floor_order, drift_order)

    def derivatives(self, s, floors):
        """{floor: [x^(lo), ..., x^(hi-1)]} at s of the floors asked for ({floor: (lo, hi)}, hi <= 5)."""
        phi = self.motion.b.shapes
        orders = 0
        for span in floors.values():
            orders = max(orders, span[1])
        q = self._modal(s, orders)
        out = {}
        for k, span in floors.items():
            out[k] = floor_derivatives(phi[k], q, span[0], span[1])
        return out
