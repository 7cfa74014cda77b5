"""The damper on a shear building (storeys >= 1): the level model and its two segments.

Coordinates: floor displacements x_1..x_N and the particle's y, relative to the ground [m]; the
particle hangs from floor j (Params.floor is j - 1), r = y - x_j, stops at r = -+d (gap
x_j - y = +-d, as at the pendulum levels).  With m_k the floor masses, m the particle's mass,
w1 its pendulum frequency and c_p = 2 zeta_p m w1:

    M x'' + C x' + K x = -M 1 a_g + e_j (F + F0 sin(Omega t + phi) + m w1^2 r + c_p r'),
    m (y'' + a_g) = -m w1^2 r - c_p r'

(building.py gives M, K and the classical modal damping C).  While the particle rides stop s the
wire and dashpot forces are internal: (M + m e_j e_j^T) x'' + C x' + K x = -(M 1 + m e_j) a_g +
e_j (F + F0 sin), y = x_j - s d, and the stop's force on the particle is
N = m (x_j'' + a_g + w1^2 r).  An impact exchanges momentum between the particle and floor j
only (impact.py with mu = m / m_j): no other floor moves at that instant.

The Damper keeps x, v = floor j's displacement and velocity and y, u the particle's; the model
keeps the other floors' state in `others` (x_k, then v_k, for k != j), carries it along each piece
the Damper takes (follow) and saves it with the Damper's state (get_state: key "others").  Both the free (N+1)-DOF system and
the riding N-DOF one are solved in closed form by modes (modal.py).
"""
import math

from .impact import collide, impact_loss
from .level_model import LevelModel
from .modal import ModesError, _dot3, _dot_change, _dot_real, _matrix_sum, _total, solved_modes
from .modal_segments import ModalFlight, ModalStick, harmonic_work, take_peaks
from .params import ParameterError, check_finite
from .stepping import at_rest, rest_peaks
from .peaks import Peaks
from .imk_storeys import IMKHysteresis
from .storeys import KEPT_REGIMES, Hysteresis
from .yielding import StoreyGuards


def _per_mass(matrix, masses):
    return [[value / masses[i] for value in row] for i, row in enumerate(matrix)]


