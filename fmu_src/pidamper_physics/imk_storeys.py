"""Deteriorating storeys in a building's event loop: one imk.IMKStorey per storey, exact.

Between events every storey moves along one linear piece of its law: its force (P-Delta not
included) is F = f + k_s (delta - u), (u, f) the storey's point at its last event (its anchor) and
k_s the piece's slope (the unloading stiffness off the backbone, the backbone's slope along it), so
the building is linear (K_t from k_s - P/h) and moves in closed form.  The storey's own law places
its next events as drifts (`IMKStorey.start` / `resume` plan the piece to the first of them, in
its own arithmetic); the building locates them as guards, each in metres:

- ahead: the drift of the piece's event in the leg's direction d (touch, kink, crossing of zero
  force, ultimate drift, residual onset): d (a - delta) >= 0;
- behind: off the backbone, the event of the other direction along the same line: d (delta - b) >= 0;
- reversal: where leaving in direction -d would change the storey at once (on the backbone: the
  unloading stiffness deteriorates; at a point of zero force: an excursion ends), the drift
  velocity's reversal d delta' / w >= 0;
- instability: along a piece whose slope is below P/h (post-capping, the residual plateau, an
  unloading line whose stiffness deteriorated below it), the first drift where the storey moves
  outward and its restoring force with P-Delta, F - P delta / h, no longer holds it back, if
  nothing ahead along its path (the law's own moves of a copy) would: gravity carries it on, the
  building collapses (sidesway);
- collapse: the drift ratio collapse_drift (a guard far beyond the physics' collapse).

At a guard's zero the storey takes its piece to the event in its own arithmetic (so a storey's
history is the law's own, whatever the building's rounding), then goes on in its direction (or
reverses); a storey that passes its ultimate drift on the side it moves to collapses the building.
Energy: the work done on storey i is e_acc (the law's, exact along a line) and its strain energy is
F^2 / (2 Ke) (P-Delta's potential -P delta^2 / 2h beside it); hysteretic = sum e_acc - F^2 / 2Ke.
Plain Python (math): this ships inside the FMU.
"""
import math

from .imk import LOST, LOST_NEG, LOST_POS, PARAMETERS, IMKStorey, check_imk
from .refusals import ParameterError, check_finite
from .storeys import COLLAPSE, Hysteresis, Storeys

AHEAD, BEHIND, REVERSE, UNSTABLE = 3, 4, 5, 6  # the kinds of a deteriorating storey's guards
_INF = math.inf


def imk_law(tables, geometric):
    """storeys.Storeys of the storeys' elastic range (what the elastic track of a yielding building
    reads: Ke, the lesser yield force of the two sides, P/h)."""
    return Storeys([t[0] for t in tables], [min(t[4], t[10]) for t in tables], [0.0] * len(tables), geometric)


#: IMKBilin's parameters a building storey takes from its own table (Ke is the storey's stiffness
#: storey[k].k, Fy_pos its yield force storey[k].Fy), with their defaults: drifts [m] for a 3 m storey
#: (capping at 2 % drift past yield, zero force 10 % beyond, ultimate drift 13 %), force ratios,
#: reference energies Lamda Fy_pos [m] and exponents; Fy_neg 0 means Fy_pos
IMK_DEFAULTS = {"Fy_neg": 0.0, "dp_pos": 0.06, "dpc_pos": 0.3, "du_pos": 0.4, "FmaxFy_pos": 1.1, "FresFy_pos": 0.4,
                "dp_neg": 0.06, "dpc_neg": 0.3, "du_neg": 0.4, "FmaxFy_neg": 1.1, "FresFy_neg": 0.4,
                "LamdaS": 3.0, "LamdaC": 3.0, "LamdaK": 3.0, "Cs": 1.0, "Cc": 1.0, "Ck": 1.0, "D_pos": 1.0, "D_neg": 1.0}


def check_storey_law(law):
    """The storeys' law as an int (0 bilinear, 1 IMKBilin), or a ParameterError naming storey_law."""
    if law not in (0, 1) or isinstance(law, bool) or isinstance(law, float) and not law.is_integer():
        raise ParameterError("storey_law", law, "it must be 0 (bilinear, as OpenSees Steel01) or 1 (deteriorating, "
                             "as OpenSees IMKBilin)")
    return int(law)


