"""Bilinear storeys with kinematic hardening, P-Delta and the collapse limit of a yielding building.

Storey k (stiffness k [N/m], yield force Fy [N], post-yield stiffness ratio b, 0 <= b < 1) has the
force of OpenSees `Steel01` without isotropic hardening: a linear spring b k in parallel with an
elastic-perfectly-plastic spring of stiffness (1 - b) k and yield force (1 - b) Fy,

    F(delta) = b k delta + f_p,    f_p = (1 - b) k (delta - delta_p),    |f_p| <= (1 - b) Fy,

delta the storey drift, delta_p the EPP spring's plastic drift (the drift at which f_p = 0).  In a
regime s the storey is linear, F = kt delta + c:

    s = 0 (elastic):        kt = k,    c = -(1 - b) k delta_p       (delta_p held)
    s = +1 / -1 (yielding): kt = b k,  c = s (1 - b) Fy            (delta_p = delta - s Fy / k)

P-Delta adds the geometric stiffness -P / h to every regime's kt (P the gravity load the storey
carries, h its height): `b k - P / h < 0` is a negative tangent.  Fy = 0 is an elastic storey.
Plain Python (math): this ships inside the FMU.
"""
from .modal import SECULAR
from .refusals import SCALE_RANGE, ParameterError, check_finite

ELASTIC = 0
#: default post-yield stiffness ratio, and the drift ratio at which a yielding building collapses
HARDENING = 0.02
COLLAPSE_DRIFT = 0.10
__all__ = ["Storeys", "check_storeys", "check_damping", "gravity_loads", "ELASTIC", "HARDENING", "COLLAPSE_DRIFT",
           "GRAVITY"]
#: default gravitational acceleration of the gravity loads [m/s2]
GRAVITY = 9.81


#: a yielding tangent b k - P/h within FLAT k of zero is zero: the modes cannot tell a mechanism
#: that stiff from one of no stiffness at all (its eigenvalue is below the secular level)
FLAT = 1e-8


class Storeys:
    """The storey laws of an N-storey building: stiffnesses k [N/m], yield forces Fy [N] (0:
    elastic), hardening ratios b, geometric stiffnesses P/h [N/m] (0 without P-Delta).  A storey
    whose yielding tangent b k - P/h lies within FLAT k of zero is `flat`: its b is taken as P/(h k),
    its yielding tangent as exactly 0."""

    def __init__(self, stiffnesses, yield_forces, ratios, geometric):
        self.k = list(stiffnesses)
        self.Fy = list(yield_forces)
        self.geometric = list(geometric)
        self.flat = [abs(b * k - g) <= FLAT * k for b, k, g in zip(ratios, self.k, self.geometric)]
        self.b = [g / k if flat else b for b, k, g, flat in zip(ratios, self.k, self.geometric, self.flat)]
        self.n = len(self.k)
        #: elastic range of the EPP spring: |delta - delta_p| <= Fy / k
        self.reach = [fy / k for fy, k in zip(self.Fy, self.k)]
        self.yields = [fy > 0.0 for fy in self.Fy]

    @property
    def any_yield(self):
        return any(self.yields)

    def tangent(self, i, s):
        """kt of storey i in regime s [N/m] (the geometric stiffness included)."""
        if s == ELASTIC:
            return self.k[i] - self.geometric[i]
        return 0.0 if self.flat[i] else self.b[i] * self.k[i] - self.geometric[i]

    def offset(self, i, s, dp):
        """c of storey i in regime s with plastic drift dp [N]."""
        if s == ELASTIC:
            return -(1.0 - self.b[i]) * self.k[i] * dp if dp else 0.0
        return s * (1.0 - self.b[i]) * self.Fy[i]

    def force(self, i, drift, dp):
        """The bilinear spring's force of storey i [N] (P-Delta not included)."""
        k, b = self.k[i], self.b[i]
        return b * k * drift + (1.0 - b) * k * (drift - dp)

    def strain(self, i, drift, dp):
        """Strain energy of storey i [J]: its two springs and the P-Delta potential."""
        k, b = self.k[i], self.b[i]
        e = drift - dp
        return 0.5 * (b * k * drift * drift + (1.0 - b) * k * e * e - self.geometric[i] * drift * drift)


