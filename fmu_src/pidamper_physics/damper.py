"""The pendulum impact damper stepped from event to event.

Coordinates are linear: x = L2 theta (primary), y = L1 alpha (particle), v, u
their velocities [m, m/s].  Between events both bodies follow closed-form
linear motion (segments.py); events are located exactly (events.py) by the
event loop every model shares (stepping.py), and handled by these rules:

- impact (transversal contact inside the gap): Newton's law (impact.py);
  displacement form: if the rebound would rise less than `CHATTER_HEIGHT`
  position-rounding units while the pair is pressed into the stop, the rest of
  the chatter sequence is collapsed into one plastic impact and the particle
  rides the stop (stick);
  angle form: if after the law the pair still closes in angle terms, the bodies
  pass through the stop (documented rule, physics notes section 6) until they
  re-enter the gap;
- touch (contact at an approach speed below float64 resolution, pressed inward):
  stick (displacement form) or pass-through (angle form); a touch that leaves
  again is no event at all;
- release: the contact force of a riding particle reaches zero;
- re-entry (angle form): the overlap ends.

Bookkeeping: `impacts` counts every application of the impact law (chatter
impacts and the collapse of a chatter tail included); `dissipated` sums the
losses of every impact and collapse; `work_in` adds the energy change over each
smooth segment, which equals the integral of F v dt over it, because no
force but the applied ones does work between events.  Hence
E(0) + work_in - E(t) = dissipated up to rounding.

Materials (Params.materials, impact.Contact): each impact's e may come from its approach speed and
reduced mass (LevelModel.approach), and its peak force, pressure and duration are booked in
`contacts` (impact.Tally); the constant-e motion is the same with or without them.
"""
import math

from .levels import model_for
from .params import DISPLACEMENT, Params, ParameterError, check_finite, check_restitution
from .segments import GAP_RESOLUTION, TOLERANCE
from .impact import Tally, tally
from .stepping import CHATTER_HEIGHT, FREE, MAX_PIECES, OUTSIDE, STICK, EventDriven, at_rest, unsigned

__all__ = ["Damper", "check_state", "FREE", "STICK", "OUTSIDE", "CHATTER_HEIGHT", "MAX_PIECES", "STATE_KEYS"]

STATE_KEYS = ("t", "t_lo", "x", "v", "y", "u", "mode", "side", "fresh", "impacts", "dissipated",
              "work_in", "viscous", "energy")
#: keys a state of an older build may lack, and their values then
_OPTIONAL = {"t_lo": 0.0}


_STATE_CHOICES = {"mode": (FREE, STICK, OUTSIDE), "side": (-1, 0, 1), "fresh": (False, True)}


def check_state(state):
    """Refuse a state dict that Damper.get_state did not write: missing keys, wrong types,
    non-finite numbers, a negative impact count (t_lo may be absent: states of older builds)."""
    if not isinstance(state, dict):
        raise ParameterError("state", type(state).__name__, "it must be the dict Damper.get_state writes")
    for key in STATE_KEYS + ("step_hint",):
        if key not in state:
            if key in _OPTIONAL:
                continue
            raise ParameterError(f"state {key}", None, "the key is missing: a state this model did not write")
        value = state[key]
        if key in _STATE_CHOICES:
            if type(value) not in (int, bool) or value not in _STATE_CHOICES[key]:
                raise ParameterError(f"state {key}", value, f"it must be one of {_STATE_CHOICES[key]}")
        elif key == "impacts":
            if type(value) is not int or value < 0:
                raise ParameterError(f"state {key}", value, "it must be an integer >= 0")
        else:
            check_finite(f"state {key}", value)


