"""The damper unit alone: the particle and its stops, for a structure modelled elsewhere.

A particle of mass m hangs as a pendulum (length L1, w1 = sqrt(g/L1), small angles) from an
attachment point of someone else's structure, whose mass at that point is M_s.  The unit knows the
attachment only through its absolute acceleration a_s [m/s2], held over each step.  In the
relative coordinate r = y - x_s [m] (particle minus attachment):

    r'' = -w1^2 r - 2 zeta_p w1 r' - a_s          between contacts,   stops at r = +-d.

The force of the unit on the structure (positive along the structure's x) is the wire and dashpot
force m w1^2 r + 2 zeta_p m w1 r', the stop's reaction while the particle rides a stop, and the
impulses of the impacts.

Impact law (two bodies, m and M_s, Newton restitution e, momentum conserved).  With w the
approach velocity r' before, the impulse on the structure is J = m M_s / (m + M_s) (1 + e) w
(the particle receives -J); energy lost 0.5 m M_s / (m + M_s) (1 - e^2) w^2.  What the unit
does with its own relative motion depends on how the host passes the impulse on
(`impulse_aware`):

- 0, mean force (default): the host passes F_s, the step's mean force, impulses included, and
  the structure's acceleration a_s carries the attachment's share J / M_s back to the unit in
  the next step.  So the unit jumps ONLY the particle's velocity, r' -> w - J/m
  = w (m - e M_s) / (m + M_s).  (Jumping the attachment as well would make the structure's
  response reach the unit twice: once here, once through a_s.)
  Rule for m > e M_s: after that jump the particle still approaches the stop in the unit's frame;
  the contact is then plastic in the unit's frame: the particle's relative velocity is brought
  to zero, total impulse J = m w.  That is the limit of repeated impacts of the law, each at the
  velocity the last one left (a geometric series of ratio (m - e M_s) / (m + M_s)): the particle
  ends on the stop at zero relative speed, riding it while pressed (or leaving it) until the
  attachment's share arrives through a_s.  The loss booked is that of the impulse m w between the
  two bodies, 0.5 m w^2 (M_s - m) / M_s: the co-simulated pair then separates as with restitution
  m / M_s, not e, so this mode cannot converge to the two-body law when m > e M_s (measured:
  docs/cosim); use impulse_aware = 1 there.
- 1, impulse-aware: the host passes the impulse itself (J_s at t_J) to a structure that applies
  it at that instant, and F_s holds the smooth force only; the structure's acceleration then
  never carries the impulse, so the unit jumps the attachment too: the full two-body law acts in
  its frame, r' -> -e w, exactly as in a monolithic model.

With the materials given (impact.MATERIAL_NAMES: restitution, S_y, E1, nu1, E2, nu2, R, e_max) the
restitution may come from each impact's approach speed and reduced mass m M_s / (m + M_s)
(impact.Contact), and each impact's peak force, pressure and duration are booked (impact.Tally:
largest of the step, plastic count), as in every particle model.

Chatter collapses into sticking by the rule of damper.py (a rebound that would rise less than
CHATTER_HEIGHT position-rounding units while the particle is pressed into the stop ends the
sequence with a plastic impact: relative velocity to zero, by the mode's law); the unit steps with
the event loop of every model (stepping.py).  Riding a stop:
r = s d, r' = 0; the stop's force on the particle N = m (a_s + w1^2 s d) is constant under held
a_s, so the particle rides while s N < 0 (pressed: -s a_s > w1^2 d) and is released at the
step's start otherwise.  Events are located by events.locate (conservative advancement, no
contact can be missed), and each call's work is capped (bound_work) as Damper's.

Outputs of a step [t, t + h]: F_s [N], the mean force on the structure, F_s h = -(change of the
particle's absolute momentum) - (in mode 1) the impulses J_s, where the particle's absolute
velocity changes by Delta r' + a_s h (+ the attachment's jumps J/M_s the unit applied itself in
mode 1): momentum passes exactly, to rounding.  J_s [N s] the step's impulses on the structure
(all modes), t_J [s] their |J|-weighted time (the step's end without impulses).
Plain Python (math): this ships inside the FMU.
"""
import math

from .impact import MATERIAL_DEFAULTS, MATERIAL_NAMES, Tally, check_contact, plastic_in_unit_frame, relative, tally
from .oscillator import DampedOscillator
from .params import SCALE_RANGE, ZETA_GAP, ParameterError, check_finite, check_restitution
from .segments import GAP_RESOLUTION, TOLERANCE, noise_size
from .stepping import FREE, STICK, EventDriven