class BuildingModel(LevelModel):
    """Level model of a building with the particle hung from floor j (see the module doc)."""

    def __init__(self, p):
        super().__init__(p)
        b = p.building
        n, j = b.n, p.floor
        self.n, self.j = n, j
        m, ww1 = p.m, p.w1 * p.w1
        self.mu_j = m / b.masses[j]  # the impact law's mass ratio: particle to floor j
        # free flight: q = (x_1..x_N, y); the wire and the particle dashpot join floor j and y
        # (the particle's row per its own mass, so a massless particle, mu = 0, still swings)
        K = [row + [0.0] for row in b.K]
        K[j][j] += m * ww1
        K[j][n] -= m * ww1
        self.Kf = _per_mass(K, b.masses) + [[-ww1 if k == j else ww1 if k == n else 0.0 for k in range(n + 1)]]
        # riding: floor j carries the particle
        ride = list(b.masses)
        ride[j] += m
        self.ride_masses = ride
        self.Kr = _per_mass(b.K, ride)
        self.Cf, self.Cr = self._damping(b.C)
        self.damping_now = b.C  # the building's damping matrix in the storeys' current regime [N s/m]
        try:
            self.free = (solved_modes(self.Kf, self.Cf), self.Kf, self.Cf)
            self.ride = (solved_modes(self.Kr, self.Cr), self.Kr, self.Cr)
        except ModesError as err:
            raise ParameterError("storeys, floor[k].m, storey[k].k, mu, FR, zeta_s, zeta_p",
                                 (p.storeys, b.masses, b.stiffnesses, p.mu, p.FR, p.zeta_s, p.zeta_p),
                                 f"the building with its particle needs distinct modes: {err}") from None
        self.fastest = max(self.free[0].fastest, self.ride[0].fastest, p.Omega_acting)
        self.others = [0.0] * (2 * (n - 1))
        self.peaks = Peaks(b.heights)  # the running maxima (peaks.py), raised along every piece
        self._ground = 0.0  # the held ground acceleration of the segments being built [m/s2]
        # yielding storeys (storeys.py): their state, each regime's (free, ride) systems, the piece's
        # hysteretic energy (booked by follow, taken off the dashpots' share by work)
        self.storeys = None
        if p.law is not None:
            w = max(b.omegas)
            self.storeys = Hysteresis(p.law, b.heights, p.collapse_drift, w) if p.imk is None else \
                IMKHysteresis(p.law, p.imk, b.heights, p.collapse_drift, w)
        self._regimes = {}
        self._hysteretic = 0.0
        self._acc_key = self._acc = None  # the last state's floor accelerations: the outputs of a step ask twice
        self._held_kept = {}  # id(masses): (storeys' version, masses, held forces per mass)

    # ---- yielding storeys ---------------------------------------------------------------

    @property
    def collapsed(self):
        return self.storeys is not None and self.storeys.collapsed

    def _regime(self):
        """Point free, ride, Kf, Cf, Kr, Cr at the current regime's systems (built once per regime);
        a regime without modes collapses the building (its reason kept) and keeps the last ones."""
        key = self.storeys.key()
        systems = self._regimes.get(key)
        if systems is None:
            if len(self._regimes) >= KEPT_REGIMES:  # (deteriorating storeys rarely revisit a regime)
                self._regimes.clear()
            p, j, n = self.p, self.j, self.n
            b = p.building
            K = [row + [0.0] for row in self.storeys.stiffness()]
            K[j][j] += p.m * p.w1 * p.w1
            K[j][n] -= p.m * p.w1 * p.w1
            Kf = _per_mass(K, b.masses) + [self.Kf[n]]
            Kr = _per_mass(self.storeys.stiffness(), self.ride_masses)
            C = b.damping_matrix(self.storeys.stiffness())  # (b.C itself unless Rayleigh on the tangent)
            Cf, Cr = (self.Cf, self.Cr) if C is b.C else self._damping(C)
            try:
                systems = ((solved_modes(Kf, Cf), Kf, Cf), (solved_modes(Kr, Cr), Kr, Cr), Kf, Cf, Kr, Cr, C)
            except ModesError as err:
                systems = f"the regime {key} (storeys elastic 0, yielding +1 / -1) has no modes: {err}"
            self._regimes[key] = systems
        if isinstance(systems, str):  # the Damper sees `collapsed` and stops (its clock gives the time)
            self.storeys.collapse(math.nan, systems)
            return
        self.free, self.ride, self.Kf, self.Cf, self.Kr, self.Cr, self.damping_now = systems

    def _damping(self, C):
        """(Cf, Cr) per mass, free flight and riding, of the building's damping matrix C [N s/m]:
        the particle's dashpot 2 zeta_p m w1 joins floor j and the particle in flight."""
        p, j, n = self.p, self.j, self.n
        m, cwp = p.m, 2.0 * p.zeta_p * p.w1
        Cf = [row + [0.0] for row in C]
        Cf[j][j] += m * cwp
        Cf[j][n] -= m * cwp
        return (_per_mass(Cf, p.building.masses) + [[-cwp if k == j else cwp if k == n else 0.0 for k in range(n + 1)]],
                _per_mass(C, self.ride_masses))

    def _held(self, masses):
        """The storeys' held forces per mass [m/s2] on each floor in the current regime (None if the
        storeys are elastic), kept per version of the storeys' state for the free and the riding
        masses (shared: do not change it)."""
        storeys = self.storeys
        if storeys is None:
            return None
        kept = self._held_kept.get(id(masses))
        if kept is not None and kept[0] == storeys.version and kept[1] is masses:
            return kept[2]
        held = _per_floor(storeys.held(), masses)
        self._held_kept[id(masses)] = (storeys.version, masses, held)
        return held

    def storey_event(self, guard, x, v, t):
        """A storey guard's zero at time t [s] (the damper floor at x, v): yield, unload or collapse
        (returns the collapse reason, else None)."""
        xs, _ = self.floors(x, v)
        reason = self.storeys.event(guard, self.p.building.drifts(xs), t)
        if reason is None:
            self._regime()
        return reason

    def _decide(self, x, v):
        """Regimes after the damper floor's velocity jumped to v."""
        xs, vs = self.floors(x, v)
        b = self.p.building
        if self.storeys.decide(b.drifts(xs), b.drifts(vs)):
            self._regime()

    # ---- state ------------------------------------------------------------------------

    def floors(self, x, v):
        """(displacements, velocities) of all floors [m, m/s], floor 1 first."""
        return _all_floors(self.others, self.j, self.n, x, v)

    def set_floors(self, xs, vs):
        """Put the other floors' state (the damper floor's is the Damper's x, v)."""
        j = self.j
        self.others = list(xs[:j]) + list(xs[j + 1:]) + list(vs[:j]) + list(vs[j + 1:])

    def follow(self, seg, tau):
        """The other floors at tau of the piece the Damper takes, the maxima along it and its
        hysteretic energy."""
        seg.take_peaks(self.peaks, tau, self._ground)
        self.others = seg.others(tau)
        if self.storeys is not None:
            b = self.p.building
            self._hysteretic = self.storeys.piece(b.drifts(seg.start_floors), b.drifts(seg.floors_at(tau)))

    def resting(self):
        """The other floors at rest and the storeys elastic (a yielding building keeps its pieces)."""
        return self.storeys is None and at_rest(self.others)

    def rest_piece(self, tau, ground):
        """follow() over a piece at rest: the floors stay at +0.0, so only the maxima of the absolute
        velocities may rise, to the ground's (stepping.rest_peaks); True if one did."""
        return rest_peaks(self.peaks, tau, ground)

    def get_state(self):
        state = super().get_state()
        state["others"] = list(self.others)  # the other floors
        state["peaks"] = self.peaks.get_state()  # the running maxima and the ground's velocity
        if self.storeys is not None:
            state["storeys"] = self.storeys.get_state()
        return state

    def set_state(self, state):
        others = state.get("others")
        if not isinstance(others, list) or len(others) != len(self.others):
            raise ParameterError("state others", others, f"{len(self.others)} numbers: the other floors")
        for k, value in enumerate(others):
            check_finite(f"state others[{k}]", value)
        self.peaks.set_state(state.get("peaks"))
        if self.storeys is not None:
            self.storeys.set_state(state.get("storeys"))
            self._regime()
        self.others = [float(v) for v in others]

    def displacements(self, x, v, y, u):
        return x, v, y, u

    def particle_swing(self, x, v, y, u):
        return y - x, u - v

    def angles(self, x, v, y, u):
        """theta: the damper floor's displacement / L2 (L2 = g / w_1^2, the pendulum of the building's
        first frequency); alpha: the particle's wire angle r / L1."""
        p = self.p
        return x / p.L2, v / p.L2, (y - x) / p.L1, (u - v) / p.L1

    def from_angles(self, theta, theta_dot, alpha, alpha_dot):
        """The building starts at rest (set_floors for another start); the particle at alpha."""
        p = self.p
        return 0.0, 0.0, p.L1 * alpha, p.L1 * alpha_dot

    def energy(self, x, v, y, u):
        p = self.p
        b = p.building
        xs, vs = self.floors(x, v)
        r = y - x
        m, w1 = p.m, p.w1
        if self.storeys is None:
            return b.energy(xs, vs) + 0.5 * m * (u * u + w1 * w1 * r * r)
        kinetic = 0.5 * _dot3(b.masses, vs, vs)
        return kinetic + self.storeys.strain(b.drifts(xs)) + 0.5 * m * (u * u + w1 * w1 * r * r)

    # ---- segments -------------------------------------------------------------------

    def _loads(self, fc):
        """Held loads per mass of the free system: -a_g on every floor, F/m_j - a_g on floor j."""
        b = [fc[1]] * (self.n + 1)
        b[self.j] = fc[0]
        if self.storeys is not None:
            for i, c in enumerate(self._held(self.p.building.masses)):
                b[i] += c
        return b

    def flight(self, x, v, y, u, fc, psi, T, always_bound=False):
        p = self.p
        self._ground = -fc[1]
        n, j, o = self.n, self.j, self.others
        z0 = o[:j] + [x] + o[j:n - 1] + [y] + o[n - 1:n - 1 + j] + [v] + o[n - 1 + j:] + [u]
        seg = BuildingFlight(self.free, z0, self._loads(fc), p.F0 / p.M, p.Omega, psi, T, p.D, always_bound,
                             (j, n))
        return seg if self.storeys is None else WithStoreys(seg, self.storeys, T, 2)

    def stick(self, x, v, side, fc, psi, T):
        p = self.p
        self._ground = -fc[1]
        n, j, o = self.n, self.j, self.others
        z0 = o[:j] + [x] + o[j:n - 1] + o[n - 1:n - 1 + j] + [v] + o[n - 1 + j:]
        mj = p.M
        mr = self.ride_masses[j]
        b = [fc[1]] * n
        b[j] = (mj * fc[0] + p.m * fc[1]) / mr
        if self.storeys is not None:
            b = [bi + c for bi, c in zip(b, self._held(self.ride_masses))]
        a = p.F0 / mr
        # N/m = x_j'' + a_g - w1^2 side d = row j of the ride system, plus constants
        contact = ([-k for k in self.Kr[j]], [-c for c in self.Cr[j]], b[j] - p.w1 * p.w1 * side * p.d - fc[1])
        seg = ModalStick(self.ride, z0, j, side, p.d, b, a, p.Omega, psi, T, contact)
        return seg if self.storeys is None else WithStoreys(seg, self.storeys, T, 1)

    def snap(self, x, v, y, u, side):
        return x, v, x - side * self.p.d, u

    def approach(self, x, v, y, u):
        mu = self.mu_j
        return u - v, self.p.M * mu / (1.0 + mu)  # the particle on its floor (p.M: that floor's mass)

    def collide(self, x, v, y, u, side, e):
        mu = self.mu_j
        v1, u1 = collide(v, u, mu, e)
        if self.storeys is not None:
            self._decide(x, v1)
        return (x, v1, y, u1), impact_loss(self.p.M, mu, e, v, u), u - v, u1 - v1

    # ---- outputs --------------------------------------------------------------------

    def _accelerations(self, x, v, y, u, side, f, ground):
        """Relative accelerations of all floors [m/s2] (f = applied force per floor-j mass); the
        last result is kept for the same state and loads (the others compared by value)."""
        key = (x, v, y, u, side, f, ground, self.others)
        if key == self._acc_key:
            return self._acc
        self._acc_key, self._acc = key, self._compute_accelerations(x, v, y, u, side, f, ground)
        return self._acc

    def _compute_accelerations(self, x, v, y, u, side, f, ground):
        p = self.p
        n, j = self.n, self.j
        xs, vs = self.floors(x, v)
        if side:
            K, C, mj = self.Kr, self.Cr, self.ride_masses[j]
            loads = [-ground] * n
            loads[j] = (p.M * f - mj * ground) / mj
            q, dq = xs, vs
            held = self._held(self.ride_masses)
        else:
            K, C = self.Kf, self.Cf
            loads = [-ground] * (n + 1)
            loads[j] = f - ground
            q, dq = xs + [y], vs + [u]
            held = self._held(p.building.masses)
        if held is not None:
            for i, c in enumerate(held):
                loads[i] += c
        return _relative_accelerations(K, C, loads, q, dq, n)

    def acceleration(self, x, v, y, u, side, f, ground):
        return self._accelerations(x, v, y, u, side, f, ground)[self.j]

    def observables(self, x, v, y, u, side, f, ground):
        """Damper.observables of this level inline (the FMU's outputs at every step): the same
        operations as angles, displacements, contact_accel and acceleration, so the same bits."""
        p = self.p
        contact = p.m * self.contact_accel(x, v, side, f, ground) if side else 0.0
        a = self._accelerations(x, v, y, u, side, f, ground)[self.j]
        return x / p.L2, v / p.L2, (y - x) / p.L1, (u - v) / p.L1, x, y, a, contact

    def contact_accel(self, x, v, side, f, ground):
        p = self.p
        return self.acceleration(x, v, x - side * p.d, v, side, f, ground) + ground - p.w1 * p.w1 * side * p.d

    def building_outputs(self, x, v, y, u, side, f, ground):
        """(floor displacements [m], floor absolute accelerations [m/s2], storey drifts [m], base
        shear [N]) of the current state."""
        b = self.p.building
        xs, vs = self.floors(x, v)
        acc = [a + ground for a in self._accelerations(x, v, y, u, side, f, ground)]
        if self.storeys is None:
            return xs, acc, b.drifts(xs), b.base_shear(xs, vs)
        drifts = b.drifts(xs)
        n, C = self.n, self.damping_now
        shear = _total(self.storeys.restoring(drifts)) + _matrix_sum(C, vs, None, None, n)
        return xs, acc, drifts, shear

    def building_observables(self, x, v, y, u, side, f, ground):
        """building_outputs, peak_outputs and the storeys' outputs in one flat list, the floors and the
        drifts taken once: the floor displacements, absolute accelerations and storey drifts, the
        base shear, the drift ratios, the running maxima of |drift ratio|, |absolute velocity|
        and |absolute acceleration|, the springs' forces and the drifts of zero spring force, the
        hysteretic energy and collapsed (0 / 1) [m, m/s2, m, N, 1, 1, m/s, m/s2, N, m, J, 1]."""
        b = self.p.building
        xs, vs = self.floors(x, v)
        storeys, n = self.storeys, self.n
        acc = self._accelerations(x, v, y, u, side, f, ground)
        if storeys is None:
            return _elastic_outputs(xs, vs, acc, ground, b, self.peaks, n)
        out, drifts, ratios = _floor_table(xs, acc, ground, b.heights, n)
        out.append(_total(storeys.restoring(drifts)) + _matrix_sum(self.damping_now, vs, None, None, n))
        out += ratios
        pk = self.peaks
        out += pk.drift
        out += pk.velocity
        out += pk.acceleration
        out += storeys.forces(drifts)
        out += storeys.zero_force_drifts(drifts)
        out += [storeys.hysteretic, storeys.collapsed]
        return out

    def peak_outputs(self, drifts):
        """(storey drift ratios [1] of the storey drifts [m] building_outputs gave, and the running
        maxima: |drift ratio| per storey [1], |absolute velocity| and |absolute acceleration| per
        floor [m/s, m/s2])."""
        pk = self.peaks
        return [d / h for d, h in zip(drifts, self.p.building.heights)], pk.drift, pk.velocity, pk.acceleration

    def work(self, seg, tau, before, after, fc, psi, e_change):
        """(work of the held loads and the harmonic, work taken by the dashpots) over a piece."""
        p = self.p
        b = p.building
        xs0, xs1 = seg.start_floors, seg.floors_at(tau)
        ground = -fc[1]
        held = p.M * (fc[0] + ground) * (after[0] - before[0]) - ground * (
            _dot_change(b.masses, xs1, xs0) + p.m * (after[2] - before[2]))
        w = held + p.M * harmonic_work(seg, tau, p.F0 / p.M, p.Omega, psi, _floor_velocity)
        return w, w - e_change - self._hysteretic