def gravity_loads(masses, g, extra=None):
    """P_k = g (the masses of floors k..N, plus `extra` = (floor index, mass) carried there) [N]."""
    n = len(masses)
    carried = list(masses)
    if extra is not None:
        carried[extra[0]] += extra[1]
    return [g * sum(carried[k:]) for k in range(n)]


def check_storeys(stiffnesses, yield_forces, ratios, heights, masses, p_delta, g, collapse_drift, extra=None):
    """The Storeys of a building once its yielding parameters are checked: a ParameterError names
    the storey's value and the rule (storey[k].Fy >= 0, 0 <= storey[k].b < 1, p_delta 0/1, g > 0,
    collapse_drift in (0, 1], and with P-Delta every storey's k - P/h > 0: the elastic building
    must stand).  `extra`: (floor index, mass) of a damper's particle carried on that floor."""
    n = len(stiffnesses)
    for k in range(n):
        fy = check_finite(f"storey[{k + 1}].Fy", yield_forces[k])
        if fy < 0.0:
            raise ParameterError(f"storey[{k + 1}].Fy", fy, "it must be >= 0 (0 = an elastic storey)")
        reach, (lo, hi) = fy / stiffnesses[k], SCALE_RANGE
        if fy and not lo <= reach <= hi:
            raise ParameterError(f"storey[{k + 1}].Fy", fy, f"its yield drift Fy/k = {reach!r} m (storey[{k + 1}].k = "
                                 f"{stiffnesses[k]!r} N/m) must lie in {lo:g} to {hi:g} m, where float arithmetic "
                                 "holds its squares and products (0 = an elastic storey)")
        b = check_finite(f"storey[{k + 1}].b", ratios[k])
        if not 0.0 <= b < 1.0:
            raise ParameterError(f"storey[{k + 1}].b", b, "it must lie in [0, 1) (0 = elastic-perfectly-plastic)")
    if p_delta not in (0, 1) or isinstance(p_delta, float) and not p_delta.is_integer():
        raise ParameterError("p_delta", p_delta, "it must be 0 (off) or 1 (on)")
    theta = check_finite("collapse_drift", collapse_drift)
    if not 0.0 < theta <= 1.0:
        raise ParameterError("collapse_drift", theta, "it must lie in (0, 1] (a storey drift ratio)")
    geometric = [0.0] * n
    if p_delta:
        g = check_finite("g", g)
        if not g > 0.0:
            raise ParameterError("g", g, "it must be > 0 (P-Delta's gravity loads)")
        loads = gravity_loads(masses, g, extra)
        geometric = [p / h for p, h in zip(loads, heights)]
        for k in range(n):
            if not stiffnesses[k] - geometric[k] > 0.0:
                raise ParameterError(f"storey[{k + 1}].k", stiffnesses[k],
                                     f"with P-Delta it must exceed P/h = {geometric[k]:.6g} N/m (gravity load "
                                     f"{loads[k]:.6g} N over storey[{k + 1}].h = {heights[k]!r} m): the elastic "
                                     "building would not stand")
    return Storeys(stiffnesses, yield_forces, ratios, geometric)


def check_damping(storeys, zeta, spread=1.0):
    """Refuse a yielding storey of (nearly) zero tangent whose damping the modes cannot resolve:
    its yielding regime's mechanism would have a double zero eigenvalue and no modes.  The
    mechanism's own eigenvalue is at least 2 zeta w_1, and must stand clear of the secular level
    SECULAR w_n of the fastest mode (modal.py): zeta_s >= 50 SECULAR w_n / w_1, `spread` = w_n / w_1
    of the elastic building."""
    least = 50.0 * SECULAR * spread
    if zeta >= least:
        return
    for i in range(storeys.n):
        if storeys.yields[i] and storeys.flat[i]:
            raise ParameterError(f"storey[{i + 1}].b", storeys.b[i], "a yielding storey of zero tangent stiffness "
                                 f"(b k - P/h = 0) needs damping the modes can resolve: set zeta_s >= {least:.3g} "
                                 f"(now {zeta!r}) or b > 0")


YIELD, UNLOAD, COLLAPSE = 0, 1, 2  # the kinds of a storey guard
#: a building keeps the modes of at most this many regimes (deteriorating storeys rarely revisit one)
KEPT_REGIMES = 256


