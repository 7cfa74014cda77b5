"""Deteriorating storeys: the modified Ibarra-Medina-Krawinkler bilinear law, exact in drift.

The law is OpenSees's `IMKBilin` as openseespy 3.7.1.2 runs it (the Nov-2022 rewrite by Ichinohe and
Elkady, `setTrialStrain` unchanged to v3.7.1), with deformation = storey drift u [m] and force =
storey shear F [N].  Its 21 parameters, in the command's order (`PARAMETERS`):

    Ke                  elastic stiffness [N/m]
    dp, dpc, du         per side (_pos, _neg): drift from yield to capping, from capping down to zero
                        force along the post-capping line, and the ultimate drift (absolute) [m]
    Fy, FmaxFy, FresFy  per side: effective yield force [N], capping and residual force over Fy
    LamdaS/C/K          reference energies Eref = Lamda Fy_pos of the basic strength, post-capping
                        strength and unloading stiffness [m] (Fy_pos for both sides, as the source)
    Cs, Cc, Ck          their exponents;  D_pos, D_neg: the sides' factors on beta_S and beta_C

The material is rate independent and piecewise linear in u: a monotone drift move is a sequence of
linear pieces whose ends are events, each located exactly (`IMKStorey.move`):
  - touch: the unloading/reloading line (slope K) reaches the backbone of the direction of motion;
  - kink: a corner of that backbone (capping point, either edge of the residual plateau);
  - cross: the force on an unloading/reloading line crosses zero, which ends an excursion: the
    backbone of the direction of motion deteriorates by the energy of the excursion just ended;
  - ultimate: the drift reaches du in the direction of motion (that side's strength goes to 0);
  - residual: the drift passes the residual onset of the current backbone;
and a move that starts against the force while on the backbone is a reversal: the unloading
stiffness deteriorates by the energy since the last crossing (less the elastic energy F^2 / 2K).

These are the step -> 0 limits of the source's per-step rules, so OpenSees converges to this law
as its strain step falls (at second order, tests/test_imk.py): the source takes a reversal at its
last sample and an excursion's energies at the start of the step whose trial force changes sign,
integrates the energy by the trapezoid and tests the residual force and the loss of strength at its
samples.  Two of its sample rules are read as the limit would have them: a force equal to the
residual counts only while it follows the plateau over a positive drift (not where a reloading line
meets the plateau's corner, which the source's rotation of the pre-capping slope constructs), and
one crossing is one excursion (the source counts a second when a sample lands on zero force), a
reloading line that reaches the backbone exactly where a move ends has not yet reached it, and
along a backbone of zero force towards zero drift, where the source's rules fire at every sample
(that side lost, a reversal, an excursion), their limit applies once where that stretch begins.
Where the source computes pow() of a negative base with a non-integer exponent (it returns NaN
stress), beta is 0 here.  Otherwise the source's rules are kept, also where they differ from
Lignos & Krawinkler (2011): an excursion that exhausts the remaining reference energy makes beta
negative, clamped to 0 (no collapse, no deterioration after it); the post-capping slope deteriorates
with the basic strength; after the residual is reached every unloading from the backbone takes
0.5 Ke; the ultimate drift removes one side's strength and leaves the other at its residual.

Failure states (`failure`): 0 elastic, 1 on or past a backbone, 2 residual reached, 3 positive side
lost, 4 negative side lost, 5 both lost (or a beta above 1: F = 0 from then on).
Plain Python (math): this ships inside the FMU.
"""
import math

from .refusals import ParameterError, check_finite

PARAMETERS = ("Ke", "dp_pos", "dpc_pos", "du_pos", "Fy_pos", "FmaxFy_pos", "FresFy_pos",
              "dp_neg", "dpc_neg", "du_neg", "Fy_neg", "FmaxFy_neg", "FresFy_neg",
              "LamdaS", "LamdaC", "LamdaK", "Cs", "Cc", "Ck", "D_pos", "D_neg")