def imk_tables(stiffnesses, yield_forces, entries):
    """Per storey the 21 IMKBilin values (imk.PARAMETERS' order, checked) of storeys with
    stiffnesses Ke [N/m], yield forces Fy_pos [N] and `entries`: per storey a dict of the other
    parameters by IMKBilin's names (IMK_DEFAULTS fills what is missing; None: all defaults)."""
    n = len(stiffnesses)
    entries = list(entries or []) + [None] * (n - len(entries or []))
    tables = []
    for k in range(n):
        if not check_finite(f"storey[{k + 1}].Fy", yield_forces[k]) > 0.0:
            raise ParameterError(f"storey[{k + 1}].Fy", yield_forces[k], "it must be > 0: with storey_law = 1 every "
                                 "storey is an IMKBilin storey of this yield force (Fy_pos)")
        given = dict(entries[k] or {})
        unknown = sorted(set(given) - set(IMK_DEFAULTS))
        if unknown:
            raise ParameterError(f"storey[{k + 1}]", unknown, f"IMKBilin parameters among {sorted(IMK_DEFAULTS)} (Ke "
                                 f"is storey[{k + 1}].k, Fy_pos storey[{k + 1}].Fy)")
        p = {**IMK_DEFAULTS, **given, "Ke": stiffnesses[k], "Fy_pos": yield_forces[k]}
        if not p["Fy_neg"]:
            p["Fy_neg"] = p["Fy_pos"]
        tables.append([p[key] for key in PARAMETERS])
    return check_tables(tables, n)


def check_tables(tables, n):
    """n storeys' IMKBilin parameter lists (imk.PARAMETERS' order), each checked (imk.check_imk,
    naming storey[k]); a ParameterError names what is wrong."""
    if not isinstance(tables, (list, tuple)) or len(tables) != n:
        raise ParameterError("storey IMK tables", tables, f"a list of {n} IMKBilin parameter lists, storey 1 first")
    return [check_imk(list(t), f"storey[{k + 1}]") for k, t in enumerate(tables)]


