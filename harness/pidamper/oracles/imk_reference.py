"""An independent event-driven reference (a test oracle) for shear buildings of deteriorating
storeys: yielding_reference's DOP853 at rtol 1e-12 (its matrices, damping, P-Delta and particle
damper), with storeys of OpenSees's `IMKBilin` law given to it (`storey`: the law's class, e.g.
pidamper_physics.imk.IMKStorey, checked on its own against OpenSees and by hand: this reference
checks the building, not the law) and its own bookkeeping and event functions.

The law is rate independent and piecewise linear in drift.  The reference finds each storey's next
piece by driving a copy of it: a copy moved far on in the direction of motion lists its events
(the first beyond the storey's drift is the piece's end), two copies moved to points inside the
piece give its force line.  Event functions: that end, every zero of a storey's drift velocity
(where the law may turn), the force with P-Delta reaching zero along an outward backbone steeper
down than P/h (sidesway: the reference stops there), and the drift ratio limit.  At an end the
storey is moved to it, at a turn to where it stands; the law does the rest (reversals,
excursions, deterioration) in its own order.  It imports nothing of pidamper_physics: the law is
the caller's argument, and nothing of the building's event loop (imk_storeys, yielding) is used."""
import numpy as np

from .yielding_reference import Reference


class IMKReference(Reference):
    def __init__(self, m, laws, h, zeta, storey, p_delta=False, g=9.81, damper=None, damping="modal",
                 collapse_drift=0.3):
        """laws: per storey the 21 IMKBilin values (their Ke the storey's stiffness); storey: the law's
        class (storey(values) a storey at rest; move(u), turn(d), clone(), events, u, f, ...)."""
        n = len(m)
        super().__init__(m, [law[0] for law in laws], [0.0] * n, [0.0] * n, h, zeta, p_delta, g, damper, damping)
        self.units = [storey(law) for law in laws]
        self.theta_c = collapse_drift
        self.dirs = [1] * n
        self.lines = [self._line(i) for i in range(n)]
        self.held = [False] * n  # a storey whose line's zero of force with P-Delta was passed, resisted
        self.collapse = None  # (t, storey, "sidesway" / "ultimate" / "drift")
        self.log = []  # (t, storey, the law's event kind, its drift)
        self.changes = []  # (t, storey) of every event that changed a storey's law beyond its position

    def _line(self, i):
        """Storey i's force line (f0, slope: F = f0 + slope drift) ahead in its direction, the drift
        where that piece ends (None: none), whether it follows the backbone."""
        unit, d = self.units[i], self.dirs[i]
        u = unit.u
        far = unit.clone()
        far.events = []
        far.move(u + d * 10.0 * (abs(u) + max(unit.pos.du, unit.neg.du)))
        tiny = 1e-12 * max(abs(u), unit.pos.fy0 / unit.ke)  # (a piece shorter: the next one's start)
        ends = [e for _, e in far.events if d * (e - u) > tiny]
        end = min(ends, key=lambda e: d * (e - u)) if ends else None
        span = abs(end - u) if end is not None else 1.0
        points = []
        for share in (1.0 / 3.0, 2.0 / 3.0):
            c = unit.clone()
            x = u + d * share * span
            points.append((x, c.move(x), c.on_backbone))
        (x1, f1, backbone), (x2, f2, _) = points
        slope = (f2 - f1) / (x2 - x1)
        return f1 - slope * x1, slope, end, backbone

    def _resists(self, i, d, drift):
        """Whether storey i, moving in direction d past `drift`, meets a force with P-Delta pointing
        back anywhere ahead: a copy of it moved outward, sampled at its corners and just past them."""
        unit = self.units[i]
        probe = unit.clone()
        probe.events = []
        far = drift + d * 10.0 * (abs(drift) + max(unit.pos.du, unit.neg.du))
        probe.move(far)
        points = sorted({e for _, e in probe.events if d * (e - drift) > 0.0} | {drift}, key=lambda e: d * e)
        for x in points:
            c = unit.clone()
            force = c.move(x)
            if d * (force - self.kg[i] * x) > 1e-9 * abs(force):
                return True
        return False

    def spring(self, drift):
        return np.array([f0 + s * d for (f0, s, _, _), d in zip(self.lines, drift)]) - self.kg * drift

    def damping_matrix(self):
        if self.damping != "rayleigh-tangent":
            return self.C
        kt = np.array([line[1] for line in self.lines]) - self.kg
        return self.rayleigh[0] * self.M + self.rayleigh[1] * (self.D.T @ np.diag(kt) @ self.D)

    def rhs(self, t, z, ag, F):
        out = super().rhs(t, z, ag, F)
        out[-1] = 0.0  # (the hysteretic energy is not integrated here)
        return out

    @property
    def stopped(self):
        return self.collapse is not None

    def _events_at(self, t, z, ag, F):
        return self._event_functions(self._align(t, z, ag, F))

    def _align(self, t, z, ag, F):
        """Each storey's direction of motion at t (its drift velocity's sign, else its drift
        acceleration's where the velocity is at its rounding level, right after a located turn; 0:
        at rest and staying); a storey that moves against its leg turns now."""
        n = self.n
        rate = self.D @ z[n:2 * n]
        acc = self.D @ self.rhs(t, z, ag, F)[n:2 * n]
        noise = 1e-10 * (1.0 + np.max(np.abs(rate)))
        moving = []
        for i in range(n):
            way = np.sign(rate[i]) if abs(rate[i]) > noise else np.sign(acc[i])
            if way == -self.dirs[i]:
                self._handle(("turn", i, self.dirs[i]), t, z)
            moving.append(way != 0)
        return moving

    def _event_functions(self, moving):
        n = self.n
        fns = []
        if self.damper is not None:
            j, gap = self.damper["floor"], self.damper["d"]
            for sg in (1, -1):
                fns.append(self._fn(lambda t, z, *_, sg=sg: gap - sg * (z[j] - z[2 * n]), ("impact", j, sg)))
        for i in range(n):
            d = self.dirs[i]
            f0, slope, end, _ = self.lines[i]
            if end is not None:
                fns.append(self._fn(lambda t, z, *_, i=i, d=d, a=end: d * (a - (self.D @ z[:n])[i]), ("end", i, d)))
            if moving[i]:
                fns.append(self._fn(lambda t, z, *_, i=i, d=d: d * (self.D @ z[n:2 * n])[i], ("turn", i, d)))
            if slope < self.kg[i] and not self.held[i]:  # outward with no force with P-Delta holding it
                fns.append(self._fn(lambda t, z, *_, i=i, d=d, f0=f0, s=slope, g=self.kg[i]: max(
                    d * (f0 + (s - g) * (self.D @ z[:n])[i]), -d * (self.D @ z[:n])[i]), ("sidesway", i, d)))
            limit = self.theta_c * self.h[i]
            fns.append(self._fn(lambda t, z, *_, i=i, c=limit: c - abs((self.D @ z[:n])[i]), ("drift", i, 0)))
        return fns

    def _handle(self, tag, t, z):
        kind, k, d = tag
        n = self.n
        if kind == "impact":
            super()._handle(tag, t, z)  # (Newton's law; then _decide)
            return
        if kind == "drift":
            self.collapse = (t, k, kind)
            return
        if kind == "sidesway":  # the force with P-Delta is zero: collapse if nothing ahead resists
            if self._resists(k, d, (self.D @ z[:n])[k]):
                self.held[k] = True  # (until the storey's line changes)
            else:
                self.collapse = (t, k, kind)
            return
        unit = self.units[k]
        before = len(unit.events) if unit.events is not None else 0
        unit.events = unit.events if unit.events is not None else []
        law = _law(unit)
        if kind == "end":
            unit.move(self.lines[k][2])
        else:
            drift = (self.D @ z[:n])[k]
            if d * (drift - unit.u) > 0.0:
                unit.move(drift)
            unit.turn(-d)  # (what the next move would do first)
            self.dirs[k] = -d
        if _law(unit) != law:
            self.changes.append((t, k))
        for note, u in unit.events[before:]:
            self.log.append((t, k, note, u))
        if unit.failure in (3, 4, 5) and self.collapse is None and any(
                note.startswith("failure") and note[-1] in "345" for note, _ in unit.events[before:]):
            self.collapse = (t, k, "ultimate")
        self.lines[k] = self._line(k)
        self.held[k] = False
        self.events.append((t, kind, k))

    def _decide(self, z, t):
        """After an impact: a storey whose drift velocity now opposes its leg turns."""
        n = self.n
        rate = self.D @ z[n:2 * n]
        for i in range(n):
            if self.dirs[i] * rate[i] < 0.0:
                self._handle(("turn", i, self.dirs[i]), t, z)


def _law(unit):
    """What of an IMKStorey's state is more than its position on its current line."""
    return unit.k, unit.e_crossing, unit.failure, unit.on_backbone, unit.pos.snapshot(), unit.neg.snapshot()