ELASTIC, BACKBONE, RESIDUAL, LOST_POS, LOST_NEG, LOST = 0, 1, 2, 3, 4, 5
#: a piece along the residual plateau shorter than this fraction of the yield drift is the rounding
#: of a reloading line meeting the plateau's corner, not a stay on the plateau
_CORNER = 1e-9
_INF = math.inf

END, KINK, TOUCH, CROSS, ULTIMATE, RES = "end", "kink", "touch", "cross", "ultimate", "residual"


def check_imk(values, name="storey"):
    """The 21 IMKBilin parameters (PARAMETERS' order) as floats, each refused with the rule it breaks,
    naming `name`'s parameter (ParameterError)."""
    if len(values) != len(PARAMETERS):
        raise ParameterError(name, values, f"{len(PARAMETERS)} numbers in IMKBilin's order {PARAMETERS}")
    p = {key: check_finite(f"{name}.{key}", v) for key, v in zip(PARAMETERS, values)}

    def refuse(key, rule):
        raise ParameterError(f"{name}.{key}", p[key], rule)

    if p["Ke"] <= 0.0:
        refuse("Ke", "the elastic stiffness must be > 0")
    for side in ("pos", "neg"):
        for key in ("dp", "dpc", "Fy"):
            if p[f"{key}_{side}"] <= 0.0:
                refuse(f"{key}_{side}", "it must be > 0 (both sides are given as positive magnitudes)")
        if p[f"FmaxFy_{side}"] < 1.0:
            refuse(f"FmaxFy_{side}", "the capping force must not be below the yield force (FmaxFy >= 1)")
        if not 0.0 <= p[f"FresFy_{side}"] <= 1.0:
            refuse(f"FresFy_{side}", "the residual force is a fraction of the yield force, 0 <= FresFy <= 1")
        capping = p[f"Fy_{side}"] / p["Ke"] + p[f"dp_{side}"]
        if p[f"du_{side}"] < capping:
            refuse(f"du_{side}", f"the ultimate drift must not come before the capping drift Fy/Ke + dp = {capping!r}")
    for key in ("LamdaS", "LamdaC", "LamdaK", "Cs", "Cc", "Ck"):
        if p[key] <= 0.0:
            refuse(key, "it must be > 0 (a large Lamda is a law without deterioration)")
    for key in ("D_pos", "D_neg"):
        if p[key] < 0.0:
            refuse(key, "it must be >= 0")
    return [p[key] for key in PARAMETERS]


def _div(a, b):
    """a / b as IEEE division (C): +-inf, or nan, for b == 0 (the source divides so)."""
    if b == 0.0:
        if a == 0.0 or a != a:
            return math.nan
        return _INF if (math.copysign(1.0, a) > 0.0) == (math.copysign(1.0, b) > 0.0) else -_INF
    return a / b


def _first_event(candidate):
    """Sort key of a piece's candidate ends (length, kind): the shortest, an event before the end
    of the move at the same length (a move that ends exactly at a crossing of zero force crosses)."""
    return candidate[0], candidate[1] == END


def _beta(energy, reference, c):
    """(energy / reference)^c, the source's deterioration factor (its clamping is the caller's); 0
    where C's pow() of a negative base and a non-integer exponent gives nan."""
    base = _div(energy, reference)
    if base != base or (base < 0.0 and c != math.floor(c)):
        return 0.0
    try:
        return math.pow(base, c)
    except (OverflowError, ValueError):  # a huge base, or 0 to a negative power
        return _INF