class Hysteresis:
    """The storeys' state of a yielding building: each storey's regime (0 elastic, +1 / -1
    yielding) and plastic drift delta_p [m], the hysteretic energy [J], the events so far and the
    collapse latch; what depends on it (tangent stiffness, held forces, guards, energy).

    law: Storeys; heights [m]; theta_c: the collapse drift ratio; w [rad/s]: the frequency that
    scales a drift velocity guard into metres (the elastic building's fastest)."""

    def __init__(self, law, heights, theta_c, w):
        self.law, self.heights, self.theta_c, self.w = law, list(heights), theta_c, w
        self.n = n = law.n
        self.regime = [ELASTIC] * n
        self.dp = [0.0] * n
        self.hysteretic = 0.0
        self.events = 0
        self.collapsed, self.collapse_reason, self.collapse_time = 0, "", 0.0
        self.log = None  # a list to record (t, storey index, kind) of every event in, if given
        self.version = 0  # counts the changes of regime and dp: what is derived from them is kept per version
        self._guards = None  # (version, guards())

    # ---- the regime's linear system -----------------------------------------------------

    def key(self):
        """What the regime's linear system depends on (a dict key): the storeys' regimes."""
        return tuple(self.regime)

    def pristine(self):
        """No storey has yielded: the storeys are the elastic building's."""
        return not any(self.regime) and not any(self.dp)

    def tangents(self):
        """Per storey its tangent stiffness [N/m] in the current regime, P-Delta included."""
        law = self.law
        return [law.tangent(i, s) for i, s in enumerate(self.regime)]

    def stiffness(self):
        """K_t [N/m] (n x n, nested lists) of the current regime, P-Delta included."""
        n = self.n
        kt = self.tangents() + [0.0]
        K = [[0.0] * n for _ in range(n)]
        for i in range(n):
            K[i][i] = kt[i] + kt[i + 1]
            if i + 1 < n:
                K[i][i + 1] = K[i + 1][i] = -kt[i + 1]
        return K

    def held(self):
        """Per floor the storeys' held forces on it [N] in the current regime: -c_i + c_(i+1)."""
        law, n, regime, dp = self.law, self.n, self.regime, self.dp
        c = [law.offset(i, regime[i], dp[i]) for i in range(n)] + [0.0]
        return [c[i + 1] - c[i] for i in range(n)]

    def restoring(self, drifts):
        """Per floor the storeys' force on it [N] (springs and P-Delta; dashpots not included)."""
        law, n, regime, dp = self.law, self.n, self.regime, self.dp
        f = [law.tangent(i, regime[i]) * drifts[i] + law.offset(i, regime[i], dp[i]) for i in range(n)]
        return [f[i] - (f[i + 1] if i + 1 < n else 0.0) for i in range(n)]

    # ---- values -----------------------------------------------------------------------------

    def plastic(self, i, drift):
        """delta_p of storey i at the drift (a yielding storey's moves with it)."""
        s = self.regime[i]
        return self.dp[i] if s == ELASTIC else drift - s * self.law.reach[i]

    def forces(self, drifts):
        """The bilinear springs' forces [N] (P-Delta not included)."""
        return [self.law.force(i, drifts[i], self.plastic(i, drifts[i])) for i in range(self.n)]

    def zero_force_drifts(self, drifts):
        """Per storey the drift at which its spring's force is zero [m]: (1 - b) delta_p."""
        return [(1.0 - self.law.b[i]) * self.plastic(i, drifts[i]) for i in range(self.n)]

    def strain(self, drifts):
        """Strain energy of the storeys [J] (P-Delta potential included), summed storey 1 first."""
        law, e = self.law, 0.0
        for i in range(self.n):
            d = drifts[i]
            e += law.strain(i, d, self.plastic(i, d))
        return e

    # ---- events ---------------------------------------------------------------------------

    def guards(self):
        """[(storey, order, coef, const, kind)]: guard = const + coef delta^(order) >= 0, in metres
        (yield surfaces and collapse limits on the drift, order 0; a yielding storey's drift
        velocity over w, order 1); kept until the regimes or plastic drifts change (do not change it)."""
        kept = self._guards
        if kept is None or kept[0] != self.version:
            kept = self._guards = (self.version, self._make_guards())
        return kept[1]

    def _make_guards(self):
        law, out = self.law, []
        for i in range(self.n):
            s = self.regime[i]
            if law.yields[i]:
                if s == ELASTIC:
                    for sg in (1, -1):  # reach - sg (delta - dp) >= 0
                        out.append((i, 0, -sg, law.reach[i] + sg * self.dp[i], YIELD))
                else:
                    out.append((i, 1, s / self.w, 0.0, UNLOAD))
            limit = self.theta_c * self.heights[i]
            out.append((i, 0, -1.0, limit, COLLAPSE))
            out.append((i, 0, 1.0, limit, COLLAPSE))
        return out

    def piece(self, d0, d1):
        """Book the hysteretic energy of a piece from drifts d0 to d1: (1 - b) Fy s (d1 - d0) of
        each yielding storey [J]; returns it."""
        law, e, regime = self.law, 0.0, self.regime
        for i in range(self.n):
            s = regime[i]
            if s != ELASTIC:
                e += (1.0 - law.b[i]) * law.Fy[i] * s * (d1[i] - d0[i])
        self.hysteretic += e
        return e

    def event(self, guard, drifts, t):
        """Apply a guard's zero at time t [s]; returns the collapse reason, or None."""
        i, _, coef, _, kind = guard
        self.events += 1
        self.version += 1
        if self.log is not None:
            self.log.append((t, i, kind))
        if kind == YIELD:
            self.regime[i] = 1 if coef < 0.0 else -1
        elif kind == UNLOAD:
            self.dp[i] = drifts[i] - self.regime[i] * self.law.reach[i]
            self.regime[i] = ELASTIC
        else:
            return self.collapse(t, f"storey {i + 1} reached the drift ratio collapse_drift = {self.theta_c!r}")
        return None

    def collapse(self, t, reason):
        self.collapsed, self.collapse_reason, self.collapse_time = 1, reason, t
        return reason

    def decide(self, drifts, rates):
        """Regimes after a velocity jump (drift velocities `rates` [m/s]): a yielding storey whose
        drift velocity reverses unloads; an elastic storey on its yield surface moving outward
        yields.  Returns whether a regime changed."""
        law, changed = self.law, False
        for i in range(self.n):
            if not law.yields[i]:
                continue
            s = self.regime[i]
            if s != ELASTIC and s * rates[i] < 0.0:
                self.dp[i] = drifts[i] - s * law.reach[i]
                self.regime[i] = ELASTIC
                changed = True
            elif s == ELASTIC:
                e = drifts[i] - self.dp[i]
                if abs(e) >= law.reach[i] * (1.0 - 1e-12) and e * rates[i] > 0.0:
                    self.regime[i] = 1 if e > 0.0 else -1
                    changed = True
        if changed:
            self.version += 1
        return changed

    # ---- state ----------------------------------------------------------------------------

    _KEYS = ("regime", "dp", "hysteretic", "events", "collapsed", "collapse_reason", "collapse_time")

    def get_state(self):
        return {"regime": list(self.regime), "dp": list(self.dp), "hysteretic": self.hysteretic,
                "events": self.events, "collapsed": self.collapsed, "collapse_reason": self.collapse_reason,
                "collapse_time": self.collapse_time}

    def set_state(self, state):
        """Restore get_state's dict; anything else is refused naming the key (ParameterError)."""
        if not isinstance(state, dict) or set(state) != set(self._KEYS):
            raise ParameterError("state storeys", state, f"the dict Hysteresis.get_state writes (keys {self._KEYS})")
        regime, dp = state["regime"], state["dp"]
        if not isinstance(regime, list) or len(regime) != self.n or any(s not in (-1, 0, 1) for s in regime):
            raise ParameterError("state storeys regime", regime, f"a list of {self.n} values in -1, 0, 1")
        if not isinstance(dp, list) or len(dp) != self.n:
            raise ParameterError("state storeys dp", dp, f"a list of {self.n} numbers")
        dp = [check_finite(f"state storeys dp[{k}]", v) for k, v in enumerate(dp)]
        for key in ("hysteretic", "collapse_time"):
            check_finite(f"state storeys {key}", state[key])
        if state["collapsed"] not in (0, 1) or type(state["events"]) is not int or state["events"] < 0:
            raise ParameterError("state storeys collapsed, events", (state["collapsed"], state["events"]),
                                 "collapsed 0 or 1, events an integer >= 0")
        self.regime, self.dp = [int(s) for s in regime], dp
        self.version += 1
        self.hysteretic, self.events = float(state["hysteretic"]), state["events"]
        self.collapsed, self.collapse_reason = int(state["collapsed"]), str(state["collapse_reason"])
        self.collapse_time = float(state["collapse_time"])
