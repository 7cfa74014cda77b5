"""Validity of the linear (small-angle) model: how far a swing of amplitude A [rad] is from it.

A pendulum of amplitude A swings at w(A) = w0 AGM(1, cos(A/2)) (the arithmetic-geometric mean
form of the complete elliptic integral), so the linear model, which swings at w0 whatever A,
has the relative frequency error 1 - AGM(1, cos(A/2)), about A^2/16: 0.25 % at 0.2 rad,
1 % at 0.4 rad, 6 % at 1 rad.  Beyond A = pi a real pendulum goes over the top.
"""
import math



def frequency_error(amplitude):
    """Relative frequency error of the linear model for a free swing of `amplitude` [rad]:
    1 - AGM(1, cos(A/2)), carried as the deficits 1 - a, 1 - b of the AGM iteration so that
    small swings keep every digit (1.0 from pi on, where the pendulum no longer swings back)."""
    a = abs(amplitude)
    if a >= math.pi:
        return 1.0
    da, db = 0.0, 2.0 * math.sin(0.25 * a) ** 2  # 1 - 1, 1 - cos(A/2)
    for _ in range(64):
        if db - da <= 1e-17 * da:
            break
        b = math.sqrt((1.0 - da) * (1.0 - db))
        da, db = 0.5 * (da + db), (da + db - da * db) / (1.0 + b)
    return da


class SmallAngleMonitor:
    """Watches a Damper for swings beyond `limit` [rad] (> 0): warns at the first, then keeps
    the largest swing of each body for a summary at the end of the run.

    The swings are the free-swing envelopes sqrt(q^2 + (q_dot/w)^2) of each body at the
    checked instants, so a peak between two checks is not missed in free flight.  The check
    compares squares against bars that rise with each new largest swing: a few multiplications
    per call, no allocation."""

    DEFAULT_LIMIT = 0.4  # rad: the linear model's frequency is then 1 % off

    def __init__(self, params, limit=DEFAULT_LIMIT):
        self.p = params
        self.limit = limit
        self.warned = False
        # swing > bar  <=>  x^2 + (v/w2)^2 > (bar L2)^2, and alike for the particle (a building's
        # floors are no pendulum: only its particle is watched)
        self._k2, self._x2 = 1.0 / params.w2 ** 2, (limit * params.L2) ** 2 if not params.storeys else math.inf
        self._k1 = 1.0 / params.w1 ** 2
        self._y2 = (limit * params.L1) ** 2 if params.mu > 0.0 else math.inf

    def check(self, damper):
        """A warning text the first time a body's swing exceeds the limit, else None."""
        x, v = damper.x, damper.v
        y, u = damper.model.particle_swing(x, v, damper.y, damper.u)
        sx, sy = x * x + v * v * self._k2, y * y + u * u * self._k1
        if sx <= self._x2 and sy <= self._y2:
            return None
        if sx > self._x2:
            self._x2 = sx
        if sy > self._y2:
            self._y2 = sy
        if self.warned:
            return None
        self.warned = True
        primary, particle = self._swings(sx, sy)
        body, swing = ("primary (theta)", primary) if primary > particle else ("particle (alpha)", particle)
        return (f"t = {damper.t:.6g} s: the {body} swings {swing:.3g} rad, beyond the small-angle limit "
                f"{self.limit:g} rad of the linear model; {_effect(swing)}. Warned once per run; the largest "
                "swings follow at the end of the run.")

    def get_state(self):
        """JSON-able state: [warned, bar of the primary, bar of the particle]."""
        return [self.warned, self._x2, self._y2]

    def set_state(self, state):
        self.warned, self._x2, self._y2 = state

    def _swings(self, sx, sy):
        """(primary, particle) swings [rad] of the squared envelopes; a building's floors are
        no pendulum (0), nor is a particle without mass."""
        primary = math.sqrt(sx) / self.p.L2 if not self.p.storeys else 0.0
        return primary, (math.sqrt(sy) / self.p.L1 if self.p.mu > 0.0 else 0.0)

    def largest(self):
        """(primary, particle) largest swings [rad] seen since the limit was first exceeded
        (a body that never exceeded it reports the limit; a particle without mass, or a
        building's floors, 0)."""
        return self._swings(self._x2, self._y2 if self._y2 < math.inf else 0.0)

    def summary(self):
        """The closing text of a run that left the small-angle range, else None."""
        if not self.warned:
            return None
        primary, particle = self.largest()
        swing = max(primary, particle)
        within = "within the limit"
        bodies = [] if self.p.storeys else [f"primary {within if primary <= self.limit else f'{primary:.3g} rad'}"]
        bodies.append(f"particle {within if particle <= self.limit else f'{particle:.3g} rad'}")
        return (f"largest swings of the run: {', '.join(bodies)} (limit {self.limit:g} rad); "
                f"at {swing:.3g} rad {_effect(swing)}.")


class DriftMonitor:
    """Watches a building's largest storey drift ratio (the running maxima peaks.Peaks locates
    exactly) for one beyond `limit` [1] (> 0): there a shear building describes no real building
    (storeys collapse by drift ratios of about 0.1, and its geometry is that of small rotations).
    Warns once per run; a comparison per storey and step, no allocation."""

    DEFAULT_LIMIT = 0.2  # twice the drift ratio at which a yielding building counts as collapsed

    def __init__(self, limit=DEFAULT_LIMIT):
        self.limit = limit
        self.warned = False

    def check(self, t, peaks):
        """A warning text the first time a storey's largest drift ratio exceeds the limit, else None."""
        if self.warned:
            return None
        drift, limit = peaks.drift, self.limit
        for k in range(peaks.n):
            if drift[k] > limit:
                self.warned = True
                h = 1.0 / peaks.inv_h[k]
                return (f"t = {t:.6g} s: storey {k + 1}'s drift ratio reached {drift[k]:.3g} (a drift of "
                        f"{drift[k] * h:.3g} m over its {h:g} m), beyond drift_limit = {limit:g}: no real storey "
                        "stands there and the shear building's small-rotation geometry no longer holds, so the "
                        "motion from here is the model's only. Warned once per run.")
        return None


def _effect(swing):
    error = frequency_error(swing)
    if error >= 1.0:
        return "a real pendulum would go over the top: the linear model does not describe that motion"
    return (f"a real pendulum swings {100 * error:.2g} % slower than the linear model "
            f"(about {2 * math.pi * error:.2g} rad of phase per period)")