class _Damper(EventDriven):
    """Damper's stepping half: advance() and the methods each piece calls (in the compiled build a
    typed class, damper.pxd, whose state the loop reads from C fields; Damper, a Python subclass,
    adds the rest and stays open to patching)."""

    def advance(self, t_end, force=0.0, ground=0.0, observe=None):
        """Move to time t_end [s] with the external force `force` [N] on the primary and the
        ground acceleration `ground` [m/s2] of a base excitation (it acts on both bodies; x and y
        are then measured from the moving ground) held constant.  observe(seg, t0, t1), if
        given, sees each smooth piece before the state leaves it: the segment `seg` started at
        t0 and holds up to t1 (events, if any, at t1)."""
        total = force + t_end + ground
        if total - total != 0.0:  # some value is not finite, or their sum overflowed
            check_finite("F", force)
            check_finite("a_g", ground)
            check_finite("t_end", t_end)
        if self.halted:  # a collapsed building holds its state; the clock goes on
            self.t, self.t_lo = max(t_end, self.t), 0.0
            self.still = False
            return
        self._run(t_end, (force / self.p.M - ground, -ground), observe)  # loads per mass: primary, particle
        if not self._in_range():  # a value overflowed: refuse rather than answer inf or nan
            self._overflowed(force, ground)

    def _in_range(self):
        """False when a value of the state (or the books) is not finite, or their sum overflows."""
        x, v, y, u, e, w = self.x, self.v, self.y, self.u, self.energy, self.work_in
        check = x + v + y + u + e + w
        return check - check == 0.0

    def observables(self, force=0.0, ground=0.0):
        """(theta, theta_dot, alpha, alpha_dot, x, y, a, contact_force) in one call [rad, rad/s, m,
        m/s2, N]: the values of angles(), displacements(), acceleration() and contact_force()."""
        p = self.p
        f = self._applied(force)
        side = self.side if self.mode == STICK else 0
        inline = self._observables
        if inline is not None:
            return inline(self.x, self.v, self.y, self.u, side, f, ground)
        x, v, y, u, model = self.x, self.v, self.y, self.u, self.model
        theta, theta_dot, alpha, alpha_dot = model.angles(x, v, y, u)
        px, _, py, _ = model.displacements(x, v, y, u)
        contact = p.m * model.contact_accel(x, v, side, f, ground) if side else 0.0
        return theta, theta_dot, alpha, alpha_dot, px, py, model.acceleration(x, v, y, u, side, f, ground), contact

    def _resting(self, fc):
        """At rest: no load (fc, the harmonic), the particle free, every body's position and velocity
        and the energy +0.0, and a level that rests (a building of elastic storeys whose other
        floors are at rest too).  A piece from there would be +0.0 again (stepping.at_rest), add
        zeros to the work and the dashpots' energy, and raise no maximum but by the ground's velocity."""
        if fc[0] != 0.0 or fc[1] != 0.0 or self.p.F0 != 0.0 or self.mode != FREE:
            return False
        resting = self.model.resting
        return (resting is not None and at_rest((self.x, self.v, self.y, self.u, self.energy))
                and unsigned(self.work_in) and unsigned(self.viscous) and resting())

    def _applied(self, force):
        """Applied force per primary mass [m/s2]: the held `force` [N] and the built-in harmonic."""
        p = self.p
        return force / p.M + p.F0 / p.M * math.sin(self._phase()) if p.F0 else force / p.M

    def _segment(self, fc, horizon):
        """The segment from the current state and mode; fc = (loads per mass on primary, particle)."""
        psi = self._phase()
        model = self.model
        if self.mode == STICK:
            return model.stick(self.x, self.v, self.side, fc, psi, horizon)
        if self.mode == OUTSIDE:
            return model.outside(self.x, self.v, self.y, self.u, fc, psi, horizon, self.side)
        return model.flight(self.x, self.v, self.y, self.u, fc, psi, horizon)

    def _move(self, seg, tau, t_end, fc, observe):
        """Take the state at tau of the segment, tick the clock by tau (t_end: the piece ends
        there) and book the work of the loads and the dashpots (a level without dashpots,
        work = None, books the energy change as the work).

        The clock is t + t_lo: t is t + tau rounded (or t_end) and t_lo keeps the rounding
        error (two-sum), so a forcing phase tied to the clock does not drift over long runs,
        and a tau below one ulp of t still moves the state."""
        t = self.t
        t_new, lo = self._tick(tau, t_end)
        if observe is not None:
            observe(seg, t, t_new)
        book = self.model.work
        before = (self.x, self.v, self.y, self.u) if book is not None else None
        self.x, self.v, self.y, self.u = after = seg.positions(tau)
        if self._follow is not None:
            self._follow(seg, tau)
        if tau > 0.0:
            self.fresh = False
        e_new = self._energy()
        if book is None:
            self.work_in += e_new - self.energy
        else:
            work, viscous = book(seg, tau, before, after, fc, self._phase(), e_new - self.energy)
            self.work_in += work
            self.viscous += viscous
        self.energy = e_new
        self.t, self.t_lo = t_new, lo

    def _coast(self, state, tau, t_end):
        """_move for a free flight the level computed without a segment (no dashpots to book)."""
        t_new, lo = self._tick(tau, t_end)
        self.x, self.v, self.y, self.u = x, v, y, u = state
        if tau > 0.0:
            self.fresh = False
        e_new = self.model.energy(x, v, y, u)
        self.work_in += e_new - self.energy
        self.energy = e_new
        self.t, self.t_lo = t_new, lo

    def _energy(self):
        return self.model.energy(self.x, self.v, self.y, self.u)

    def _phase(self):
        """Phase [rad] of the built-in harmonic force at the state's time."""
        p = self.p
        om, phi, t, lo = p.Omega, p.phi, self.t, self.t_lo
        return om * t + phi + om * lo

    def _flight(self, fc, span):
        """Free flight from the current state with its bounds built (after a contact)."""
        return self.model.flight(self.x, self.v, self.y, self.u, fc, self._phase(), span, always_bound=True)

    def _snap(self, side):
        """Put the pair exactly on the stop (removes rounding-level overlap)."""
        self.x, self.v, self.y, self.u = self.model.snap(self.x, self.v, self.y, self.u, side)