def _all_floors(others, j, n, x, v):
    """BuildingModel.floors: the other floors' x_k, then v_k (k != j), with floor j's x, v put in."""
    xs, vs = [], []
    for k in range(n - 1):
        if k == j:
            xs.append(x)
            vs.append(v)
        xs.append(others[k])
        vs.append(others[n - 1 + k])
    if j == n - 1:
        xs.append(x)
        vs.append(v)
    return xs, vs


def _relative_accelerations(K, C, loads, q, dq, n):
    """`[loads[i] - K[i] . q - C[i] . dq for i < n]` (the dots added left to right from 0)."""
    out = []
    for i in range(n):
        load = loads[i]
        out.append(load - _dot_real(K[i], q) - _dot_real(C[i], dq))
    return out


def _floor_table(xs, acc, ground, heights, n):
    """(the floor displacements, absolute accelerations (acc + ground) and storey drifts in one list,
    the drifts, the drift ratios) of floors xs [m] with relative accelerations acc [m/s2]."""
    out = list(xs)
    for k in range(n):
        a = acc[k]
        out.append(a + ground)
    drifts, ratios = [], []
    for k in range(n):
        d = xs[k] - (xs[k - 1] if k else 0.0)
        h = heights[k]
        drifts.append(d)
        ratios.append(d / h)
    out += drifts
    return out, drifts, ratios


