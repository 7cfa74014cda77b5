"""Benchmark cases: the model, its start, forcing, horizon and the measure that matters.

All cases use the displacement form.  Angles become lengths: x = L2 theta, y = L1 alpha.
"""
import math
from dataclasses import dataclass, field, replace

EPS = 2.220446049250313e-16
# chatter collapses when the rebound apex is below 16 rounding units of 64 eps each,
# relative to the size of the motion (the core's rule: damper.CHATTER_HEIGHT, segments.TOLERANCE)
EPS_HEIGHT = 16 * 64 * EPS


@dataclass(frozen=True)
class Case:
    name: str
    title: str
    mu: float = 0.1
    FR: float = 5.0
    d: float = 0.1
    e: float = 0.2
    theta_dot_0: float = 0.0
    F0: float = 0.0
    phi: float = 0.0
    periods: float = 6.0  # horizon in primary periods
    measure: str = "damping"  # "damping", "amplitude" or "statistics"
    sampled: bool = False  # feed the harmonic through input F, held over each step
    well_conditioned: bool = True
    g: float = 9.81
    L2: float = 1.0
    M: float = 1.0
    held: object = field(default=None, compare=False)  # (times, F values) when sampled
    grazing: bool = False  # the reference must not step over a shallow dip through a stop
    ground: float = 0.0  # constant ground acceleration of a base excitation [m/s2]

    @property
    def ref_max_step(self):
        """Longest reference step: 1e-4 of a period where contacts may only graze the stop."""
        return self.period * 1e-4 if self.grazing else None

    @property
    def w2(self):
        return math.sqrt(self.g / self.L2)

    @property
    def w1(self):
        return self.FR * self.w2

    @property
    def Omega(self):
        return self.w2  # every forced case is at resonance

    @property
    def period(self):
        return 2 * math.pi / self.w2

    @property
    def horizon(self):
        return self.periods * self.period

    @property
    def x0(self):
        return 0.0

    @property
    def v0(self):
        return self.L2 * self.theta_dot_0

    y0 = 0.0
    u0 = 0.0

    @property
    def amplitude(self):
        """A length scale of the motion [m]: free amplitude, or the undamped growth at the horizon."""
        return max(self.v0 / self.w2, self.F0 / (2 * self.M * self.w2) * self.horizon, self.d)

    def start_values(self):
        """The FMU parameters of this case (built-in harmonic unless sampled)."""
        values = {"g": self.g, "L2": self.L2, "M": self.M, "mu": self.mu, "FR": self.FR, "d": self.d, "e": self.e,
                  "theta_dot_0": self.theta_dot_0}
        if self.F0 and not self.sampled:
            values.update({"F0": self.F0, "Omega": self.Omega, "phi": self.phi})
        return values

    def with_held_input(self, h):
        """The sampled case as a reference sees it: F0 sin(Omega t + phi) held over steps of h."""
        import numpy as np

        n = int(round(self.horizon / h))
        times = h * np.arange(n + 1)
        values = self.F0 * np.sin(self.Omega * times + self.phi)
        return replace(self, F0=0.0, held=(times, values))


W2 = math.sqrt(9.81)
CASES = (
    Case("free-fr1.5", "free decay, FR = 1.5", FR=1.5, theta_dot_0=0.7 * W2),
    Case("free-fr5", "free decay, FR = 5 (chatter and sticking)", FR=5.0, theta_dot_0=0.7 * W2),
    Case("resonance", "forced at resonance, built-in harmonic (mu = 0.02, F0 = 0.01 M g)", mu=0.02,
         F0=0.0981, phi=math.pi / 2, periods=20, measure="amplitude"),
    Case("resonance-sampled", "forced at resonance, harmonic sampled into input F", mu=0.02, F0=0.0981,
         phi=math.pi / 2, periods=20, measure="amplitude", sampled=True),
    Case("chatter", "chatter-heavy: e = 0.8, d = 0.02 m, FR = 5", e=0.8, d=0.02, theta_dot_0=0.2 * W2),
    Case("grazing", "near-grazing: amplitude 1e-6 above the clearance, e = 1", e=1.0, FR=2.0, d=0.1,
         theta_dot_0=0.1 * (1 + 1e-6) * W2, periods=20, measure="statistics", well_conditioned=False, grazing=True),
)