MEAN_FORCE = 0
IMPULSE_AWARE = 1

#: default parameters of the unit (the FMU's start values): a 6 t particle (2 % of the default
#: ShearBuilding's 300 t) on a 1 m wire in a +-5 cm gap, hung from a 100 t floor
DEFAULTS = {"m": 6000.0, "M_s": 1e5, "L1": 1.0, "g": 9.81, "d": 0.05, "e": 0.5, "zeta_p": 0.0,
            "impulse_aware": MEAN_FORCE, "r_0": 0.0, "r_dot_0": 0.0, **MATERIAL_DEFAULTS}

STATE_KEYS = ("t", "r", "rd", "mode", "side", "fresh", "impacts", "dissipated", "F_s", "J_s", "t_J",
              "impacts_in_step")
_CHOICES = {"mode": (FREE, STICK), "side": (-1, 0, 1), "fresh": (False, True)}


class Riding:
    """The particle riding a stop while pressed into it: it stays there over the piece (the stop's
    force is constant under held a_s), so the segment has no event (clear)."""

    clear = True
    reach = math.inf
    __slots__ = ("state",)

    def __init__(self, r, rd):
        self.state = (r, rd)

    def positions(self, tau):
        return self.state


class UnitFlight(DampedOscillator):
    """Free flight of the particle relative to the attachment over one piece: the damped
    oscillator r'' + 2 zeta w r' + w^2 r = p (p = -a_s held; `positions` = DampedOscillator.at);
    guards D - r (stop +1) and D + r (stop -1); the guard protocol of events.py (values, derivs,
    bounds, noise, growth, clear)."""

    reach = math.inf
    __slots__ = ("D", "bounds", "noise", "growth", "clear")

    def __init__(self, w, zeta, r, v, p, D, T, always_bound=False):
        DampedOscillator.__init__(self, w, zeta, r, v, p)
        self.D = D
        ww, a, b = self.ww, self.a, self.b
        amp = math.hypot(a, b)  # |r - r_e| <= amp, |d^j r / dtau^j| <= w^j amp (|lambda| = w, Re lambda <= 0)
        re = abs(p) / ww
        swing = re + amp
        zmax = min(swing, abs(r) + abs(v) * T + 0.5 * ww * amp * T * T)
        n0 = TOLERANCE * (D + noise_size(swing, zmax, D))
        self.growth = w
        self.clear = zmax < D - n0 * (1.0 + w * T)
        if self.clear and not always_bound:
            self.bounds = self.noise = None
            return
        b1 = min(w * amp, abs(v) + ww * amp * T)
        self.bounds = (ww * amp, ww * w * amp, ww * ww * amp)
        self.noise = (n0, TOLERANCE * b1, TOLERANCE * (ww * amp + ww * re), TOLERANCE * ww * w * amp)

    positions = DampedOscillator.at

    def values(self, tau):
        r, v = self.positions(tau)
        D = self.D
        return D - r, -v, D + r, v

    def derivs(self, tau, i):
        r, v = self.positions(tau)
        r2 = self.p - self.ww * r - 2.0 * self.s * v
        r3 = -self.ww * v - 2.0 * self.s * r2
        if i == 0:
            return self.D - r, -v, -r2, -r3
        return self.D + r, v, r2, r3


def _positive(name, value):
    lo, hi = SCALE_RANGE
    if not lo <= check_finite(name, value) <= hi:
        raise ParameterError(name, value, f"it must lie in {lo:g} to {hi:g} (> 0)")
    return float(value)


