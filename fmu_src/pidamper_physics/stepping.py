"""The event loop every event-driven model of the core steps with (Damper, DamperUnit).

A model moves from event to event over a call `advance(t_end, ...)`: it builds the closed-form
segment of its current mode, asks events.locate for the first contact event inside the piece,
moves to it (or to the piece's end) and handles it.  What this module owns, once for all models:

- the clock: time t + t_lo [s], advanced by a two-sum so that a piece shorter than one ulp of t
  still moves the state and a forcing phase tied to the clock does not drift;
- the loop and its progress argument (below), with the work cap of a call (`bound_work`);
- the contact rule after an event: a pair that still closes after the contact (or whose rebound
  would rise less than CHATTER_HEIGHT position-rounding units while pressed into the stop)
  settles on the stop (displacement form: the chatter tail collapses into one plastic impact and
  the pair rides the stop) or passes through it (angle form);
- the refusals a call can end in, each naming the value and the rule.

A model provides the physics: `_segment(loads, span)` (the segment of its mode from the current
state), `_flight(loads, span)` (free flight from the current state, bounds always built),
`_move(seg, tau, t_end, loads, observe)` (take the state at tau and book it; tick the clock with
`_tick`), `_snap(side)`, `_impact(side)`, `_collapse(side, counted)`, `_unresolved(noise)` and the
attributes `_clearance` [m] (the gap's half-width the guards measure), `_max_span` [s] (longest
piece: one period of the fastest motion) and `_passes_through` (angle form); a model with a
segment-free free flight sets `_coaster` and provides `_coast(state, tau, t_end)` (Damper's linear
level: measured faster than building a segment for the pieces clear of the stops).

Progress: a pass either ends the call (the piece reaches t_end), moves the state by a whole span
(at most h / _max_span such passes), or moves it to an event and handles it.  An event switches
the mode and sets `fresh`, so locate does not report the same instant again: the next event lies
at tau > 0 (events.py: every locate pass advances tau by at least one ulp, at most
events.MAX_PASSES passes).  Hence passes <= h / _max_span + 2 (events + 1) for the closed-form
models (the nonlinear level adds its integrator steps, seg.reach): finite, as the events are
(chatter collapses below CHATTER_HEIGHT), and capped at max_pieces, so no input makes a call run
on without bound.
A model at rest (`_resting`: every value of its state exactly +0.0, no load) takes no segments:
the closed form from there is +0.0 again, so each piece only ticks the clock and lets the model
book what rest changes (`_rest`); `still` then says that the call changed no output.
Plain Python (math): this ships inside the FMU.
"""
import math

from .events import CROSS, classify, locate, resolution_speed
from .params import ParameterError
from .segments import GAP_RESOLUTION

FREE = 0     # the particle swings freely inside the gap
STICK = 1    # the particle rides stop `side` (displacement form)
OUTSIDE = 2  # angle form: the bodies have passed through stop `side`

CHATTER_HEIGHT = 16.0  # rebound apex, in position-rounding units, below which chatter collapses

#: most pieces (loop passes of a call: a smooth piece, or a piece that ends at an event) one call
#: may take, divided by the model's `piece_weight` (an integrator step of the nonlinear level costs
#: about five closed-form pieces); a step that needs more is refused (FMI 2.0 cannot interrupt
#: fmi2DoStep): about 0.3 s of work on the 2-core machine at every level
MAX_PIECES = 10000


def at_rest(values):
    """True when every value is +0.0 exactly.  A closed form started from +0.0 under no load gives
    +0.0 again (each component is +0.0 plus terms that are zeros of either sign), whereas a -0.0
    start may come out as +0.0: such a state takes the full step once."""
    for value in values:
        if value != 0.0 or math.copysign(1.0, value) < 0.0:
            return False
    return True


def unsigned(value):
    """False for -0.0 only: an accumulator a step adds a zero of either sign to keeps its value
    bit for bit unless it is -0.0 (-0.0 + 0.0 is +0.0)."""
    return value != 0.0 or math.copysign(1.0, value) > 0.0


def same_bits(a, b):
    """True when the floats a and b are equal bit for bit (a zero's sign counts: a result computed
    from -0.0 may differ from one computed from +0.0)."""
    return a == b and (a != 0.0 or math.copysign(1.0, a) == math.copysign(1.0, b))


def same_floats(a, b):
    """True when a and b hold the same floats bit for bit, pair by pair (same_bits), over the
    shorter of the two (as all(map(same_bits, a, b)), without the Python call per pair)."""
    for i in range(min(len(a), len(b))):
        if not same_bits(a[i], b[i]):
            return False
    return True


