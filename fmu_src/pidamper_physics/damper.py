"""The pendulum impact damper stepped from event to event.

Coordinates are linear: x = L2 theta (primary), y = L1 alpha (particle), v, u
their velocities [m, m/s].  Between events both bodies follow closed-form
linear motion (segments.py); events are located exactly (events.py) and
handled here:

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
"""
import math

from .events import CROSS, locate, classify, resolution_speed
from .levels import model_for
from .params import DISPLACEMENT, Params, ParameterError, check_finite, check_restitution
from .segments import GAP_RESOLUTION, TOLERANCE

FREE = 0     # both bodies swing freely inside the gap
STICK = 1    # the particle rides stop `side` (displacement form)
OUTSIDE = 2  # angle form: the bodies have passed through stop `side`

CHATTER_HEIGHT = 16.0  # rebound apex, in position-rounding units, below which chatter collapses

#: most pieces (loop passes of Damper.advance: a smooth piece, or a piece that ends at an event)
#: one call may take, divided by the level's `piece_weight` (an integrator step of the nonlinear
#: level costs about five closed-form pieces); a step that needs more is refused (FMI 2.0 cannot
#: interrupt fmi2DoStep): about 0.3 s of work on the 2-core machine at every level
MAX_PIECES = 10000

STATE_KEYS = ("t", "t_lo", "x", "v", "y", "u", "mode", "side", "fresh", "impacts", "dissipated",
              "work_in", "viscous", "energy")


_STATE_CHOICES = {"mode": (FREE, STICK, OUTSIDE), "side": (-1, 0, 1), "fresh": (False, True)}


def check_state(state):
    """Refuse a state dict that Damper.get_state did not write: missing keys, wrong types,
    non-finite numbers, a negative impact count (t_lo may be absent: states of older builds)."""
    if not isinstance(state, dict):
        raise ParameterError("state", type(state).__name__, "it must be the dict Damper.get_state writes")
    for key in STATE_KEYS + ("step_hint",):
        if key not in state:
            if key == "t_lo":
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


