"""Exact running maxima of a building's response, located on its closed-form pieces.

Per storey k the peak |drift ratio| (x_k - x_(k-1)) / h_k, per floor the peak |absolute velocity|
v_k + v_g and the peak |absolute acceleration| x_k'' + a_g (its regular part: an impact's or an
impulse's velocity jump is an impulse, not an acceleration; both one-sided values at the jump
count, as the end of one piece and the start of the next).  v_g is the ground's velocity, the
integral of the held a_g from rest at the start.

Each piece the motion takes is a closed form f(s), 0 <= s <= tau, whose value and first two
derivatives the piece gives at any s (`derivatives`), with a bound B3 on |f'''| over the piece
(`bounds`).  Between two points a < b, Taylor's theorem bounds f from either end:

    sigma f(a + s) <= sigma (f + f' s + f'' s^2 / 2)(a) + B3 s^3 / 6      (and backwards from b),

so the interval holds nothing above the running maximum once the better of the two cubics stays
below it (`_cubic_max`); else a Newton step on f' (the vertex of the nearer end's quadratic)
proposes the next point, or the interval is halved.  Near a maximum Newton lands on it, and its
negative curvature then clears the neighbourhood on both sides, so a new peak costs a few
evaluations.  First of all, a piece whose quantities all stay below their maxima by the first-order
bound |f(s)| <= |f(0)| + s max|f'| is done with its start alone (most pieces, once the motion stops
growing): no higher derivatives, no search.  A quantity that the forward cubic from the piece's
start clears over the whole piece is not evaluated again, nor one that a later point clears for the
rest of it.  Accepted excess: REL of the maximum (a peak is exact to that, far below the motion's own
rounding).
Plain Python (math): this ships inside the FMU.
"""
import math

from .params import ParameterError, check_finite

REL = 1e-13  # relative excess over the running maximum an interval may hide
_TINY = 1e-300
#: a first-order bound clears a piece when, times this, it stays at or below the maximum: room for
#: the rounding of the values a search of the piece would compute
_SURE = 1.0 + 1e-12
_MAX_POINTS = 400  # evaluations per piece before the rest of it is accepted (never reached in practice)


def _cubic_max(f, f1, f2, b3, length):
    """Max over 0 <= s <= length of |f + f1 s + f2 s^2/2| + b3 s^3/6 (both signs)."""
    best = 0.0
    for sg in (1.0, -1.0):
        c0, c1, c2 = sg * f, sg * f1, sg * f2
        top = c0 if c0 > 0.0 else 0.0
        end = c0 + length * (c1 + length * (0.5 * c2 + length * b3 / 6.0))
        if end > top:
            top = end
        # the local maximum of the cubic: the smaller root of c1 + c2 s + b3 s^2 / 2
        if b3 > 0.0:
            disc = c2 * c2 - 2.0 * b3 * c1
            if disc >= 0.0:
                s = (-c2 - math.sqrt(disc)) / b3
                if 0.0 < s < length:
                    top = max(top, c0 + s * (c1 + s * (0.5 * c2 + s * b3 / 6.0)))
        elif c2 < 0.0 < c1:
            s = -c1 / c2
            if s < length:
                top = max(top, c0 + 0.5 * c1 * s)
        if top > best:
            best = top
    return best


class Piece:
    """A closed-form piece [0, tau] of a building's motion as Peaks searches it (the base of each
    model's pieces): start() -> (x, v, acc, jerk, snap) of the floors at its start, first() -> (x, v,
    acc) as start() gives them, bounds(floor_order, drift_order) -> (per floor the bounds of
    |x^(floor_order)| and |x^(floor_order + 1)|, per storey the bound of its drift's derivative of
    order drift_order) over the piece, derivatives(s, {k: (lo, hi)}) -> {k: [x_k^(lo), ...,
    x_k^(hi-1)]} at s; every value relative to the ground, floor 1 first."""

    __slots__ = ()

    def start(self):
        raise NotImplementedError

    def first(self):
        raise NotImplementedError

    def bounds(self, floor_order, drift_order):
        raise NotImplementedError

    def derivatives(self, s, floors):
        raise NotImplementedError