class IMKHysteresis(Hysteresis):
    """The deteriorating storeys' state of a building (see the module doc), with storeys.Hysteresis's
    interface.  tables: per storey the 21 IMKBilin values; law: imk_law's Storeys; heights [m];
    theta_c: collapse drift ratio; w [rad/s]: scales a drift velocity guard into metres."""

    def __init__(self, law, tables, heights, theta_c, w):
        Hysteresis.__init__(self, law, heights, theta_c, w)
        self.units = [IMKStorey(t, f"storey[{k + 1}]") for k, t in enumerate(tables)]
        self.ke = [t[0] for t in tables]
        self.legs = [None] * self.n  # per storey (d, plan, slope, ahead, behind, reverse, unstable)
        for i in range(self.n):
            self._leg(i, 1, self.units[i].start(1))

    # ---- a storey's leg ---------------------------------------------------------------------

    def _leg(self, i, d, plan):
        """Storey i goes on in direction d along `plan` (IMKStorey.start / resume's): its slope and
        the drifts of its guards."""
        unit = self.units[i]
        if plan is None:  # lost: no force, no slope, no events
            self.legs[i] = (d, None, 0.0, None, None, False, None)
            return
        slope = _slope(unit, plan)
        ahead = unit.u + d * plan[0] if plan[0] < _INF else None
        probe = unit.clone()
        probe.events = []  # what the law does on leaving in -d at once (an excursion of no energy too)
        before = probe.snapshot()
        back = probe.start(-d)
        behind, reverse = None, True
        if back is not None and not probe.events and probe.snapshot() == before and _slope(probe, back) == slope:
            reverse = False
            behind = unit.u - d * back[0] if back[0] < _INF else None
        self.legs[i] = (d, plan, slope, ahead, behind, reverse, self._unstable(i, d, plan, slope))

    def _unstable(self, i, d, plan, slope):
        """Along a piece of slope < P/h (the storey's restoring force with P-Delta, F - P delta / h,
        falls as it moves on): the first drift z of the piece where the storey moves outward (d z >= 0)
        and that force no longer holds it back (d (F - P z / h) <= 0), the storey's drift if it is
        past it, if nothing ahead of z along the storey's path turns it back (_resists); else None."""
        unit, g = self.units[i], self.law.geometric[i]
        if slope >= g:
            return None
        zero = (slope * unit.u - unit.f) / (slope - g)  # f + slope (z - u) - g z = 0
        onset = zero if d * zero > 0.0 else 0.0
        if d * (onset - unit.u) <= 0.0:
            onset = unit.u  # already past it: _lost collapses the building at once
        elif plan[0] < _INF and d * (onset - unit.u) > plan[0]:
            return None
        return None if _resists(unit, d, onset, g) else onset

    # ---- the regime's linear system -------------------------------------------------------

    def key(self):
        return tuple(leg[2] for leg in self.legs)

    def pristine(self):
        """No storey has left its elastic line through the origin (the elastic building's state)."""
        return all(u.failure == 0 and u.u == 0.0 and u.f == 0.0 and u.k == u.ke and u.e_acc == 0.0
                   for u in self.units)

    def tangents(self):
        """Per storey the slope of its piece less P/h [N/m]."""
        g = self.law.geometric
        return [self.legs[i][2] - g[i] for i in range(self.n)]

    def held(self):
        n, units, legs = self.n, self.units, self.legs
        c = [units[i].f - legs[i][2] * units[i].u for i in range(n)] + [0.0]
        return [c[i + 1] - c[i] for i in range(n)]

    def restoring(self, drifts):
        g = self.law.geometric
        f = [self._force(i, drifts[i]) - g[i] * drifts[i] for i in range(self.n)] + [0.0]
        return [f[i] - f[i + 1] for i in range(self.n)]

    # ---- values ---------------------------------------------------------------------------

    def _force(self, i, drift):
        unit = self.units[i]
        return unit.f + self.legs[i][2] * (drift - unit.u)

    def _hysteretic(self, i, drift):
        """Work done on storey i to the drift less its strain energy F^2 / 2Ke [J]."""
        unit = self.units[i]
        f = self._force(i, drift)
        return unit.e_acc + 0.5 * (unit.f + f) * (drift - unit.u) - 0.5 * f * f / self.ke[i]

    def forces(self, drifts):
        return [self._force(i, drifts[i]) for i in range(self.n)]

    def zero_force_drifts(self, drifts):
        """Per storey the drift at zero force along its unloading line from where it stands [m]."""
        out = []
        for i in range(self.n):
            k = self.units[i].k
            out.append(drifts[i] - self._force(i, drifts[i]) / k if k > 0.0 else drifts[i])
        return out

    def strain(self, drifts):
        g, e = self.law.geometric, 0.0
        for i in range(self.n):
            f, d = self._force(i, drifts[i]), drifts[i]
            e += 0.5 * (f * f / self.ke[i] - g[i] * d * d)
        return e

    def piece(self, d0, d1):
        e = 0.0
        for i in range(self.n):
            if d1[i] != d0[i]:
                e += self._hysteretic(i, d1[i]) - self._hysteretic(i, d0[i])
        self.hysteretic += e
        return e

    # ---- events ---------------------------------------------------------------------------

    def _make_guards(self):
        out = []
        for i in range(self.n):
            d, plan, slope, ahead, behind, reverse, unstable = self.legs[i]
            if ahead is not None:
                out.append((i, 0, -float(d), d * ahead, AHEAD))
            if behind is not None:
                out.append((i, 0, float(d), -d * behind, BEHIND))
            if reverse:
                out.append((i, 1, d / self.w, 0.0, REVERSE))
            if unstable is not None:
                out.append((i, 0, -float(d), d * unstable, UNSTABLE))
            limit = self.theta_c * self.heights[i]
            out.append((i, 0, -1.0, limit, COLLAPSE))
            out.append((i, 0, 1.0, limit, COLLAPSE))
        return out

    def event(self, guard, drifts, t):
        i, kind = guard[0], guard[4]
        self.events += 1
        self.version += 1
        if self.log is not None:
            self.log.append((t, i, kind))
        if kind == COLLAPSE:
            return self.collapse(t, f"storey {i + 1} reached the drift ratio collapse_drift = {self.theta_c!r}")
        if kind == UNSTABLE:
            return self.collapse(t, f"storey {i + 1} lost its lateral strength under P-Delta (sidesway) at drift "
                                 f"{drifts[i]!r} m")
        before = self._hysteretic(i, drifts[i])
        unit, d, plan = self.units[i], self.legs[i][0], self.legs[i][1]
        if kind == AHEAD:
            unit.take(d, plan)
            self._leg(i, d, unit.resume(d))
            self._catch_up(i, drifts[i])
        elif kind == BEHIND:
            unit.take(-d, unit.start(-d))
            self._leg(i, -d, unit.resume(-d))
            self._catch_up(i, drifts[i])
        else:
            self._reverse(i, drifts[i])
        self.hysteretic += self._hysteretic(i, drifts[i]) - before
        return self._lost(i, t)

    def _catch_up(self, i, drift):
        """Take at once storey i's next events that lie within rounding (1e-12 of the drift, or of
        the yield drift) of the drift it has reached: they happen at this instant."""
        unit = self.units[i]
        near = 1e-12 * max(abs(drift), unit.pos.fy0 / unit.ke)
        while True:
            d, plan, ahead = self.legs[i][0], self.legs[i][1], self.legs[i][3]
            if ahead is None or d * (ahead - drift) > near:
                return
            unit.take(d, plan)
            self._leg(i, d, unit.resume(d))

    def _reverse(self, i, drift):
        """Storey i, moving in its leg's direction d, turns at the drift: it follows its piece there,
        then starts a leg in -d."""
        unit, d = self.units[i], self.legs[i][0]
        if d * (drift - unit.u) > 0.0:
            unit.move(drift)
        self._leg(i, -d, unit.start(-d))

    def _lost(self, i, t):
        """Collapse if storey i has lost its strength on the side it moves to (past its ultimate
        drift, or exhausted); None otherwise."""
        unit, d = self.units[i], self.legs[i][0]
        if unit.failure == LOST or unit.failure == (LOST_POS if d > 0 else LOST_NEG):
            side = unit.pos if d > 0 else unit.neg
            why = (f"passed its ultimate drift du = {side.du!r} m" if d * unit.u >= side.du else
                   "lost its strength (its force fell to zero: cyclic deterioration exhausted it)")
            return self.collapse(t, f"storey {i + 1} {why} at drift {unit.u!r} m")
        if self.legs[i][6] == unit.u:
            return self.collapse(t, f"storey {i + 1} lost its lateral strength under P-Delta (sidesway) at drift "
                                 f"{unit.u!r} m")
        return None

    def decide(self, drifts, rates):
        """After a velocity jump: a storey whose drift velocity now opposes its leg and that would
        change on turning (a reversal guard) turns at once.  Returns whether one did."""
        changed = False
        for i in range(self.n):
            leg = self.legs[i]
            if leg[5] and leg[0] * rates[i] < 0.0:
                before = self._hysteretic(i, drifts[i])
                self._reverse(i, drifts[i])
                self.hysteretic += self._hysteretic(i, drifts[i]) - before
                changed = True
        if changed:
            self.version += 1
        return changed

    # ---- state ----------------------------------------------------------------------------

    def get_state(self):
        state = Hysteresis.get_state(self)
        state["regime"] = [leg[0] for leg in self.legs]  # each storey's direction
        state["dp"] = [list(u.snapshot()[:8]) + [list(u.pos.snapshot()), list(u.neg.snapshot())] for u in self.units]
        state["plans"] = [None if leg[1] is None else list(leg[1]) for leg in self.legs]
        return state

    def set_state(self, state):
        if not isinstance(state, dict) or "plans" not in state:
            raise ParameterError("state storeys", state, "the dict IMKHysteresis.get_state writes")
        state = dict(state)
        plans, dirs, units = state.pop("plans"), state["regime"], state["dp"]
        n = self.n
        if not (isinstance(plans, list) and isinstance(units, list) and len(plans) == len(units) == n):
            raise ParameterError("state storeys plans, dp", (plans, units), f"{n} storeys' plans and states")
        state["dp"] = [0.0] * n
        Hysteresis.set_state(self, state)  # checks the directions and the bookkeeping
        for i in range(n):
            _restore(self.units[i], units[i], i)
            plan = plans[i]
            if plan is not None:
                plan = (float(plan[0]), str(plan[1]), float(plan[2]), bool(plan[3]), float(plan[4]))
            self._leg(i, int(dirs[i]) or 1, plan)


