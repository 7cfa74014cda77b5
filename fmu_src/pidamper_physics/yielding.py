"""A shear building with bilinear storeys (storeys.py), stepped exactly from event to event.

With x the floor displacements relative to the ground [m], storey drifts delta_k = x_k - x_(k-1):

    M x'' + C x' + sum_k e_k F_k(delta_k) = f - M 1 a_g,      (e_k: +1 on floor k, -1 on floor k - 1)

C the classical modal damping of the elastic building (P-Delta included: building.ShearBuilding),
kept while storeys yield.  Between events every storey is in one regime (storeys.py: elastic,
yielding up or down), so the system is linear, M x'' + C x' + K_t x = f - M 1 a_g - sum e_k c_k,
and moves in the closed form of that regime's modes (modal.Modes / Motion: complex modes, as C is
not proportional to K_t; zero tangents move secularly, negative ones grow), each regime's modes
computed once and kept.  Its guards (events.locate finds their first zero, exactly):

- an elastic storey reaching its yield surface: Fy/k -+ (delta - delta_p) = 0 (it yields);
- a yielding storey's drift velocity reversing: s delta' = 0 (it unloads, delta_p held from then);
- a storey's drift ratio reaching the collapse limit: theta_c h -+ delta = 0 (the building
  collapses: the state, the maxima and the bookkeeping hold from that instant on).

An impulse J [N s] on floor k (a host's impact) jumps v_k by J / m_k; the regimes are decided
again at once (a yielding storey whose drift velocity reverses unloads at that instant).

Bookkeeping: `work_in` (the held loads' work, relative frame, and the impulses'), `hysteretic`
((1 - b) Fy |d delta_p| of the yielding pieces, exact) and `viscous` (what the dashpots took over
each piece: its work less its hysteretic energy and its change of E) close the balance
E(0) + work_in = E + viscous + hysteretic, E the kinetic and strain energy (P-Delta potential
included: storeys.Storeys.strain); the tests check the hysteretic and viscous parts each against
an independent integration.  Running maxima as in shear_motion (peaks.py).
Plain Python (math): this ships inside the FMU.
"""
import math

from .events import locate
from .modal import ModesError, Motion, _dot3, solved_modes
from .peaks import Peaks, Piece
from .refusals import ParameterError, check_finite, check_step
from .segments import TOLERANCE
from .shear_motion import ShearMotion, make_building
from .stepping import MAX_PIECES, same_bits, same_floats
from .imk_storeys import IMKHysteresis, check_tables, imk_law
from .storeys import KEPT_REGIMES, Hysteresis, check_damping, check_storeys


def building_motion(masses, stiffnesses, heights, zeta, yield_forces, ratios, p_delta=0, g=9.81,
                    collapse_drift=0.1, t0=0.0, damping=0, imk=None):
    """The motion of a bare shear building, its parameters checked (a ParameterError names the
    value and the rule): ShearMotion if no storey can yield, else YieldingMotion.  Floors [kg],
    storeys' stiffnesses [N/m], heights [m], yield forces [N] (0 elastic) and hardening ratios
    storey 1 first; zeta: every elastic mode's damping ratio; p_delta 0/1 with gravity g [m/s2];
    collapse_drift: the drift ratio at which a yielding building collapses; damping: the model
    (building.DAMPING_MODELS: 0 modal, 1 / 2 Rayleigh on the initial / tangent stiffness); imk: per
    storey the 21 IMKBilin values (imk.PARAMETERS) of deteriorating storeys, whose Ke must be the
    storey's stiffness (then yield_forces and ratios are not read), or None."""
    make_building(masses, stiffnesses, zeta, heights, None, damping)  # the elastic building's own checks first
    if imk is not None:
        tables = check_tables(imk, len(masses))
        for k, table in enumerate(tables):
            if table[0] != stiffnesses[k]:
                raise ParameterError(f"storey[{k + 1}].Ke", table[0], f"it must be the storey's stiffness storey[{k + 1}].k"
                                     f" = {stiffnesses[k]!r} N/m")
        yield_forces, ratios = [min(t[4], t[10]) for t in tables], [0.0] * len(tables)
    law = check_storeys(stiffnesses, yield_forces, ratios, heights, masses, p_delta, g, collapse_drift)
    if imk is not None:
        building = make_building(masses, stiffnesses, zeta, heights, law.geometric, damping)
        return YieldingMotion(building, imk_law(tables, law.geometric), collapse_drift, t0=t0, tables=tables)
    building = make_building(masses, stiffnesses, zeta, heights, law.geometric, damping)
    if not law.any_yield:
        return ShearMotion(building, t0=t0)
    check_damping(law, zeta, building.spread)
    return YieldingMotion(building, law, collapse_drift, t0=t0)