class Damper(_Damper):
    """Event-driven pendulum impact damper; see the module doc for the rules."""

    def __init__(self, params=None, theta0=0.0, theta_dot0=0.0, alpha0=0.0, alpha_dot0=0.0, t0=0.0, floors0=None):
        """A building (storeys >= 1) starts at rest, or at floors0 = (displacements, velocities) of
        its floors [m, m/s]; theta0 and theta_dot0 then play no part (alpha0 is the particle's wire angle)."""
        p = params if params is not None else Params()
        self.p = p
        self.model = model = model_for(p)
        for name, val in (("theta_0", theta0), ("theta_dot_0", theta_dot0), ("alpha_0", alpha0),
                          ("alpha_dot_0", alpha_dot0), ("start time", t0)):
            check_finite(name, val)
        self._start_clock(float(t0))
        self.x, self.v, self.y, self.u = model.from_angles(theta0, theta_dot0, alpha0, alpha_dot0)
        if floors0 is not None:
            self._start_floors(*floors0)
        x, _, y, _ = self.displacements()
        gap = p.cx * x - p.cy * y
        slack = 64 * 2.220446049250313e-16 * (p.D + abs(p.cx * x) + abs(p.cy * y))
        if abs(gap) > p.D + slack:
            name = "d" if p.contact_form == DISPLACEMENT else "d_angle"
            raise ParameterError("theta_0, alpha_0", (theta0, alpha0),
                                 f"the initial state penetrates a stop: |gap| = {abs(gap)!r} > {name} = {p.D!r}")
        self._clearance = p.D
        self._passes_through = p.contact_form != DISPLACEMENT
        self.dissipated = 0.0
        self.work_in = 0.0
        self.viscous = 0.0  # energy taken by the dashpots (damped level on)
        self.energy = self._energy()
        self.energy0 = self.energy
        self.on_impact = None  # optional callback(t, side, rel_before, rel_after, loss)
        self.on_collapse = None  # optional callback(t, reason): a yielding building collapsed
        # what the impacts' contacts did (impact.Tally), with the materials given; the primary's
        # (first) period: w1 = FR w_primary
        self.contacts = tally(p.materials, 2.0 * math.pi * p.FR / p.w1)
        self.e_applied = p.e  # the restitution of the last impact
        # longest segment: one period of the fastest motion keeps trig arguments (and
        # so rounding) small and the derivative bounds tight
        self._max_span = 2.0 * math.pi / model.fastest
        self._coaster = model.coast  # the level's segment-free flight, or None
        self._follow = model.follow  # the level's own state carried along a piece, or None
        self._observables = model.observables  # the level's outputs inline, or None (bound once: per step)

    # ---- public API -------------------------------------------------------------------

    def dense(self, times, force=0.0, ground=0.0):
        """Advance to times[-1] and return x, v, y, u [m, m/s] at the sorted times (>= now) from
        the closed-form pieces, without restarting the motion at each output time."""
        times = [float(t) for t in times]
        rows = []
        k = 0

        def take(seg, t0, t1):
            nonlocal k
            while k < len(times) and times[k] <= t1:
                rows.append(seg.positions(times[k] - t0))
                k += 1

        if times and times[0] <= self.t:
            while k < len(times) and times[k] <= self.t:
                rows.append((self.x, self.v, self.y, self.u))
                k += 1
        if times:
            self.advance(times[-1], force, ground, observe=take)
        while len(rows) < len(times):  # times equal to the end, after the last piece
            rows.append((self.x, self.v, self.y, self.u))
        return rows

    def floors(self):
        """(displacements, velocities) of a building's floors [m, m/s] relative to the ground, floor 1
        first (storeys >= 1 only)."""
        if not self.p.storeys:
            raise ParameterError("storeys", self.p.storeys, "floors() needs a building: storeys >= 1")
        return self.model.floors(self.x, self.v)

    def building_outputs(self, force=0.0, ground=0.0):
        """(floor displacements [m], floor absolute accelerations [m/s2], storey drifts [m], base
        shear [N]) under held force `force` [N] on the damper floor and ground acceleration `ground`."""
        side = self.side if self.mode == STICK else 0
        return self.model.building_outputs(self.x, self.v, self.y, self.u, side, self._applied(force), ground)

    def building_observables(self, force=0.0, ground=0.0):
        """Every output of the building in one flat list (BuildingModel.building_observables) under held
        force `force` [N] on the damper floor and ground acceleration `ground` [m/s2]."""
        side = self.side if self.mode == STICK else 0
        return self.model.building_observables(self.x, self.v, self.y, self.u, side, self._applied(force), ground)

    def _start_floors(self, xs, vs):
        n = self.p.storeys
        if not n or len(xs) != n or len(vs) != n:
            raise ParameterError("floors0", (xs, vs), f"it needs a building and {n} displacements and velocities")
        for k, value in enumerate(list(xs) + list(vs)):
            check_finite(f"floors0[{k}]", value)
        r, w = self.y - self.x, self.u - self.v
        j = self.p.floor
        self.x, self.v = float(xs[j]), float(vs[j])
        self.y, self.u = self.x + r, self.v + w
        self.model.set_floors([float(x) for x in xs], [float(v) for v in vs])

    def bound_work(self):
        """Cap each advance() at MAX_PIECES / the level's piece_weight pieces, refusing a call that
        needs more (for hosts that cannot interrupt a call, such as fmi2DoStep)."""
        EventDriven.bound_work(self, self.model.piece_weight)

    def set_restitution(self, e):
        self.p.e = check_restitution(e)

    def angles(self):
        """(theta, theta_dot, alpha, alpha_dot) [rad, rad/s]: primary angle and the particle's
        wire angle from the vertical (its pivot moves with the primary from the coupled level on)."""
        return self.model.angles(self.x, self.v, self.y, self.u)

    def displacements(self):
        """(x, v, y, u): horizontal positions and velocities of primary and particle [m, m/s]."""
        return self.model.displacements(self.x, self.v, self.y, self.u)

    def acceleration(self, force=0.0, ground=0.0):
        """Primary acceleration [m/s2] (relative to the ground) under held force `force` [N] and
        ground acceleration `ground` [m/s2]."""
        return self.model.acceleration(self.x, self.v, self.y, self.u, self.contact, self._applied(force), ground)

    def contact_force(self, force=0.0, ground=0.0):
        """Force [N] of the stop on the particle while it rides a stop, else 0."""
        if self.mode != STICK:
            return 0.0
        return self.p.m * self.model.contact_accel(self.x, self.v, self.side, self._applied(force), ground)

    def get_state(self):
        """Plain dict (JSON-safe) of everything that determines the future motion: the keys of
        STATE_KEYS, the level's own (LevelModel.get_state) and, with materials, Tally's."""
        state = {k: getattr(self, k) for k in STATE_KEYS}
        state.update(self.model.get_state())
        if self.contacts is not None:
            state.update(self.contacts.get_state())
        return state

    def set_state(self, state):
        """Restore a dict get_state() wrote; anything else is refused (ParameterError naming the
        key, its value and the rule) before the state changes."""
        check_state(state)
        contacts = None if self.contacts is None else Tally.check_state(state)
        self.model.set_state(state)  # checks its own keys before it changes anything
        if contacts is not None:
            self.contacts.set_state(contacts)
        self._may_coast = True
        self.halted = bool(self.model.collapsed)
        for k in STATE_KEYS:
            setattr(self, k, state.get(k, _OPTIONAL.get(k)))

    # ---- internals --------------------------------------------------------------------

    def _own_event(self, seg, guard):
        """A storey's yield, unload or collapse (a yielding building)."""
        self.model.storey_event(seg.storey.guards[guard - seg.contacts], self.x, self.v, self.t)
        self._halt_if_collapsed()

    def _halt_if_collapsed(self):
        """Stop the motion once the building collapsed (a storey's limit, or a regime without modes)."""
        model = self.model
        if model.collapsed and not self.halted:
            self.halted = True
            storeys = model.storeys
            if storeys.collapse_time != storeys.collapse_time:  # NaN: the model did not know the time
                storeys.collapse_time = self.t
            if self.on_collapse is not None:
                self.on_collapse(self.t, storeys.collapse_reason)

    def _rest(self, fc, tau):
        return self.model.rest_piece(tau, -fc[1])

    def _fastest_from(self):
        return f", from g, L2, FR, mu{', Omega' if self.p.Omega_acting else ''}"

    def _unresolved(self, noise):
        p = self.p
        name = "d" if p.contact_form == DISPLACEMENT else "d_angle"
        raise ParameterError(name, p.D, f"the motion here reaches {noise / TOLERANCE:.6g} m, so the gap is known to "
                             f"{noise:.3g} only, more than 1/{GAP_RESOLUTION:g} of the clearance: contacts cannot "
                             f"be resolved at t = {self.t!r} s (raise {name}, or lower the loads that drive the "
                             "motion: F, a_g, F0)")

    def _overflowed(self, force, ground):
        raise ParameterError("F, a_g", (force, ground), f"the motion they drive (with the parameters {self.p.as_dict()}) "
                             f"leaves the range of float arithmetic by t = {self.t!r} s (x = {self.x!r}, "
                             f"energy = {self.energy!r}); the state is left there")

    def _impact(self, side):
        e, contacts = self.p.e, self.contacts
        self.e_applied = e
        if contacts is not None:
            w, mass = self.model.approach(self.x, self.v, self.y, self.u)
            e = self.e_applied = contacts.impact(self.t, w, mass, e, True)
        state, loss, before, after = self.model.collide(self.x, self.v, self.y, self.u, side, e)
        self.x, self.v, self.y, self.u = state
        self.impacts += 1
        self._account(loss)
        self._halt_if_collapsed()
        if self.on_impact is not None:
            self.on_impact(self.t, side, before, after, loss)

    def _collapse(self, side, counted):
        """Plastic impact that ends a chatter sequence on stop `side` (counted as an impact),
        or evens out the rounding-level relative speed of a touch (not counted)."""
        state, loss, before, _ = self.model.collide(self.x, self.v, self.y, self.u, side, 0.0)
        if before == 0.0:
            return
        self.e_applied = 0.0
        if counted and self.contacts is not None:
            self.contacts.impact(self.t, before, self.model.approach(self.x, self.v, self.y, self.u)[1], 0.0, False)
        self.x, self.v, self.y, self.u = state
        self._account(loss)
        self._halt_if_collapsed()
        if counted:
            self.impacts += 1
            if self.on_impact is not None:
                self.on_impact(self.t, side, before, 0.0, loss)

    def _account(self, loss):
        self.dissipated += loss
        e_new = self._energy()
        self.energy = e_new