def rest_peaks(peaks, tau, a_g):
    """peaks.Peaks.take() of a piece of tau [s] over which every floor stays at rest relative to
    the ground (displacement, velocity, acceleration and all their derivatives zero, a_g zero): the
    start's absolute velocity is the ground's, |0 + v_g| = |v_g|, which may raise the velocity
    maxima; every other start value is zero, and with the piece's bounds zero the forward cubic
    clears the rest of it.  The ground's velocity moves on as in take().  True if a maximum rose."""
    vg = peaks.v_ground
    top = abs(vg)
    raised = False
    velocity = peaks.velocity
    for k in range(peaks.n):
        if top > velocity[k]:
            velocity[k] = top
            raised = True
    peaks.v_ground = vg + a_g * tau
    return raised


def contact_outcome(seg, side):
    """(closing, settles) after a contact on stop `side` (+1: guard 0), from the flight `seg` of
    the post-contact state: closing, the pair still approaches the stop (the first significant
    derivative of its guard is negative); settles, it closes or its rebound would rise less than
    CHATTER_HEIGHT rounding units while it is pressed into the stop."""
    g, g1, g2, g3 = seg.derivs(0.0, 0 if side > 0 else 1)
    n0, n1, n2, n3 = seg.noise
    _, first = classify(g1, g2, g3, resolution_speed(g2, n0, n1, n2), n2, n3)
    closing = first < 0.0
    return closing, closing or (g2 < -n2 and g1 * g1 <= -2.0 * g2 * CHATTER_HEIGHT * n0)