class YieldingMotion:
    """A shear building with bilinear storeys (see the module doc), at rest at t0.

    building: building.ShearBuilding (masses, elastic stiffnesses, heights, P-Delta's geometric
    stiffness and the damping from its elastic modes); law: storeys.Storeys (the same k and
    geometric stiffness, the yield forces and hardening ratios); collapse_drift [1]: the drift
    ratio at which the building counts as collapsed."""

    def __init__(self, building, law, collapse_drift, t0=0.0, tables=None):
        self.b = building
        self.n = n = building.n
        self.t = check_finite("start time", t0)
        self.x, self.v = [0.0] * n, [0.0] * n
        self._max_span = 2.0 * math.pi / max(building.omegas)
        w = max(building.omegas)
        self.storeys = Hysteresis(law, building.heights, collapse_drift, w) if tables is None else \
            IMKHysteresis(law, tables, building.heights, collapse_drift, w)
        self.fresh = False
        self.work_in = self.viscous = 0.0
        self.frozen = None  # (absolute accelerations, base shear) at the collapse instant
        self.peaks = Peaks(building.heights)
        self._systems = {}  # regime -> Modes, or the reason it has none
        self._regime = (-1, None)  # (storeys' version, the Modes of their regime)
        self._held = (-1, None, None, None)  # (storeys' version, forces, ground, loads per mass)
        self._dampings = (-1, None)  # (storeys' version, their regime's damping matrix): _damping_matrix()
        self._c = [[c / m for c in row] for row, m in zip(building.C, building.masses)]
        # the elastic building, stepped while no storey has yielded and none can reach a limit in
        # the step: its state is then this motion's (the modal one of ShearMotion)
        self.track = ShearMotion(building, t0=self.t)
        self.track.peaks = self.peaks
        self._booked = None  # (x, drifts, energy) of the state as the last piece left it (see _move)
        self._restored = None  # (the _booked it belongs to, _restoring() of that state)
        self.energy0 = self.energy()
        self.pieces = 0
        self.on_collapse = None  # optional callback(t, reason)

    # ---- floor values ------------------------------------------------------------------

    @property
    def collapsed(self):
        return self.storeys.collapsed

    @property
    def hysteretic(self):
        return self.storeys.hysteretic

    def floors(self):
        """(x, v): floor displacements and velocities relative to the ground [m, m/s]."""
        return list(self.x), list(self.v)

    def drifts(self, x=None):
        x = self.x if x is None else x
        return [x[k] - (x[k - 1] if k else 0.0) for k in range(self.n)]

    def _booking(self):
        """(x, drifts, energy) as the last piece booked them, if it left the current state; else None."""
        booked = self._booked
        return booked if booked is not None and booked[0] is self.x else None

    def _drifts_now(self):
        """drifts() of the current state, as the last piece booked them if it left this state (do
        not change the list)."""
        booked = self._booking()
        return self.drifts() if booked is None else booked[1]

    def storey_forces(self):
        """The bilinear springs' forces [N] (P-Delta and dashpots not included), storey 1 first."""
        if self.track is not None:  # elastic: the elastic building's k delta
            return [k * d for k, d in zip(self.b.stiffnesses, self.drifts())]
        return self.storeys.forces(self._drifts_now())

    def plastic_drifts(self):
        """Per storey the drift at which its spring's force is zero [m]."""
        return self.storeys.zero_force_drifts(self._drifts_now())

    def _restoring(self):
        """Per floor the storeys' and dashpots' force on it [N] (kept for the state the last piece
        left: the accelerations and the base shear both ask; do not change the list)."""
        booked, kept = self._booking(), self._restored
        if booked is not None and kept is not None and kept[0] is booked:
            return kept[1]
        C, n, v = self._damping_matrix(), self.n, self.v
        r = self.storeys.restoring(self._drifts_now())
        out = []
        for i in range(n):
            row, damping = C[i], 0.0
            for j in range(n):
                damping += row[j] * v[j]
            out.append(r[i] + damping)
        if booked is not None:
            self._restored = (booked, out)
        return out

    def observables(self, forces):
        """Every observable of the state in one flat list, in ShearMotion.observables's order
        (forces [N]: the held floor forces)."""
        x, v = self.floors()
        pk = self.peaks
        return [*x, *v, *self.absolute_accelerations(forces, x, v), *self.b.drift_ratios(x), *pk.drift, *pk.velocity,
                *pk.acceleration, *self.storey_forces(), *self.plastic_drifts(), self.hysteretic, self.collapsed,
                self.energy(), self.viscous, self.work_in, self.base_shear()]

    def absolute_accelerations(self, forces, x=None, v=None):
        """x_k'' + a_g [m/s2] of every floor under the forces [N] (held from the collapse instant)."""
        if self.frozen is not None:
            return list(self.frozen[0])
        if self.track is not None:
            return self.track.absolute_accelerations(forces, self.x, self.v)
        return [(f - r) / m for f, r, m in zip(forces, self._restoring(), self.b.masses)]

    def base_shear(self):
        """Force of the building on the ground [N]: the sum over the floors of the storeys' and
        dashpots' forces (held from the collapse instant)."""
        if self.frozen is not None:
            return self.frozen[1]
        if self.track is not None:
            return self.b.base_shear(self.x, self.v)
        total = 0.0
        for force in self._restoring():
            total += force
        return total

    def energy(self, x=None, v=None):
        """Kinetic and strain energy [J] (relative motion; P-Delta potential included)."""
        if x is None and v is None:
            booked = self._booking()
            if booked is not None:  # the state the last piece left: its energy is booked
                return booked[2]
        x = self.x if x is None else x
        v = self.v if v is None else v
        if self.track is not None:  # elastic: the elastic building's energy
            return self.b.energy(x, v)
        kin = 0.5 * _dot3(self.b.masses, v, v)
        return kin + self.storeys.strain(self.drifts(x))

    # ---- stepping -------------------------------------------------------------------------

    def advance(self, t_end, forces, ground=0.0, impulses=()):
        """Move to t_end [s] under the held floor forces [N] and ground acceleration [m/s2];
        `impulses`: (time, floor index 0..N-1, J [N s]), clamped into [t, t_end].

        While no storey has yielded the building is the elastic one, and steps as it
        (ShearMotion, `track`): at once when no storey can reach a limit in the step
        (ShearMotion.drift_reach), else after a trial by regimes found no event in it.  So a
        building whose storeys never reach their yield forces moves bit for bit as the elastic
        building, whatever its yield forces are."""
        check_step(self.t, t_end, forces, ground)
        self.pieces = 0
        kicks = [(t, k, j) for t, k, j in impulses if j != 0.0]
        if self.track is None:
            self._by_regimes(t_end, forces, ground, kicks)
        elif not self._clear(t_end, forces, ground, kicks):
            trial, events = self.get_state(), self.storeys.events
            self.track = None
            self._by_regimes(t_end, forces, ground, kicks)
            if self.storeys.events == events:  # nothing happened: the step is the elastic building's
                self.set_state(trial)
                self._elastic(t_end, forces, ground, kicks)
        else:
            self._elastic(t_end, forces, ground, kicks)

    def _by_regimes(self, t_end, forces, ground, kicks):
        for t_k, k, j in sorted((min(max(t, self.t), t_end), k, j) for t, k, j in kicks):
            self._run(t_k, forces, ground)
            self._kick(k, j)
        self._run(t_end, forces, ground)

    def _clear(self, t_end, forces, ground, kicks):
        """Whether every storey provably stays inside its yield and collapse limits over the
        step (ShearMotion.drift_reach, with the rounding of its scale)."""
        law, theta_c, heights = self.storeys.law, self.storeys.theta_c, self.b.heights
        reach, scale = self.track.drift_reach(t_end, forces, ground, kicks)
        slack = TOLERANCE * scale
        for i, bound in enumerate(reach):
            limit = min(theta_c * heights[i], law.reach[i]) if law.yields[i] else theta_c * heights[i]
            if not bound + TOLERANCE * bound + slack < limit:
                return False
        return True

    def _elastic(self, t_end, forces, ground, kicks):
        """The step as the elastic building (the track), its work and dashpot energy booked."""
        track = self.track
        e0, w0 = self.energy(), track.work_in
        self._booked = None
        track.advance(t_end, forces, ground, kicks)
        self.t = t_end
        self.x, self.v = track.floors()
        work = track.work_in - w0
        self.work_in += work
        self.viscous += work - (self.energy() - e0)

    def _run(self, t_stop, forces, ground):
        while self.t < t_stop:
            if self.collapsed:
                self.peaks.v_ground += ground * (t_stop - self.t)
                self.t = t_stop
                return
            self.pieces += 1
            if self.pieces > MAX_PIECES:  # fmi2DoStep cannot be interrupted: a call's work is capped
                raise ParameterError("step", t_stop - self.t, f"it needed more than {MAX_PIECES} pieces by "
                                     f"t = {self.t!r} s (the state is left there): take shorter communication steps")
            modes = self._modes()
            if isinstance(modes, str):
                self._collapse(modes, forces)
                continue
            span = min(t_stop - self.t, self._max_span)
            if modes.growth_rate > 0.0:  # a growing regime: its bounds grow at most e-fold over a piece
                span = min(span, 1.0 / modes.growth_rate)
            motion = Motion(modes, self.x + self.v, self._loads(forces, ground))
            guards = StoreyGuards(self.storeys, motion, span)
            event = locate(guards, span, self.fresh)
            tau = span if event is None else event[0]
            self._move(motion, tau, forces, ground, guards)
            self.t = t_stop if event is None and span == t_stop - self.t else self.t + tau
            if event is not None:
                self.fresh = True
                self._booked = None  # the storeys' state changes: so may the energy's terms
                reason = self.storeys.event(guards.guards[event[2]], self.drifts(), self.t)
                if reason is not None:
                    self._collapse(reason, forces)

    def _modes(self):
        """The Modes of the current regime (per mass), once per regime; a string if it has none."""
        version = self.storeys.version
        if self._regime[0] == version:
            return self._regime[1]
        modes = self._regime_modes()
        self._regime = (version, modes)
        return modes

    def _regime_modes(self):
        key = self.storeys.key()
        modes = self._systems.get(key)
        if modes is None:
            if len(self._systems) >= KEPT_REGIMES:  # (deteriorating storeys rarely revisit a regime)
                self._systems.clear()
            stiffness = self.storeys.stiffness()
            K = [[k / m for k in row] for row, m in zip(stiffness, self.b.masses)]
            c = self._c
            if self.b.tangent_damping():  # Rayleigh on this regime's tangent stiffness
                c = [[v / m for v in row] for row, m in zip(self._damping_matrix(), self.b.masses)]
            try:
                modes = solved_modes(K, c)
            except ModesError as err:
                modes = f"the regime {key} (storeys elastic 0, yielding +1 / -1) has no modes: {err}"
            self._systems[key] = modes
        return modes

    def _damping_matrix(self):
        """C [N s/m] of the storeys' current regime: the building's own, or under Rayleigh damping on
        the tangent stiffness a0 M + a1 K_t (kept per version of the storeys' state)."""
        if not self.b.tangent_damping():
            return self.b.C
        kept = self._dampings
        if kept[0] != self.storeys.version:
            kept = self._dampings = (self.storeys.version, self.b.damping_matrix(self.storeys.stiffness()))
        return kept[1]

    def _loads(self, forces, ground):
        """Held loads per mass [m/s2]: (F_k + the storeys' held forces) / m_k - a_g (kept while
        they and the storeys' state stay the same; do not change the list)."""
        version = self.storeys.version
        held = self._held
        if held[0] == version and same_bits(held[2], ground) and same_floats(held[1], forces):
            return held[3]
        loads = [(f + c) / m - ground for f, c, m in zip(forces, self.storeys.held(), self.b.masses)]
        self._held = (version, list(forces), ground, loads)
        return loads

    def _move(self, motion, tau, forces, ground, guards):
        """Take the state at tau of the piece (guards: its StoreyGuards); book its work,
        hysteretic and dashpot energy and raise the maxima along it."""
        n = self.n
        self.peaks.take(RegimePiece(motion, n, tau, guards), tau, ground)
        if tau <= 0.0:
            return
        booked = self._booking()
        x0 = self.x
        if booked is not None:  # the state the last piece left, unchanged since
            d0, e0 = booked[1], booked[2]
        else:
            d0, e0 = self.drifts(), self.energy()
        z = motion.state(tau)
        self.x, self.v = z[:n], z[n:]
        self._booked = None
        if not all(map(math.isfinite, z)):
            raise ParameterError("a_g, F", (ground, forces), f"the motion left the range of float arithmetic by "
                                 f"t = {self.t!r} s")
        work, masses, x1 = 0.0, self.b.masses, self.x
        for k in range(n):
            work += (forces[k] - masses[k] * ground) * (x1[k] - x0[k])
        d1 = self.drifts()
        hysteretic = self.storeys.piece(d0, d1)
        e1 = self.energy()
        self.work_in += work
        self.viscous += work - hysteretic - (e1 - e0)  # what the dashpots took
        self.fresh = False
        self._booked = (self.x, d1, e1)

    def _collapse(self, reason, forces):
        self.frozen = (self.absolute_accelerations(forces), self.base_shear())
        self.storeys.collapse(self.t, reason)
        if self.on_collapse is not None:
            self.on_collapse(self.t, reason)

    def _kick(self, k, j):
        """Impulse j [N s] on floor k now; the regimes decided again."""
        if self.collapsed:
            return
        before = self.v[k]
        self._booked = None  # the velocities change in place
        self.v[k] += j / self.b.masses[k]
        self.work_in += 0.5 * j * (before + self.v[k])
        if self.storeys.decide(self.drifts(), self.drifts(self.v)):
            self.fresh = True

    # ---- state ----------------------------------------------------------------------------

    _KEYS = ("t", "x", "v", "fresh", "work_in", "viscous", "frozen", "peaks", "storeys", "track")

    def get_state(self):
        track = self.track
        return {"t": self.t, "x": list(self.x), "v": list(self.v), "fresh": self.fresh, "work_in": self.work_in,
                "viscous": self.viscous, "frozen": None if self.frozen is None else [list(self.frozen[0]),
                                                                                     self.frozen[1]],
                "peaks": self.peaks.get_state(), "storeys": self.storeys.get_state(),
                "track": None if track is None else [list(track.q), list(track.qd)]}

    def set_state(self, state):
        if not isinstance(state, dict) or set(state) != set(self._KEYS):
            raise ParameterError("state", state if not isinstance(state, dict) else sorted(state),
                                 f"it must be the dict YieldingMotion.get_state writes (keys {sorted(self._KEYS)})")
        n = self.n
        for key in ("x", "v"):
            values = state[key]
            if not isinstance(values, list) or len(values) != n:
                raise ParameterError(f"state {key}", values, f"it must be a list of {n} numbers")
            for k, value in enumerate(values):
                check_finite(f"state {key}[{k}]", value)
        for key in ("t", "work_in", "viscous"):
            check_finite(f"state {key}", state[key])
        frozen = state["frozen"]
        if frozen is not None and not (isinstance(frozen, list) and len(frozen) == 2 and len(frozen[0]) == n):
            raise ParameterError("state frozen", frozen, f"None or [{n} accelerations, base shear]")
        self._booked = None
        self.storeys.set_state(state["storeys"])
        self.peaks.set_state(state["peaks"])
        self.t, self.work_in, self.viscous = float(state["t"]), float(state["work_in"]), float(state["viscous"])
        self.x, self.v = [float(u) for u in state["x"]], [float(u) for u in state["v"]]
        self.fresh = bool(state["fresh"])
        self.frozen = None if frozen is None else ([float(a) for a in frozen[0]], float(frozen[1]))
        self._set_track(state["track"])

    def _set_track(self, modal):
        """The elastic track from get_state's [q, q'] (None: off it); a state whose storeys have
        yielded is off it, and one whose floors are not the track's takes them (projected)."""
        n, storeys = self.n, self.storeys
        if modal is None or storeys.collapsed or not storeys.pristine():
            self.track = None
            return
        if not (isinstance(modal, list) and len(modal) == 2 and all(isinstance(c, list) and len(c) == n
                                                                     for c in modal)):
            raise ParameterError("state track", modal, f"None or [q, q'] ({n} modal coordinates each)")
        track = self.track = ShearMotion(self.b, t0=self.t)
        track.peaks = self.peaks
        track.q = [check_finite(f"state track q[{r}]", u) for r, u in enumerate(modal[0])]
        track.qd = [check_finite(f"state track qd[{r}]", u) for r, u in enumerate(modal[1])]
        if list(track.floors()) != [self.x, self.v]:
            track.set_floors(self.x, self.v)