class _Side:
    """One side's current backbone, its values signed (s = +1 the positive side, -1 the negative):
    yield force fy, pre-capping slope kp, post-capping slope kpc (<= 0), capping point (ucap, fcap),
    residual force fres; fy0 and kpc0 as built."""

    __slots__ = ("s", "fy0", "kpc0", "fy", "kp", "kpc", "ucap", "fcap", "fres", "du", "d")

    def __init__(self, s, ke, dp, dpc, du, fy, fmax, fres, d):
        self.s, self.du, self.d = s, du, d
        uy = fy / ke
        fcap = fmax * fy
        self.kp = (fcap - fy) / dp
        self.kpc0 = fcap / dpc
        self.kpc = -self.kpc0
        self.fy0 = fy
        self.fy, self.ucap, self.fcap, self.fres = s * fy, s * (uy + dp), s * fcap, s * fy * fres

    def clone(self):
        other = object.__new__(_Side)
        for key in _Side.__slots__:
            setattr(other, key, getattr(self, key))
        return other

    def snapshot(self):
        return tuple(getattr(self, key) for key in _Side.__slots__)

    def force(self, u):
        """The backbone's force at u (both slopes extended past zero, the residual a floor)."""
        s = self.s
        kb = self.kp if s * (u - self.ucap) < 0.0 else self.kpc
        f = self.fcap + (u - self.ucap) * kb
        return self.fres if s * (f - self.fres) < 0.0 else f

    def slope(self, u):
        """The backbone's slope at a drift u that is no corner (0 on the residual floor)."""
        s = self.s
        kb = self.kp if s * (u - self.ucap) < 0.0 else self.kpc
        f = self.fcap + (u - self.ucap) * kb
        return 0.0 if s * (f - self.fres) < 0.0 else kb

    def corners(self):
        """The drifts where the backbone changes slope: the capping point and the plateau's edges."""
        out = [self.ucap]
        if self.kp != 0.0:
            out.append(self.ucap + (self.fres - self.fcap) / self.kp)
        if self.kpc != 0.0:
            out.append(self.ucap + (self.fres - self.fcap) / self.kpc)
        return out

    def residual_onset(self):
        """The drift where the post-capping line reaches the residual force (None on a flat one)."""
        if self.kpc == 0.0:
            return None
        return _div(self.fres - self.fcap + self.kpc * self.ucap, self.kpc)

    def deteriorate(self, beta_s, beta_c, ke, k, u, f):
        """The source's update of this side at the end of an excursion (at drift u, force f, the
        unloading stiffness k): strength and slopes by beta_s, the capping line by beta_c, then the
        pre-capping slope rotated about the capping point so that the reloading line from (u, f)
        meets the backbone where it leaves the residual."""
        s, d = self.s, self.d
        fcap_project = self.fcap - self.kpc * self.ucap
        self.fy *= 1.0 - beta_s * d
        self.kp *= 1.0 - beta_s * d
        fcap_project *= 1.0 - beta_c * d
        uy = self.fy / ke
        self.kpc = 0.0 if s * (self.fy - self.fres) < 0.0 else \
            _div(-self.kpc0 * (self.fy - self.fres), s * self.fy0 - self.fres)
        fy_project = self.fy - self.kp * uy
        self.ucap = 0.0 if self.kp <= self.kpc else _div(fcap_project - fy_project, self.kp - self.kpc)
        self.fcap = fy_project + self.kp * self.ucap
        candidate = _div(self.fcap - self.fres, self.ucap - u - _div(self.fres - f, k))
        if s * (self.fcap - self.fres) < 0.0:  # the whole backbone at the residual
            self.fy = self.fcap = self.fres
            self.kp = self.kpc = 0.0
            self.ucap = 0.0
        elif candidate > 0.0 and self.kp > candidate:
            self.kp = candidate