def _elastic_outputs(xs, vs, acc, ground, b, peaks, n):
    """BuildingModel.building_observables of elastic storeys: the floor table, the base shear
    b.base_shear(xs, vs), the drift ratios, the running maxima, the springs' forces k_k d_k,
    zeros for the drifts of zero force and 0.0, 0 for the hysteretic energy and collapsed."""
    out, drifts, ratios = _floor_table(xs, acc, ground, b.heights, n)
    out.append(_matrix_sum(b.K, xs, b.C, vs, n))
    out += ratios
    out += peaks.drift
    out += peaks.velocity
    out += peaks.acceleration
    stiffnesses = b.stiffnesses
    for k in range(n):
        s, d = stiffnesses[k], drifts[k]
        out.append(s * d)
    out += [0.0] * n
    out += [0.0, 0]
    return out


def _floor_velocity(seg, tau):
    return seg.positions(tau)[1]


class BuildingFlight(ModalFlight):
    """Free flight of the building and the particle: z = (x_1..x_N, y, v_1..v_N, u); guards as in
    ModalFlight on the gap x_j - y."""

    def take_peaks(self, peaks, tau, ground, guards=None):
        """Raise the building's running maxima (peaks.Peaks) over [0, tau] of this piece (guards: the
        yielding storeys' StoreyGuards on its motion, or None)."""
        take_peaks(self, peaks, tau, ground, self._n + 1, self._j, self.f, guards)

    __slots__ = ("_tau", "_z", "start_floors", "z0", "_j", "_n")

    def __init__(self, system, z0, b, a, om, psi, T, D, always_bound, gap):
        ModalFlight.__init__(self, system, z0, b, a, om, psi, T, D, always_bound, gap)
        self._j, self._n = gap  # the damper floor's index and the particle's (= N)
        self._tau, self._z = 0.0, z0
        self.z0 = z0  # the start state (z at tau = 0)
        self.start_floors = z0[:self._n]

    def state(self, tau):
        if tau != self._tau:
            self._tau, self._z = tau, self.motion.state(tau)
        return self._z

    def floors_at(self, tau):
        return self.state(tau)[:self._n]

    def others(self, tau):
        z = self.state(tau)
        j, n = self._j, self._n
        return z[:j] + z[j + 1:n] + z[n + 1:n + 1 + j] + z[n + 2 + j:2 * n + 1]

    def positions(self, tau):
        z = self.state(tau)
        j, n = self._j, self._n
        return z[j], z[n + 1 + j], z[n], z[2 * n + 1]

    def values(self, tau):
        j, n = self._j, self._n
        x, y, v, u = self.motion.state(tau, (j, n, n + 1 + j, 2 * n + 1))  # the gap's four rows only
        g, dg = x - y, v - u
        D = self.D
        return D - g, -dg, D + g, dg

    def derivs(self, tau, i):
        z = self.state(tau)
        j, n = self._j, self._n
        N = n + 1
        s, c = self.motion.load(tau)
        K, C, b, a, om = self.K, self.C, self.b, self.f, self.om
        x, v = z[:N], z[N:]  # the sums added left to right from 0 (_dot_real), as sum() did before 3.12
        acc = [b[r] - _dot_real(K[r], x) - _dot_real(C[r], v) for r in range(N)]
        acc[j] += a * s
        jx = a * om * c - _dot_real(K[j], v) - _dot_real(C[j], acc)
        jy = -_dot_real(K[n], v) - _dot_real(C[n], acc)
        g, g1, g2, g3 = z[j] - z[n], z[N + j] - z[N + n], acc[j] - acc[n], jx - jy
        if i == 0:
            return self.D - g, -g1, -g2, -g3
        return self.D + g, g1, g2, g3