class StoreyGuards:
    """The storeys' guards (storeys.Hysteresis.guards) over one piece, in events.py's protocol:
    each linear in its storey's drift delta, g = const + coef delta^(order), in metres.

    Only the guards that may reach zero over [0, T] are kept (`guards`): one whose least value
    there (Taylor from the start) stays above its own rounding level cannot fire, and is left out
    so that its scale (a yield drift of kilometres) sets neither the rounding level nor the steps
    of the others.  A storey that never comes near its yield surface is then located, and moves,
    exactly as an elastic one."""

    reach = math.inf
    __slots__ = ("motion", "guards", "bounds", "noise", "growth", "clear", "n", "floors", "span", "drift_bounds",
                 "first", "last", "orders")

    def __init__(self, storeys, motion, T, orders=5):
        self._start(storeys.guards(), motion, T, storeys.n, orders)

    def _start(self, guards, motion, T, n, orders):
        """__init__'s work, typed: `guards` the storeys' (storeys.Hysteresis.guards), n their count."""
        self.motion, self.n = motion, n
        modes = motion.modes
        #: per floor [x, x', ..., x^(orders - 1)] at the start (RegimePiece's maxima start from them
        #: too, to the 4th; the guards need them to the 3rd)
        self.floors = motion.component_derivatives(0.0, 0, n, orders)
        #: per storey the bounds of its drift and its derivatives over [0, span]
        self.span, self.drift_bounds = T, motion.bounds(T, 6, None, None, modes.weighted_drifts(n))
        self._keep(guards, self.drift_bounds, _differences(self.floors, 0, orders), T, modes.fastest)

    def _keep(self, guards, bd, start, T, growth):
        """Keep the guards that may reach zero on [0, T] (bd: per storey the bounds of its drift's
        derivatives, start: its derivatives at 0) and set the protocol's bounds, noise, clear."""
        b2 = b3 = b4 = n0 = n1 = n2 = n3 = 0.0
        tol = TOLERANCE
        kept = []
        first, last, orders = len(start), 0, 2
        for guard in guards:
            i, order, coef, offset = guard[0], guard[1], guard[2], guard[3]
            c, di, bi = abs(coef), start[i], bd[i]
            d0, d1, d2 = di[order], di[order + 1], di[order + 2]  # the drift's derivatives at 0 ...
            e1, e2, e3, e4 = bi[order + 1], bi[order + 2], bi[order + 3], bi[order + 4]  # ... and their bounds
            own = tol * (abs(offset) + c * (abs(d0) + T * e1))  # its rounding level
            least = offset + coef * d0 - T * min(c * e1, abs(coef * d1) + T * c * e2)
            if least > own * (1.0 + growth * T):
                continue  # cannot reach zero on [0, T]
            kept.append(guard)
            first = min(first, i)
            last = max(last, i + 1)
            orders = max(orders, order + 2)
            b2 = max(b2, c * e2)
            b3 = max(b3, c * e3)
            b4 = max(b4, c * e4)
            n0 = max(n0, own)
            n1 = max(n1, c * (e1 + abs(d1)))
            n2 = max(n2, c * (e2 + abs(d2)))
            n3 = max(n3, c * e3)
        self.guards = kept
        # the storeys the kept guards watch lie in [first, last), to the derivative `orders` - 1 (a
        # guard's order and the next): values() computes only those
        if not kept:
            first = last = 0
        self.first, self.last, self.orders = first, last, orders
        self.bounds = (b2, b3, b4)
        self.noise = (n0, tol * n1, tol * n2, tol * n3)
        self.growth = growth if kept else 0.0
        self.clear = not kept

    def _drifts(self, tau, orders, first=0, last=None):
        """Per storey k (first <= k < last, default all) [delta, delta', ..., delta^(orders - 1)] at tau."""
        last = self.n if last is None else last
        lo = first - 1 if first else 0
        floors = self.floors
        if tau == 0.0 and max(orders, 2) <= len(floors[0]):  # the start's, as computed (the same sums)
            return _differences(floors[lo:last], first, orders)
        return _differences(self.motion.component_derivatives(tau, lo, last, max(orders, 2)), first, orders)

    def values(self, tau):
        if not self.guards:
            return []
        first = self.first
        d = self._drifts(tau, self.orders, first, self.last)
        out = []
        for guard in self.guards:
            i, order, coef, offset = guard[0], guard[1], guard[2], guard[3]
            di = d[i - first]
            out.append(offset + coef * di[order])
            out.append(coef * di[order + 1])
        return out

    def guard(self, tau, index):
        """(g, g') of guard `index` alone, as values() gives them."""
        guard = self.guards[index]
        i, order, coef, offset = guard[0], guard[1], guard[2], guard[3]
        di = self._drifts(tau, order + 2, i, i + 1)[0]
        return offset + coef * di[order], coef * di[order + 1]

    def derivs(self, tau, index):
        guard = self.guards[index]
        i, order, coef, offset = guard[0], guard[1], guard[2], guard[3]
        di = self._drifts(tau, 5, i, i + 1)[0]
        return offset + coef * di[order], coef * di[order + 1], coef * di[order + 2], coef * di[order + 3]