class EventDriven:
    """Clock, mode and event loop of an event-driven model (see the module doc)."""

    def _start_clock(self, t0):
        """Clock at t0 [s], mode FREE, no work cap, and the defaults a model may change after
        (set here, not as class attributes: the compiled build keeps them in C fields, stepping.pxd)."""
        self._passes_through = False  # angle form: a closing pair passes through the stop
        self._coaster = None  # the model's segment-free free flight (coast(state..., fx, fy, T)), if any
        self.still = False  # the last call changed nothing but the clock (it found the model at rest)
        self.halted = False  # set by a model whose motion ends (a collapsed building): the loop stops at once
        self.t = t0
        self.t_lo = 0.0  # the state's time is t + t_lo exactly: t_lo keeps what rounding t dropped
        self.mode, self.side, self.fresh = FREE, 0, False  # fresh: right after a switch at this instant
        self.impacts = 0
        self._may_coast = True  # the last piece was clear of the stops: try coasting first (a hint only)
        self.pieces = 0  # loop passes of the last advance (see the progress argument)
        self.max_pieces = math.inf  # no cap on a call's work unless bound_work() sets one

    def bound_work(self, weight=1):
        """Cap each call at MAX_PIECES // weight pieces, refusing a call that needs more (for
        hosts that cannot interrupt a call, such as fmi2DoStep)."""
        self.max_pieces = MAX_PIECES // weight

    @property
    def contact(self):
        """+1 / -1 while the particle rides that stop, else 0."""
        return self.side if self.mode == STICK else 0

    # ---- the loop -------------------------------------------------------------------------

    def _run(self, t_end, loads, observe=None):
        """Step from event to event up to t_end [s] under the held `loads` (the model's own form);
        observe(seg, t0, t1), if given, sees each smooth piece before the state leaves it.  A t_end
        before the clock, or beyond what one call may take, is refused first."""
        cap = self.max_pieces
        if t_end < self.t or t_end - self.t > self._max_span * cap:
            self._check_end(t_end)
        pieces = 0
        impacts = self.impacts
        ready = None  # a flight segment already built at the current state by the last event
        coast = self._coaster if observe is None else None
        rest = still = observe is None and self._resting(loads)  # nothing moves: no segment to build
        while self.t < t_end:
            pieces += 1
            if pieces > cap:
                self._too_many(t_end, self.impacts - impacts)
            horizon = (t_end - self.t) - self.t_lo
            if horizon <= 0.0:  # the state is already at t_end; the clock catches up
                self.t, self.t_lo = t_end, self.t_lo + (self.t - t_end)
                break
            span = min(horizon, self._max_span)
            if rest:  # the piece _move would take, minus the motion: the clock and the model's books
                if self._rest(loads, span):
                    still = False
                self.t, self.t_lo = self._tick(span, t_end if span == horizon else None)
                self.fresh = False
                self._may_coast = True
                continue
            if coast is not None and ready is None and self._may_coast and self.mode == FREE:
                state = coast(self.x, self.v, self.y, self.u, loads[0], loads[1], span)  # None: a stop within reach
                if state is not None:
                    self._coast(state, span, t_end if span == horizon else None)
                    continue
            seg = ready or self._segment(loads, span)
            self._may_coast = clear = seg.clear
            if not clear and self.mode == FREE and seg.noise[0] * GAP_RESOLUTION > self._clearance:
                self._unresolved(seg.noise[0])
            if seg.reach < span:  # an integrator step (nonlinear level) ends before the span
                span = seg.reach
            event = locate(seg, span, self.fresh)
            if event is None:
                self._move(seg, span, t_end if span == horizon else None, loads, observe)
                ready = None
                continue
            tau, kind, guard = event
            self._move(seg, tau, t_end if tau >= horizon else None, loads, observe)
            if guard >= (2 if self.mode == FREE else 1):  # beyond the contacts': the model's own (a storey's)
                ready = None
                self._switch(self.mode, self.side)
                self._own_event(seg, guard)
            else:
                ready = self._handle(kind, 1 - 2 * guard, loads, min(t_end - self.t, self._max_span))
            if self.halted:  # the model stops moving (a building's collapse); the clock goes on
                self.t, self.t_lo = t_end, 0.0
                break
        self.pieces = pieces
        self.still = still

    def _resting(self, loads):
        """True when the state is exactly at rest under `loads` (see at_rest): a piece then
        changes nothing but the clock and what _rest books.  A model that can tell overrides this."""
        return False

    def _rest(self, loads, tau):
        """Book a piece of tau [s] at rest (after _resting); True if an output changed."""
        raise NotImplementedError

    # the model's physics the loop calls at every piece (declared here so that the compiled build
    # calls them in C: stepping.pxd)

    def _segment(self, loads, span):
        """The segment of the current mode from the current state, for a piece of up to span [s]."""
        raise NotImplementedError

    def _move(self, seg, tau, t_end, loads, observe):
        """Take the state at tau [s] of seg and tick the clock (t_end: the piece ends there)."""
        raise NotImplementedError

    def _coast(self, state, tau, t_end):
        """_move to the state `state` a segment-free free flight reached after tau [s]."""
        raise NotImplementedError

    def _tick(self, tau, t_end):
        """(t, t_lo) of the clock moved by tau (two-sum; t_end: the piece ends there exactly)."""
        t = self.t
        s = t + tau
        b = s - t
        lo = self.t_lo + ((t - (s - b)) + (tau - b))
        if t_end is None:
            t_new = s + lo  # renormalised: |t_lo| stays within half an ulp of t
            return t_new, lo - (t_new - s)
        end = t_end  # a C double in the compiled build (the clock keeps t_end as given)
        return t_end, lo + (s - end)

    # ---- events ---------------------------------------------------------------------------

    def _own_event(self, seg, guard):
        """A zero of a guard beyond the contacts' (a model with its own events overrides this; it
        sets `halted` when its motion ends)."""
        raise NotImplementedError(f"{type(self).__name__} has no guards beyond its contacts")

    def _switch(self, mode, side):
        self.mode, self.side, self.fresh = mode, side, True

    def _handle(self, kind, side, loads, span):
        """Event of kind CROSS or TOUCH; in free flight `side` is the stop (+1: guard 0).
        Returns the flight segment from the new state when the pair stays free, else None."""
        if self.mode != FREE:
            self._switch(FREE, 0)  # release from the stop, or re-entry into the gap
            return None
        self._snap(side)
        if kind == CROSS:
            self._impact(side)
        seg = self._flight(loads, span)
        mode = self._after_contact(seg, side, kind == CROSS)
        self._switch(mode, 0 if mode == FREE else side)
        return seg if mode == FREE else None

    def _after_contact(self, seg, side, impacted):
        """Mode after a contact on `side`: FREE, STICK (the chatter tail collapsed) or OUTSIDE
        (angle form); `seg` is the flight from the post-contact state."""
        closing, settles = contact_outcome(seg, side)
        if self._passes_through:
            return OUTSIDE if closing else FREE
        if settles:
            self._collapse(side, impacted)
            return STICK
        return FREE

    # ---- refusals -------------------------------------------------------------------------

    def _check_end(self, t_end):
        """Refuse a t_end before the current time or beyond what one call may take."""
        if t_end < self.t:
            raise ParameterError("t_end", t_end, f"it must be >= the current time {self.t!r}")
        if t_end - self.t > self._max_span * self.max_pieces:
            self._too_long(t_end)

    def _too_long(self, t_end):
        raise ParameterError("step", t_end - self.t, f"one call may take at most {self.max_pieces} pieces, each at "
                             f"most one period {self._max_span:.6g} s of the fastest motion "
                             f"({2.0 * math.pi / self._max_span:.6g} rad/s{self._fastest_from()}), so at most "
                             f"{self.max_pieces * self._max_span:.6g} s: take shorter communication steps")

    def _fastest_from(self):
        """What sets the fastest motion, for the messages (', from ...')."""
        return ""

    def _now(self):
        """The state's time [s] for messages and callbacks."""
        return self.t

    def _too_many(self, t_end, impacts):
        raise ParameterError("step", t_end - self.t, f"it needed more than {self.max_pieces} pieces by t = {self._now()!r} s "
                             f"({impacts} impacts among them: a chatter or impact sequence too dense for one call; "
                             "the state is left there): take shorter communication steps")