class DamperUnit(EventDriven):
    """The particle and its stops, driven by the attachment's acceleration (see the module doc)."""

    NAMES = tuple(DEFAULTS)

    def __init__(self, m=DEFAULTS["m"], M_s=DEFAULTS["M_s"], L1=DEFAULTS["L1"], g=DEFAULTS["g"], d=DEFAULTS["d"],
                 e=DEFAULTS["e"], zeta_p=DEFAULTS["zeta_p"], impulse_aware=DEFAULTS["impulse_aware"],
                 r_0=DEFAULTS["r_0"], r_dot_0=DEFAULTS["r_dot_0"], t0=0.0, **materials):
        """materials: impact.MATERIAL_NAMES (restitution from the impact, its forces)."""
        lo, hi = SCALE_RANGE
        m = check_finite("m", m)
        if m < 0.0 or (m != 0.0 and not lo <= m <= hi):
            raise ParameterError("m", m, f"it must be 0 (no particle) or lie in {lo:g} to {hi:g}")
        M_s = _positive("M_s", M_s)
        if not m < M_s:
            raise ParameterError("m", m, f"it must be < M_s = {M_s!r}: a unit coupled through held accelerations "
                                 "amplifies the riding particle's reaction by m/M_s per step (the explicit loop "
                                 "diverges from m = M_s on), and the unit-frame plastic rule would create energy")
        L1, g, d = _positive("L1", L1), _positive("g", g), _positive("d", d)
        e = check_restitution(e)
        zeta_p = check_finite("zeta_p", zeta_p)
        if not 0.0 <= zeta_p < 1.0 or 1.0 - zeta_p * zeta_p < ZETA_GAP:
            raise ParameterError("zeta_p", zeta_p, "it must lie in [0, 1) (underdamped)")
        if impulse_aware not in (MEAN_FORCE, IMPULSE_AWARE) or isinstance(impulse_aware, bool):
            raise ParameterError("impulse_aware", impulse_aware,
                                 "it must be 0 (F_s carries the impulses) or 1 (J_s, t_J carry them)")
        w = math.sqrt(g / L1)
        if not lo <= w <= hi:
            raise ParameterError("g, L1", (g, L1), f"w1 = sqrt(g/L1) = {w!r} lies outside {lo:g} to {hi:g}")
        r_0, r_dot_0 = check_finite("r_0", r_0), check_finite("r_dot_0", r_dot_0)
        if abs(r_0) > d:
            raise ParameterError("r_0", r_0, f"the initial particle position must lie within the stops, "
                                 f"|r_0| <= d = {d!r}")
        self.m, self.M_s, self.L1, self.g, self.d, self.e, self.zeta_p = m, M_s, L1, g, d, e, zeta_p
        self.impulse_aware = int(impulse_aware)
        self.w = w
        unknown = sorted(set(materials) - set(MATERIAL_NAMES))
        if unknown:
            raise TypeError(f"DamperUnit got unexpected keyword arguments {unknown}")
        # what the impacts' contacts did (impact.Tally), with the materials given; the unit does not
        # know the structure's period: contacts are measured against the particle's own
        self.contacts = tally(check_contact(**{**MATERIAL_DEFAULTS, **materials}), 2.0 * math.pi / w)
        self.mu = m * M_s / (m + M_s)  # reduced mass of the impact law
        self._start_clock(check_finite("start time", t0))
        self.r, self.rd = r_0, r_dot_0
        self.dissipated = 0.0
        self.F_s = self.J_s = 0.0
        self.t_J = self.t
        self.impacts_in_step = 0
        self._clearance = d
        self._max_span = 2.0 * math.pi / w
        self.on_impact = None  # optional callback(t, side, J, rd_before, rd_after, loss)

    # ---- public API ------------------------------------------------------------------------

    def set_restitution(self, e):
        self.e = check_restitution(e)

    def advance(self, t_end, a_s):
        """Move to t_end [s] under the attachment's absolute acceleration a_s [m/s2] held; sets
        F_s, J_s, t_J and impacts_in_step of the step."""
        total = t_end + a_s
        if total - total != 0.0:
            check_finite("a_s", a_s)
            check_finite("t_end", t_end)
        self._check_end(t_end)  # in absolute time, before the clock turns to the call's own
        t0 = self._t0 = self.t
        h = t_end - t0
        rd_start = self.rd
        self._sums = [0.0, 0.0, 0.0]  # sum J, sum |J|, sum |J| (t - t0)
        if self.contacts is not None:
            self.contacts.clear()
        impacts = self.impacts
        # Within a call the clock counts the time elapsed since t0 (the unit's physics is
        # autonomous: no forcing phase to keep), as earlier builds did, so their outputs hold
        # bit for bit; a shared absolute clock moves event times by rounding, which impacts amplify.
        self.t = 0.0
        try:
            self._run(h, a_s)
        finally:
            self.t = t0 + self.t
        self.t = t_end
        total_j, abs_j, moment = self._sums
        self.J_s = total_j
        self.t_J = t0 + moment / abs_j if abs_j > 0.0 else t_end
        self.impacts_in_step = self.impacts - impacts
        if h > 0.0:
            change = -self.m * ((self.rd - rd_start) + a_s * h)  # minus the particle's absolute momentum change
            if self.impulse_aware:
                change -= total_j * (1.0 + self.m / self.M_s)
            self.F_s = change / h
        else:
            self.F_s = 0.0
        if self.r - self.r != 0.0 or self.rd - self.rd != 0.0 or self.F_s - self.F_s != 0.0:
            raise ParameterError("a_s", a_s, f"the motion it drives leaves the range of float arithmetic by t = "
                                 f"{self.t!r} s")

    def get_state(self):
        state = {k: getattr(self, k) for k in STATE_KEYS}
        if self.contacts is not None:
            state.update(self.contacts.get_state())
        return state

    def set_state(self, state):
        if not isinstance(state, dict):
            raise ParameterError("state", type(state).__name__, "it must be the dict DamperUnit.get_state writes")
        for key in STATE_KEYS:
            if key not in state:
                raise ParameterError(f"state {key}", None, "the key is missing: a state this model did not write")
            value = state[key]
            if key in _CHOICES:
                if type(value) not in (int, bool) or value not in _CHOICES[key]:
                    raise ParameterError(f"state {key}", value, f"it must be one of {_CHOICES[key]}")
            elif key in ("impacts", "impacts_in_step"):
                if type(value) is not int or value < 0:
                    raise ParameterError(f"state {key}", value, "it must be an integer >= 0")
            else:
                check_finite(f"state {key}", value)
        contacts = None if self.contacts is None else Tally.check_state(state)
        for key in STATE_KEYS:
            setattr(self, key, state[key])
        if contacts is not None:
            self.contacts.set_state(contacts)

    # ---- internals (the hooks of stepping.EventDriven) ---------------------------------------

    def _fastest_from(self):
        return ", the particle's pendulum"

    def _unresolved(self, noise):
        raise ParameterError("d", self.d, f"the motion here reaches {noise / TOLERANCE:.6g} m, so the gap is known "
                             f"to {noise:.3g} only, more than 1/{GAP_RESOLUTION:g} of the clearance: contacts cannot "
                             f"be resolved at t = {self._now()!r} s")

    def _segment(self, a_s, span):
        """Free flight, or riding: the particle rides while pressed into its stop (N constant
        under held a_s) and is released at the piece's start otherwise."""
        if self.mode == STICK:
            ww, d = self.w * self.w, self.d
            press = -self.side * a_s - ww * d  # s r'' the free motion would have at the stop
            if press > TOLERANCE * (abs(a_s) + ww * d):
                return Riding(self.r, self.rd)
            self._switch(FREE, 0)  # released
        return UnitFlight(self.w, self.zeta_p, self.r, self.rd, -a_s, self.d, span)

    def _flight(self, a_s, span):
        return UnitFlight(self.w, self.zeta_p, self.r, self.rd, -a_s, self.d, span, True)

    def _move(self, seg, tau, t_end, a_s, observe):
        self.r, self.rd = seg.positions(tau)
        if tau > 0.0:
            self.fresh = False
        self.t = self.t + tau if t_end is None else t_end  # the call's elapsed time (see advance)

    def _now(self):
        return self._t0 + self.t

    def _snap(self, side):
        self.r = side * self.d  # exactly on the stop (removes rounding-level overlap)

    def _impact(self, side):
        """Newton's two-body law at approach velocity w = r' (see the module doc)."""
        w, e = self.rd, self.e
        if self.contacts is not None:
            e = self.contacts.impact(self._now(), w, self.mu, e, True)
        J, after, loss = relative(w, self.m, self.M_s, self.mu, e, self.impulse_aware)
        if after * side > 0.0:  # m > e M_s: still approaching in the unit's frame: plastic there
            J, after, loss = plastic_in_unit_frame(w, self.m, self.M_s)
        self.rd = after
        self.impacts += 1
        self._book(J, loss)
        if self.on_impact is not None:
            self.on_impact(self._now(), side, J, w, after, loss)

    def _collapse(self, side, counted):
        """End of a chatter sequence (or a touch's rounding-level speed): relative velocity to zero
        by the mode's plastic law; counted as an impact when the contact was one."""
        w = self.rd
        if w == 0.0:
            return
        if counted and self.contacts is not None:
            self.contacts.impact(self._now(), w, self.mu, 0.0, False)
        if self.impulse_aware:
            J, _, loss = relative(w, self.m, self.M_s, self.mu, 0.0, True)
        else:
            J, _, loss = plastic_in_unit_frame(w, self.m, self.M_s)
        self.rd = 0.0
        self._book(J, loss)
        if counted:
            self.impacts += 1
            if self.on_impact is not None:
                self.on_impact(self._now(), side, J, w, 0.0, loss)

    def _book(self, J, loss):
        """Book an impulse J [N s] on the structure at the current time and its loss [J]."""
        self.dissipated += loss
        sums = self._sums
        sums[0] += J
        sums[1] += abs(J)
        sums[2] += abs(J) * (self._now() - self._t0)