def _differences(d, first, orders):
    """Per storey [delta, ..., delta^(orders - 1)] from the floors' derivatives d (d[0] the floor
    below the first storey, or floor 1 when first is 0: its storey's drift is its displacement)."""
    out = [d[0][:orders]] if not first else []
    for k in range(1, len(d)):
        a, b = d[k], d[k - 1]
        out.append([a[j] - b[j] for j in range(orders)])
    return out


class RegimePiece(Piece):
    """A closed-form piece [0, tau] of a YieldingMotion as peaks.Peaks searches it; `guards`: the
    StoreyGuards of the motion (its floors' start values, its drifts' bounds over its span)."""

    __slots__ = ("motion", "n", "tau", "guards")

    def __init__(self, motion, n, tau, guards):
        self.motion, self.n, self.tau, self.guards = motion, n, tau, guards

    def start(self):
        d, n = self.guards.floors, self.n
        return ([d[k][0] for k in range(n)], [d[k][1] for k in range(n)], [d[k][2] for k in range(n)],
                [d[k][3] for k in range(n)], [d[k][4] for k in range(n)])

    def first(self):
        """(x, v, acc) of the floors at the piece's start, as start() gives them."""
        d, n = self.guards.floors, self.n
        return [d[k][0] for k in range(n)], [d[k][1] for k in range(n)], [d[k][2] for k in range(n)]

    def bounds(self, floor_order, drift_order):
        """(per floor the bounds of |x^(floor_order)| and |x^(floor_order + 1)|, per storey the bound
        of its drift's derivative of order drift_order) over the piece."""
        motion, n, tau, guards = self.motion, self.n, self.tau, self.guards
        if tau == guards.span:  # the guards' bounds are over this piece (each order's alone)
            drifts = [b[drift_order] for b in guards.drift_bounds]
        else:
            drifts = [b[0] for b in motion.bounds(tau, drift_order + 1, None, None, motion.modes.weighted_drifts(n),
                                                  drift_order)]
        return motion.bounds(tau, floor_order + 2, None, None, motion.modes.weighted_floors(n), floor_order), drifts

    def derivatives(self, s, floors):
        return self.motion.derivatives(s, floors)