class IMKStorey:
    """One storey of the law (see the module doc): `move(u)` takes the drift to u [m] and returns the
    force [N]; `events`, if a list, gets (kind, u) of every event.  State: drift u, force f,
    unloading stiffness k, the work done on it e_acc [J] and e_acc at the last crossing, failure."""

    def __init__(self, values, name="storey", events=None):
        (ke, dp_p, dpc_p, du_p, fy_p, fmax_p, fres_p, dp_n, dpc_n, du_n, fy_n, fmax_n, fres_n,
         lam_s, lam_c, lam_k, self.cs, self.cc, self.ck, d_p, d_n) = check_imk(values, name)
        self.ke = ke
        self.pos = _Side(1.0, ke, dp_p, dpc_p, du_p, fy_p, fmax_p, fres_p, d_p)
        self.neg = _Side(-1.0, ke, dp_n, dpc_n, du_n, fy_n, fmax_n, fres_n, d_n)
        self.ref_s, self.ref_c, self.ref_k = lam_s * fy_p, lam_c * fy_p, lam_k * fy_p
        self.u = self.f = 0.0
        self.k = ke
        self.e_acc = self.e_crossing = 0.0
        self.failure = ELASTIC
        self.on_backbone = False
        self.events = events
        self._crossed_at = None  # the drift of an excursion that ended the last move

    # ---- the backbone of the direction of motion ----------------------------------------

    def backbone(self, d, u):
        """The force of the backbone of direction d (+1 / -1) at u, as the failure state leaves it."""
        side, other = (self.pos, LOST_NEG) if d > 0 else (self.neg, LOST_POS)
        if self.failure == (LOST_POS if d > 0 else LOST_NEG):
            return 0.0
        if self.failure == other:
            return side.fres
        return side.force(u)

    def _ahead(self, d):
        """(distance to the backbone's next corner in direction d, its slope until there)."""
        if self.failure in (LOST_POS, LOST_NEG):
            return _INF, 0.0
        side, u = (self.pos if d > 0 else self.neg), self.u
        near = _INF
        for c in side.corners():
            gap = d * (c - u)
            if 0.0 < gap < near:
                near = gap
        return near, side.slope(u + d * (0.5 * near if near < _INF else max(1.0, abs(u))))  # inside it

    # ---- events ---------------------------------------------------------------------------

    def _note(self, kind):
        if self.events is not None:
            self.events.append((kind, self.u))

    def _reverse(self):
        """A reversal on the backbone: the unloading stiffness deteriorates; True if beta_K > 1."""
        f, k = self.f, self.k
        elastic = 0.5 * _div(f, k) * f
        beta = _beta(self.e_acc - self.e_crossing - elastic, self.ref_k - (self.e_acc - elastic), self.ck)
        self.k = k * (1.0 - min(max(beta, 0.0), 1.0))
        if self.failure > BACKBONE:
            self.k = 0.5 * self.ke
        self.on_backbone = False
        self._note("reversal")
        return beta > 1.0

    def _excursion(self, d):
        """The end of an excursion (zero force on an unloading/reloading line, moving in direction
        d): the backbone of direction d deteriorates; True if beta_S or beta_C > 1."""
        energy = max(0.0, self.e_acc - self.e_crossing)
        beta_s = _beta(energy, self.ref_s - self.e_acc, self.cs)
        beta_c = _beta(energy, self.ref_c - self.e_acc, self.cc)
        self.e_crossing = self.e_acc
        side = self.pos if d > 0 else self.neg
        side.deteriorate(min(max(beta_s, 0.0), 1.0), min(max(beta_c, 0.0), 1.0), self.ke, self.k, self.u, self.f)
        self._note("excursion")
        return beta_s > 1.0 or beta_c > 1.0

    def _flags(self, d, exhausted=False, plateau=False):
        """The source's residual and failure flags at the current point; `plateau`: the piece just
        taken followed a flat backbone over a positive drift."""
        u, f, pos, neg = self.u, self.f, self.pos, self.neg
        onset = pos.residual_onset()
        res_pos = plateau and f == pos.fres if onset is None else u >= onset
        onset = neg.residual_onset()
        res_neg = plateau and f == neg.fres if onset is None else u <= onset
        lost_pos = d > 0 and (u >= pos.du or (self.on_backbone and f <= 0.0 and plateau))
        lost_neg = d < 0 and (u <= -neg.du or (self.on_backbone and f >= 0.0 and plateau))
        state = self.failure
        if exhausted:
            self.f, state = 0.0, LOST
        elif lost_pos:
            self.f, state = 0.0, LOST if state == LOST_NEG else LOST_POS
        elif lost_neg:
            self.f, state = 0.0, LOST if state == LOST_POS else LOST_NEG
        elif state < RESIDUAL and (res_pos or res_neg):
            state = RESIDUAL
        elif state == ELASTIC and self.on_backbone:
            state = BACKBONE
        if state != self.failure:
            self.failure = state
            self._note(f"failure {state}")

    def _zero_backbone(self, d):
        """Following a backbone of zero force towards zero drift (u d <= 0): the source's rules fire
        at every strain step there (that side lost, a reversal from the backbone, an excursion, the
        force capped back onto the backbone); their limit is applied once, at the start (the
        reversal gives 0.5 Ke, the side lost, the excursion's energy 0).  False if it was already."""
        lost = LOST_POS if d > 0 else LOST_NEG
        if self.failure in (lost, LOST) and self.k == 0.5 * self.ke and self.e_crossing == self.e_acc:
            return False
        self._flags(d, plateau=True)
        if self.failure != LOST and self._reverse():
            self._flags(d, exhausted=True)
        if self.failure != LOST and self._excursion(d):
            self._flags(d, exhausted=True)
        self.on_backbone = True
        return True

    def _to_residual(self, d):
        """Distance to the residual onset of the backbone of direction d (inf if none ahead)."""
        if self.failure >= RESIDUAL:
            return _INF
        onset = (self.pos if d > 0 else self.neg).residual_onset()
        if onset is None or d * (onset - self.u) <= 0.0:
            return _INF
        return d * (onset - self.u)

    # ---- a move ---------------------------------------------------------------------------

    def turn(self, d):
        """Start moving in direction d (+1 / -1) where the storey stands: a reversal if it is on the
        backbone and d goes against its force (or from zero force towards zero drift); then `k` is
        the slope the move leaves along.  (`move` does it first.)"""
        if self.failure != LOST and self.on_backbone and (self.f * d < 0.0 or (self.f == 0.0 and self.u * d <= 0.0)):
            if self._reverse():
                self.failure = LOST
                self.f = 0.0
                self._note(f"failure {LOST}")

    def move(self, target):
        """Take the drift monotonically to `target` [m] through every event on the way; the force
        there [N].  (A path with turns is a sequence of moves, one per leg.)"""
        target = float(target)
        if target == self.u:
            return self.f
        d = 1 if target > self.u else -1
        self.turn(d)
        crossed = self._crossed_at == self.u  # an excursion that ended the last move is this crossing
        self._crossed_at = None
        while self.failure != LOST:
            if not self.on_backbone and self.f == 0.0 and self.failure > ELASTIC and not crossed:
                if self._excursion(d):
                    self._flags(d, exhausted=True)
                    continue
                crossed = True
                self._crossed_at = self.u  # (a move ending here: the next one starts past this crossing)
            if self.u == target:
                return self.f
            self._crossed_at = None
            self._piece(d, target)
            crossed = self._crossed_at == self.u
        self.u, self.f = target, 0.0
        return self.f

    # ---- a leg in pieces (a building's storey: its events located by the building) ------

    def start(self, d):
        """Begin a leg in direction d where the storey stands, as `move` does (a reversal, an
        excursion, whatever happens at once); the plan of its first piece (`_plan`, towards
        d * infinity), or None if the storey is lost.  `take(d, plan)` takes it to its event."""
        self.turn(d)
        return self.resume(d)

    def resume(self, d):
        """Go on in direction d from an event of the leg (`move`'s loop, without a turn): what
        happens at once there, then the plan of the next piece (None if the storey is lost)."""
        crossed = self._crossed_at == self.u
        far = d * _INF
        while self.failure != LOST:
            if not self.on_backbone and self.f == 0.0 and self.failure > ELASTIC and not crossed:
                if self._excursion(d):
                    self._flags(d, exhausted=True)
                    continue
            self._crossed_at = None
            plan = self._plan(d, far)
            if plan is not None:
                return plan
            crossed = False
        self.f = 0.0
        return None

    def take(self, d, plan):
        """Take a planned piece to its event (its length must be finite)."""
        self._crossed_at = None
        self._take(d, self.u + d * plan[0], plan)

    def clone(self):
        """An independent copy of the storey's state (events not recorded)."""
        other = object.__new__(IMKStorey)
        for key in ("ke", "cs", "cc", "ck", "ref_s", "ref_c", "ref_k", "u", "f", "k", "e_acc", "e_crossing",
                    "failure", "on_backbone", "_crossed_at"):
            setattr(other, key, getattr(self, key))
        other.pos, other.neg, other.events = self.pos.clone(), self.neg.clone(), None
        return other

    def snapshot(self):
        """The storey's whole state as a tuple (for comparison)."""
        return (self.u, self.f, self.k, self.e_acc, self.e_crossing, self.failure, self.on_backbone, self._crossed_at,
                self.pos.snapshot(), self.neg.snapshot())

    def _piece(self, d, target):
        """One linear piece from the current point towards `target`, to its first event."""
        plan = self._plan(d, target)
        if plan is not None:
            self._take(d, target, plan)

    def _plan(self, d, target):
        """The piece `_piece` takes next towards `target` (d its direction): (length [m], kind,
        reach = d (target - u), follow: whether it follows the backbone, kb: the backbone's slope
        ahead).  What happens at once on leaving in direction d is done here (onto a deteriorated
        backbone, the backbone followed); None if that ended the piece (a side lost, a stretch of
        zero force along the backbone)."""
        u, f, k = self.u, self.f, self.k
        if f != 0.0 and (u >= self.pos.du if d > 0 else u <= -self.neg.du):
            self._flags(d)  # moving on beyond an ultimate drift: that side's strength is gone at once
            return None
        near, kb = self._ahead(d)
        fb = self.backbone(d, u)
        if d * (fb - f) < 0.0:  # a deteriorated backbone below the point: onto it
            self.f = f = fb
            self.on_backbone = True
            self._note("onto backbone")
        gap = d * (fb - f)
        follow = gap == 0.0 and kb <= k
        if follow:
            self.on_backbone = True
            if f == 0.0 and kb == 0.0 and u * d <= 0.0 and self._zero_backbone(d):
                return None
        reach = d * (target - u)
        candidates = [(reach, END), (near, KINK)]
        if not follow:
            if k > kb:
                touch = gap / (k - kb)
                if touch < reach - _CORNER * self.pos.fy0 / self.ke:  # one at the end is the end: not on it yet
                    candidates.append((touch, TOUCH))
            if not self.on_backbone and self.failure > ELASTIC and f * d < 0.0 and k > 0.0:
                candidates.append((-f * d / k, CROSS))
        if d > 0 and u < self.pos.du:
            candidates.append((self.pos.du - u, ULTIMATE))
        if d < 0 and u > -self.neg.du:
            candidates.append((u + self.neg.du, ULTIMATE))
        candidates.append((self._to_residual(d), RES))
        length, kind = min(candidates, key=_first_event)
        return length, kind, reach, follow, kb

    def _take(self, d, target, plan):
        """Take a piece `_plan` gave (to its event, or to `target` if that comes first)."""
        length, kind, reach, follow, kb = plan
        u, f, k = self.u, self.f, self.k
        end = length >= reach
        s = target if end else u + d * length
        if follow:
            f_new = self.backbone(d, s)
        elif kind == CROSS and not end:
            f_new = 0.0
        else:
            f_new = f + k * (s - u)
        self.e_acc += 0.5 * (f + f_new) * (s - u)
        self.u, self.f = s, f_new
        if kind == CROSS and length <= reach:
            self.f = 0.0
            exhausted = self._excursion(d)
            self._crossed_at = s
            self._flags(d, exhausted)
            return
        if kind == TOUCH and length <= reach:
            self.on_backbone = True
            self.f = self.backbone(d, s)
            self._note("touch")
        elif kind == KINK and length < reach:
            self._note("kink")
        self._flags(d, plateau=follow and kb == 0.0 and length > _CORNER * self.pos.fy0 / self.ke)