class WithStoreys:
    """A particle segment (BuildingFlight, ModalStick) of a yielding building with the storeys'
    guards appended (yielding.StoreyGuards on the same motion): guards 0..contacts-1 are the
    particle's, the rest the storeys'.  Everything else is the particle segment's."""

    reach = math.inf
    __slots__ = ("seg", "storey", "contacts", "bounds", "noise", "growth", "clear")

    def __init__(self, seg, storeys, T, contacts):
        self.seg, self.contacts = seg, contacts
        self.storey = guards = StoreyGuards(storeys, seg.motion, T, 4)  # (its pieces start from seg)
        self.bounds = _larger(seg.bounds, guards.bounds)
        self.noise = _larger(seg.noise, guards.noise)
        self.growth = max(seg.growth, guards.growth)
        self.clear = seg.clear and guards.clear

    def __getattr__(self, name):
        return getattr(self.seg, name)

    # the particle segment's, asked for every piece: passed on by name (__getattr__ is reached only
    # after a failed lookup, which formats an AttributeError first)
    @property
    def start_floors(self):
        return self.seg.start_floors

    def floors_at(self, tau):
        return self.seg.floors_at(tau)

    def positions(self, tau):
        return self.seg.positions(tau)

    def others(self, tau):
        return self.seg.others(tau)

    def take_peaks(self, peaks, tau, ground, guards=None):
        self.seg.take_peaks(peaks, tau, ground, self.storey)

    def values(self, tau):
        return self.seg.values(tau) + tuple(self.storey.values(tau))  # (the segments' values are tuples)

    def guard(self, tau, i):
        """(g, g') of guard i alone, as values() gives them."""
        if i < self.contacts:
            values = self.seg.values(tau)
            return values[2 * i], values[2 * i + 1]
        return self.storey.guard(tau, i - self.contacts)

    def derivs(self, tau, i):
        if i < self.contacts:
            return self.seg.derivs(tau, i)
        return self.storey.derivs(tau, i - self.contacts)


def _per_floor(forces, masses):
    """forces_i / masses_i per floor [m/s2]."""
    out = []
    for i in range(len(forces)):
        f, m = forces[i], masses[i]
        out.append(f / m)
    return out


def _larger(p, q):
    """The larger of each pair p_i, q_i (max(p_i, q_i): q_i only if it is larger), as a tuple."""
    out = []
    for k in range(len(p)):
        a, b = p[k], q[k]
        out.append(b if b > a else a)
    return tuple(out)