class Peaks:
    """Running maxima of a building of storey heights `heights` [m] (storey 1 first); see the
    module doc.  `drift`, `velocity`, `acceleration`: per storey / floor [1, m/s, m/s2];
    `v_ground` [m/s]: the ground's velocity at the state's time."""

    def __init__(self, heights):
        self.n = n = len(heights)
        self.inv_h = [1.0 / h for h in heights]
        self.drift, self.velocity, self.acceleration = [0.0] * n, [0.0] * n, [0.0] * n
        self.v_ground = 0.0
        self._begun = None  # take()'s: the piece's start() when _stays_below has it

    # ---- state ------------------------------------------------------------------------

    def get_state(self):
        return {"drift": list(self.drift), "velocity": list(self.velocity), "acceleration": list(self.acceleration),
                "v_ground": self.v_ground}

    def set_state(self, state):
        """Restore get_state's dict; anything else is refused naming the key (ParameterError)."""
        keys = {"drift", "velocity", "acceleration", "v_ground"}
        if not isinstance(state, dict) or set(state) != keys:
            raise ParameterError("state peaks", state, f"the dict Peaks.get_state writes (keys {sorted(keys)})")
        lists = []
        for key in ("drift", "velocity", "acceleration"):
            values = state[key]
            if not isinstance(values, list) or len(values) != self.n:
                raise ParameterError(f"state peaks {key}", values, f"a list of {self.n} numbers")
            lists.append([check_finite(f"state peaks {key}[{k}]", v) for k, v in enumerate(values)])
        v_ground = check_finite("state peaks v_ground", state["v_ground"])
        self.drift, self.velocity, self.acceleration = lists
        self.v_ground = v_ground

    # ---- one piece ----------------------------------------------------------------------

    def take(self, piece, tau, a_g):
        """Raise the maxima over a piece of length tau >= 0 [s] under the held ground acceleration
        a_g [m/s2], then move the ground's velocity on.  `piece` gives, relative to the ground,
        start() -> (x, v, acc, jerk, snap) of the floors at its start (floor 1 first; extra entries
        ignored), bounds(4, 3) -> (per floor the bounds of |x_k^(4)| and |x_k^(5)| over the piece, per
        storey the bound of the third derivative of its drift x_k - x_(k-1)), and
        derivatives(s, {k: (lo, hi)}) -> {k: [x_k^(lo), ..., x_k^(hi-1)]} at s.  A quantity that the forward cubic from the start clears over the whole
        piece is not searched."""
        n, ih = self.n, self.inv_h
        vg = self.v_ground
        self._begun = None
        if tau > 0.0 and self._stays_below(piece, tau, a_g):
            self._begun = None
            self.v_ground = vg + a_g * tau
            return
        begun = self._begun  # piece.start(), if _stays_below asked for it
        self._begun = None
        x, v, acc, jerk, snap = piece.start() if begun is None else begun
        b, drift = piece.bounds(4, 3)
        active, values = [], []
        xb = vb = ab = 0.0  # the floor below's (the ground's: unused)
        for k in range(n):
            bk = b[k]
            h = ih[k]
            xk, vk, ak, jk, sk = x[k], v[k], acc[k], jerk[k], snap[k]
            bound = drift[k]
            active.append((0, k, bound * h))
            if k:
                values.append(((xk - xb) * h, (vk - vb) * h, (ak - ab) * h))
            else:
                values.append((xk * h, vk * h, ak * h))
            active.append((1, k, bk[0]))  # the third derivative of v is x^(4), of a is x^(5)
            values.append((vk + vg, ak + a_g, jk))
            active.append((2, k, bk[1]))
            values.append((ak + a_g, jk, sk))
            xb, vb, ab = xk, vk, ak
        for i in range(len(active)):
            q, y = active[i], values[i]
            self._raise(q[0], q[1], y[0])
        active, values = self._open(active, values, tau)
        if active and tau > 0.0:
            self._scan(piece, active, values, tau, a_g)
        self.v_ground = vg + a_g * tau

    def _stays_below(self, piece, tau, a_g):
        """Raise the maxima to the piece's start; then whether every quantity stays at or below its
        maximum over the piece (with room _SURE for the rounding of the values a search would
        compute), so that no search could raise it: by the first-order bound |f(s)| <= |f(0)| +
        s max|f'|, or where that fails by the second-order one |f(s)| <= max(|f(0)|, |f(0) +
        s f'(0)|) + s^2/2 max|f''| (for an acceleration from piece.start(), kept for take()).
        `piece` gives first() -> (x, v, acc) as start() gives them and bounds(m, d) -> (per floor the
        bounds of |x^(m)| and |x^(m+1)|, per storey the bound of its drift's derivative of order d)
        over the piece."""
        n, ih, vg = self.n, self.inv_h, self.v_ground
        drift, velocity, acceleration = self.drift, self.velocity, self.acceleration
        x, v, acc = piece.first()
        b, db = piece.bounds(2, 1)
        more = begun = None  # bounds(3, 2) and start(), asked for when a second order needs them
        below = True
        xb = vb = 0.0
        half = 0.5 * tau * tau
        for k in range(n):
            h = ih[k]
            xk, vk, ak = x[k], v[k], acc[k]
            d = (xk - xb) * h if k else xk * h
            u = vk + vg
            w = ak + a_g
            self._raise(0, k, d)
            self._raise(1, k, u)
            self._raise(2, k, w)
            if below:
                bk = b[k]
                slope, curve = bk[0], bk[1]
                below = (abs(w) + tau * curve) * _SURE <= acceleration[k]
                if not below:  # second order: the jerk at the start, the bound of x^(4)
                    if begun is None:
                        begun = piece.start()
                    if more is None:
                        more = piece.bounds(3, 2)
                    end = abs(w + tau * begun[3][k])
                    below = ((abs(w) if abs(w) >= end else end) + half * more[0][k][1]) * _SURE <= acceleration[k]
                if below:
                    end = abs(u + a_g * tau)  # |v_k + v_g| moves by at most tau max|x''| beside the ground's own
                    if ((abs(u) if abs(u) >= end else end) + tau * slope) * _SURE > velocity[k]:
                        end = abs(u + tau * w)  # ... or by tau (x_k'' + a_g) and s^2/2 max|x'''|
                        below = ((abs(u) if abs(u) >= end else end) + half * curve) * _SURE <= velocity[k]
                if below and (abs(d) + tau * db[k] * h) * _SURE > drift[k]:
                    if more is None:
                        more = piece.bounds(3, 2)
                    rate = (vk - vb) * h if k else vk * h
                    end = abs(d + tau * rate)
                    below = ((abs(d) if abs(d) >= end else end) + half * more[1][k] * h) * _SURE <= drift[k]
            xb, vb = xk, vk
        self._begun = begun
        return below

    def _raise(self, kind, k, f):
        """Raise the maximum of quantity (kind, k) to |f| if that is above it."""
        top = self.drift if kind == 0 else self.velocity if kind == 1 else self.acceleration
        old = top[k]
        if abs(f) > old:
            top[k] = abs(f)

    #: the orders of the derivatives of x_k each kind needs, (lo, hi): drift 0..2, v_abs 1..3, a_abs 2..4
    _LEVELS = ((0, 3), (1, 4), (2, 5))

    def _need(self, active):
        """{floor: (lo, hi)}: the orders of each floor's derivatives the active quantities need."""
        need = {}
        for kind, k, _ in active:
            lo, hi = self._LEVELS[kind]
            for floor in range(k - 1 if kind == 0 and k else k, k + 1):  # a drift needs the floor below too
                old = need.get(floor)
                need[floor] = (lo, hi) if old is None else (min(old[0], lo), max(old[1], hi))
        return need

    def _values(self, piece, s, a_g, active, need):
        """(f, f', f'') of each active quantity at s of the piece (need: _need(active)); raises the
        maxima."""
        d = piece.derivatives(s, need)
        ih, vg = self.inv_h, self.v_ground + a_g * s
        out = []
        for q in active:
            kind, k = q[0], q[1]
            lo = need[k][0]
            dk = d[k]
            if kind == 0:
                h = ih[k]
                u0, u1, u2 = dk[0 - lo], dk[1 - lo], dk[2 - lo]
                if k:
                    dl, ll = d[k - 1], need[k - 1][0]
                    l0, l1, l2 = dl[0 - ll], dl[1 - ll], dl[2 - ll]
                    f, f1, f2 = (u0 - l0) * h, (u1 - l1) * h, (u2 - l2) * h
                else:
                    f, f1, f2 = u0 * h, u1 * h, u2 * h
            elif kind == 1:
                u1, u2, u3 = dk[1 - lo], dk[2 - lo], dk[3 - lo]
                f, f1, f2 = u1 + vg, u2 + a_g, u3
            else:
                u2, u3, u4 = dk[2 - lo], dk[3 - lo], dk[4 - lo]
                f, f1, f2 = u2 + a_g, u3, u4
            self._raise(kind, k, f)
            out.append((f, f1, f2))
        return out

    def _scan(self, piece, active, fa, tau, a_g):
        """Certify [0, tau] interval by interval (see the module doc); fa: the active quantities'
        (f, f', f'') at 0.  At each certified point the quantities that its forward cubic alone
        clears for the rest of the piece drop out, so the search goes on with those that may
        still peak."""
        a, b = 0.0, tau
        need = self._need(active)
        for _ in range(_MAX_POINTS):
            if not active:
                return
            fb = self._values(piece, b, a_g, active, need)
            length = b - a
            worst = self._worst(active, fa, fb, length)
            if worst < 0 or length <= 4e-16 * tau:  # certified (or down to rounding of the clock)
                if b >= tau:
                    return
                a, b = b, tau
                kept, fa = self._open(active, fb, tau - a)
                if len(kept) != len(active):  # fewer quantities: fewer derivatives to ask for
                    need = self._need(kept)
                active = kept
                continue
            b = a + _next(fa[worst], fb[worst], length)
        # never reached in practice: what is left is accepted (its ends are counted)

    def _open(self, active, values, rest):
        """The quantities (and their values) that the forward cubic from here does not clear over
        the `rest` of the piece."""
        kept, kept_values = [], []
        for i in range(len(active)):
            q, y = active[i], values[i]
            b3 = q[2]
            top = self._top(q[0], q[1])
            f, f1, f2 = y[0], y[1], y[2]
            if abs(f) + rest * (abs(f1) + rest * (0.5 * abs(f2) + rest * b3 / 6.0)) <= top:
                continue
            if _cubic_max(f, f1, f2, b3, rest) <= top:
                continue
            kept.append(q)
            kept_values.append(y)
        return kept, kept_values

    def _top(self, kind, k):
        """The maximum of quantity (kind, k) with the excess an interval may hide."""
        top = self.drift if kind == 0 else self.velocity if kind == 1 else self.acceleration
        value = top[k]
        return value * (1.0 + REL) + _TINY

    def _worst(self, active, fa, fb, length):
        """Index of the active quantity the interval's two cubics leave most above its maximum, or -1."""
        worst, excess = -1, 0.0
        for i in range(len(active)):
            q, y = active[i], fa[i]
            b3 = q[2]
            top = self._top(q[0], q[1])
            f, f1, f2 = y[0], y[1], y[2]
            if abs(f) + length * (abs(f1) + length * (0.5 * abs(f2) + length * b3 / 6.0)) <= top:
                continue  # far below its maximum: the crude bound settles it
            yb = fb[i]
            over = min(_cubic_max(f, f1, f2, b3, length), _cubic_max(yb[0], -yb[1], yb[2], b3, length)) - top
            if over > excess:
                worst, excess = i, over
        return worst


def _next(ya, yb, length):
    """Offset from a of the next point, well inside (0, length): a Newton step on f' from the end
    whose quadratic turns towards an extremum of |f| inside, else the midpoint.  (A step that lands
    on the other end is no new point: that end came from the same step.)"""
    lo, hi = 1e-6 * length, (1.0 - 1e-6) * length
    f, f1, f2 = yb[0], yb[1], yb[2]
    if f2 != 0.0 and f * f2 < 0.0:
        s = length + -f1 / f2  # the vertex, measured from b
        if lo < s < hi:
            return s
    f, f1, f2 = ya[0], ya[1], ya[2]
    if f2 != 0.0 and f * f2 < 0.0:
        s = -f1 / f2  # the vertex, measured from a
        if lo < s < hi:
            return s
    return 0.5 * length