class Damper:
    """Event-driven pendulum impact damper; see the module doc for the rules."""

    def __init__(self, params=None, theta0=0.0, theta_dot0=0.0, alpha0=0.0, alpha_dot0=0.0, t0=0.0, floors0=None):
        """A building (storeys >= 1) starts at rest, or at floors0 = (displacements, velocities) of
        its floors [m, m/s]; theta0 and theta_dot0 then play no part (alpha0 is the particle's wire angle)."""
        p = params if params is not None else Params()
        self.p = p
        self.model = model_for(p)
        self._carry = getattr(self.model, "others", None) is not None  # the level keeps more floors
        for name, val in (("theta_0", theta0), ("theta_dot_0", theta_dot0), ("alpha_0", alpha0),
                          ("alpha_dot_0", alpha_dot0), ("start time", t0)):
            check_finite(name, val)
        self.t = float(t0)
        self.t_lo = 0.0  # the state's time is t + t_lo exactly: t_lo keeps what rounding t dropped
        self.x, self.v, self.y, self.u = self.model.from_angles(theta0, theta_dot0, alpha0, alpha_dot0)
        if floors0 is not None:
            self._start_floors(*floors0)
        x, _, y, _ = self.displacements()
        gap = p.cx * x - p.cy * y
        slack = 64 * 2.220446049250313e-16 * (p.D + abs(p.cx * x) + abs(p.cy * y))
        if abs(gap) > p.D + slack:
            name = "d" if p.contact_form == DISPLACEMENT else "d_angle"
            raise ParameterError("theta_0, alpha_0", (theta0, alpha0),
                                 f"the initial state penetrates a stop: |gap| = {abs(gap)!r} > {name} = {p.D!r}")
        self.mode = FREE
        self.side = 0
        self.fresh = False  # True right after a mode switch at the current instant
        self.impacts = 0
        self.dissipated = 0.0
        self.work_in = 0.0
        self.viscous = 0.0  # energy taken by the dashpots (damped level on)
        self.energy = self._energy()
        self.energy0 = self.energy
        self.on_impact = None  # optional callback(t, side, rel_before, rel_after, loss)
        # longest segment: one period of the fastest motion keeps trig arguments (and
        # so rounding) small and the derivative bounds tight
        self._max_span = 2.0 * math.pi / self.model.fastest
        self._coast_model = getattr(self.model, "coast", None)  # a level's segment-free flight, if any
        self._may_coast = True  # the last piece was clear of the stops: try coasting first (a hint only)
        self._observables = getattr(self.model, "observables", None)  # a level's outputs in one call, if any
        self.pieces = 0  # loop passes of the last advance (see its progress argument)
        self.max_pieces = math.inf  # no cap on a call's work unless bound_work() sets one

    # ---- public API -------------------------------------------------------------------

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
        if t_end < self.t:
            raise ParameterError("t_end", t_end, f"it must be >= the current time {self.t!r}")
        cap = self.max_pieces
        if t_end - self.t > self._max_span * cap:
            self._too_long(t_end)
        fc = (force / self.p.M - ground, -ground)  # loads per mass on the primary and the particle
        ready = None  # a flight segment already built at the current state by the last event
        coast = self._coast_model if observe is None else None
        # Progress: a pass either ends the call (the piece reaches t_end), moves the state by a
        # whole span (_max_span, one period of the fastest motion: at most h / _max_span such
        # passes), or moves it to an event and handles it.  An event switches the mode and sets
        # `fresh`, so locate does not report the same instant again: the next event lies at
        # tau > 0 (events.py: every locate pass advances tau by at least one ulp, at most
        # events.MAX_PASSES passes).  Hence passes <= h / _max_span + 2 (events + 1) for the
        # closed-form levels (the nonlinear one adds its integrator steps, seg.reach): finite, as
        # the events are (chatter collapses below CHATTER_HEIGHT), and capped at max_pieces, so
        # no input makes a call run on without bound.
        pieces = 0
        impacts = self.impacts
        while self.t < t_end:
            pieces += 1
            if pieces > cap:
                self._too_many(t_end, self.impacts - impacts)
            horizon = (t_end - self.t) - self.t_lo
            if horizon <= 0.0:  # the state is already at t_end; the clock catches up
                self.t, self.t_lo = t_end, self.t_lo + (self.t - t_end)
                break
            span = min(horizon, self._max_span)
            if coast is not None and ready is None and self._may_coast and self.mode == FREE:
                state = coast(self.x, self.v, self.y, self.u, fc[0], fc[1], span)  # None: a stop within reach
                if state is not None:
                    self._coast(state, span, t_end if span == horizon else None)
                    continue
            seg = ready or self._segment(fc, span)
            self._may_coast = clear = seg.clear
            if not clear and self.mode == FREE and seg.noise[0] * GAP_RESOLUTION > self.p.D:
                self._unresolved(seg.noise[0])
            if seg.reach < span:  # an integrator step (nonlinear level) ends before the span
                span = seg.reach
            event = locate(seg, span, self.fresh)
            if event is None:
                self._move(seg, span, t_end if span == horizon else None, fc, observe)
                ready = None
                continue
            tau, kind, guard = event
            self._move(seg, tau, t_end if tau >= horizon else None, fc, observe)
            ready = self._handle(kind, 1 - 2 * guard, fc, min(t_end - self.t, self._max_span))
        self.pieces = pieces
        check = self.x + self.v + self.y + self.u + self.energy + self.work_in
        if check - check != 0.0:  # a value overflowed: refuse rather than answer inf or nan
            self._overflowed(force, ground)

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
        if not self._carry:
            raise ParameterError("storeys", self.p.storeys, "floors() needs a building: storeys >= 1")
        return self.model.floors(self.x, self.v)

    def building_outputs(self, force=0.0, ground=0.0):
        """(floor displacements [m], floor absolute accelerations [m/s2], storey drifts [m], base
        shear [N]) under held force `force` [N] on the damper floor and ground acceleration `ground`."""
        side = self.side if self.mode == STICK else 0
        return self.model.building_outputs(self.x, self.v, self.y, self.u, side, self._applied(force), ground)

    def _start_floors(self, xs, vs):
        n = self.p.storeys
        if not self._carry or len(xs) != n or len(vs) != n:
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
        self.max_pieces = MAX_PIECES // getattr(self.model, "piece_weight", 1)

    def set_restitution(self, e):
        self.p.e = check_restitution(e)

    def angles(self):
        """(theta, theta_dot, alpha, alpha_dot) [rad, rad/s]: primary angle and the particle's
        wire angle from the vertical (its pivot moves with the primary from the coupled level on)."""
        return self.model.angles(self.x, self.v, self.y, self.u)

    def displacements(self):
        """(x, v, y, u): horizontal positions and velocities of primary and particle [m, m/s]."""
        return self.model.displacements(self.x, self.v, self.y, self.u)

    @property
    def contact(self):
        """+1 / -1 while the particle rides that stop, else 0."""
        return self.side if self.mode == STICK else 0

    def acceleration(self, force=0.0, ground=0.0):
        """Primary acceleration [m/s2] (relative to the ground) under held force `force` [N] and
        ground acceleration `ground` [m/s2]."""
        return self.model.acceleration(self.x, self.v, self.y, self.u, self.contact, self._applied(force), ground)

    def contact_force(self, force=0.0, ground=0.0):
        """Force [N] of the stop on the particle while it rides a stop, else 0."""
        if self.mode != STICK:
            return 0.0
        return self.p.m * self.model.contact_accel(self.x, self.v, self.side, self._applied(force), ground)

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

    def get_state(self):
        """Plain dict (JSON-safe) of everything that determines the future motion."""
        state = {k: getattr(self, k) for k in STATE_KEYS}
        state["step_hint"] = getattr(self.model, "hint", 0.0)  # the integrator's next step (nonlinear)
        if self._carry:
            state["others"] = list(self.model.others)  # a building's other floors
        return state

    def set_state(self, state):
        """Restore a dict get_state() wrote; anything else is refused (ParameterError naming the
        key, its value and the rule) before the state changes."""
        check_state(state)
        if self._carry:
            others = state.get("others")
            if not isinstance(others, list) or len(others) != len(self.model.others):
                raise ParameterError("state others", others, f"{len(self.model.others)} numbers: the other floors")
            for k, value in enumerate(others):
                check_finite(f"state others[{k}]", value)
            self.model.others = [float(v) for v in others]
        self._may_coast = True
        for k in STATE_KEYS:
            setattr(self, k, state.get(k, 0.0) if k == "t_lo" else state[k])
        if hasattr(self.model, "hint"):
            self.model.hint = state["step_hint"]

    # ---- internals --------------------------------------------------------------------

    def _energy(self):
        return self.model.energy(self.x, self.v, self.y, self.u)

    def _segment(self, fc, horizon):
        """The segment from the current state and mode; fc = (loads per mass on primary, particle)."""
        psi = self._phase()
        model = self.model
        if self.mode == STICK:
            return model.stick(self.x, self.v, self.side, fc, psi, horizon)
        if self.mode == OUTSIDE:
            return model.outside(self.x, self.v, self.y, self.u, fc, psi, horizon, self.side)
        return model.flight(self.x, self.v, self.y, self.u, fc, psi, horizon)

    def _too_long(self, t_end):
        p = self.p
        raise ParameterError("step", t_end - self.t, f"one call may take at most {self.max_pieces} pieces, each at most "
                             f"one period {self._max_span:.6g} s of the fastest motion "
                             f"({2.0 * math.pi / self._max_span:.6g} rad/s, from g, L2, FR, mu"
                             f"{', Omega' if p.Omega_acting else ''}), so at most "
                             f"{self.max_pieces * self._max_span:.6g} s: take shorter communication steps")

    def _too_many(self, t_end, impacts):
        raise ParameterError("step", t_end - self.t, f"it needed more than {self.max_pieces} pieces by t = {self.t!r} s "
                             f"({impacts} impacts among them: a chatter or impact sequence too dense for one call; "
                             "the state is left there): take shorter communication steps")

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
        if self._carry:
            self.model.others = seg.others(tau)
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

    def _tick(self, tau, t_end):
        """(t, t_lo) of the clock moved by tau (two-sum; t_end: the piece ends there exactly)."""
        t = self.t
        s = t + tau
        b = s - t
        lo = self.t_lo + ((t - (s - b)) + (tau - b))
        if t_end is None:
            t_new = s + lo  # renormalised: |t_lo| stays within half an ulp of t
            return t_new, lo - (t_new - s)
        return t_end, lo + (s - t_end)

    def _coast(self, state, tau, t_end):
        """_move for a free flight the level computed without a segment (no dashpots to book)."""
        t_new, lo = self._tick(tau, t_end)
        self.x, self.v, self.y, self.u = state
        if tau > 0.0:
            self.fresh = False
        e_new = self.model.energy(*state)
        self.work_in += e_new - self.energy
        self.energy = e_new
        self.t, self.t_lo = t_new, lo

    def _applied(self, force):
        """Applied force per primary mass [m/s2]: the held `force` [N] and the built-in harmonic."""
        p = self.p
        return force / p.M + p.F0 / p.M * math.sin(self._phase()) if p.F0 else force / p.M

    def _phase(self):
        """Phase [rad] of the built-in harmonic force at the state's time."""
        p = self.p
        return p.Omega * self.t + p.phi + p.Omega * self.t_lo

    def _switch(self, mode, side):
        self.mode, self.side, self.fresh = mode, side, True

    def _handle(self, kind, side, fc, span):
        """Event of kind CROSS or TOUCH; in free flight `side` is the stop (+1: guard 0).
        Returns the flight segment from the new state when the pair stays free, else None."""
        if self.mode != FREE:
            self._switch(FREE, 0)  # release from the stop, or re-entry into the gap
            return None
        self._snap(side)
        if kind == CROSS:
            self._impact(side)
        seg = self.model.flight(self.x, self.v, self.y, self.u, fc, self._phase(), span,
                                always_bound=True)
        mode = self._after_contact(seg, side, kind == CROSS)
        self._switch(mode, 0 if mode == FREE else side)
        return seg if mode == FREE else None

    def _after_contact(self, seg, side, impacted):
        """Mode after a contact on `side`: FREE, STICK (displacement) or OUTSIDE (angle form);
        `seg` is the flight from the post-contact state."""
        g, g1, g2, g3 = seg.derivs(0.0, 0 if side > 0 else 1)
        n0, n1, n2, n3 = seg.noise
        _, first = classify(g1, g2, g3, resolution_speed(g2, n0, n1, n2), n2, n3)
        if self.p.contact_form != DISPLACEMENT:
            return OUTSIDE if first < 0.0 else FREE  # still closing: pass through the stop
        # rebound rises less than CHATTER_HEIGHT rounding units while pressed in: the
        # rest of the chatter sequence collapses into one plastic impact
        chatter_ends = g2 < -n2 and g1 * g1 <= -2.0 * g2 * CHATTER_HEIGHT * n0
        if chatter_ends or first < 0.0:
            self._collapse(side, impacted)
            return STICK
        return FREE

    def _snap(self, side):
        """Put the pair exactly on the stop (removes rounding-level overlap)."""
        self.x, self.v, self.y, self.u = self.model.snap(self.x, self.v, self.y, self.u, side)

    def _impact(self, side):
        state, loss, before, after = self.model.collide(self.x, self.v, self.y, self.u, side, self.p.e)
        self.x, self.v, self.y, self.u = state
        self.impacts += 1
        self._account(loss)
        if self.on_impact is not None:
            self.on_impact(self.t, side, before, after, loss)

    def _collapse(self, side, counted):
        """Plastic impact that ends a chatter sequence on stop `side` (counted as an impact),
        or evens out the rounding-level relative speed of a touch (not counted)."""
        state, loss, before, _ = self.model.collide(self.x, self.v, self.y, self.u, side, 0.0)
        if before == 0.0:
            return
        self.x, self.v, self.y, self.u = state
        self._account(loss)
        if counted:
            self.impacts += 1
            if self.on_impact is not None:
                self.on_impact(self.t, side, before, 0.0, loss)

    def _account(self, loss):
        self.dissipated += loss
        e_new = self._energy()
        self.energy = e_new