def _resists(unit, d, zero, g):
    """Whether a storey moving on in direction d past the drift `zero` meets a restoring force with
    P-Delta (d (F - g delta) > 0) anywhere along its path (the force is linear between the law's
    events, so at one of them): copies of it moved there, in the law's arithmetic."""
    probe = unit.clone()
    probe.events = []
    probe._crossed_at = unit.u  # (what happens here at once is done)
    probe.move(zero + d * 10.0 * (abs(zero) + max(unit.pos.du, unit.neg.du)))
    for _, x in probe.events:
        if d * (x - zero) > 0.0:
            copy = unit.clone()
            copy._crossed_at = unit.u
            if d * (copy.move(x) - g * x) > 0.0:
                return True
    return False


def _slope(unit, plan):
    """The storey's slope along a planned piece [N/m]: the backbone's if it follows it, else k."""
    return plan[4] if plan[3] else unit.k


def _restore(unit, values, i):
    """Put IMKStorey.snapshot()'s values (as get_state lists them) back into the storey."""
    name = f"state storeys dp[{i}]"
    if not (isinstance(values, list) and len(values) == 10):
        raise ParameterError(name, values, "a storey's state as IMKHysteresis.get_state writes it")
    for key, value in zip(("u", "f", "k", "e_acc", "e_crossing"), values[:5]):
        setattr(unit, key, check_finite(f"{name}.{key}", value))
    unit.failure, unit.on_backbone = int(values[5]), bool(values[6])
    unit._crossed_at = None if values[7] is None else float(values[7])
    for side, saved in ((unit.pos, values[8]), (unit.neg, values[9])):
        for key, value in zip(type(side).__slots__, saved):
            setattr(side, key, value)
