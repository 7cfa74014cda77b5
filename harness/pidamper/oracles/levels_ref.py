"""Independent reference of the damped and coupled levels: solve_ivp with the event rules of
odesolvers.IvpSolver, the equations written out here from the forces on each body (they share
nothing with pidamper_physics.levels but the model).

Damped: dashpots 2 zeta_s w2 on the primary, 2 zeta_p w1 on the particle (pivots fixed).
Coupled: the particle hangs from the primary (linearised double pendulum): the wire pulls the
primary with m w1^2 (y - x), the primary's pendulum carries both weights ((1 + mu) w2^2), and
the particle dashpot acts on the relative velocity u - v.
"""
from .odesolvers import IvpSolver


class LevelIvpSolver(IvpSolver):
    """IvpSolver for fidelity "damped" or "coupled" with damping ratios zeta_s, zeta_p."""

    def __init__(self, case, level, zeta_s=0.0, zeta_p=0.0, **kwargs):
        super().__init__(case, **kwargs)
        if level not in ("damped", "coupled"):
            raise ValueError(f"level = {level!r}: only 'damped' or 'coupled'")
        self.coupled = level == "coupled"
        self.cs = 2.0 * zeta_s * case.w2  # per unit primary mass
        self.cp = 2.0 * zeta_p * case.w1  # per unit particle mass

    def _free_acc(self, t, x, v, y, u):
        c, mu, ag = self.c, self.c.mu, self.c.ground
        if self.coupled:
            wire = self.w1sq * (y - x) + self.cp * (u - v)  # pull of the wire and dashpot on the particle, per m
            return (self.f(t) - ag - (1 + mu) * self.w2sq * x - self.cs * v + mu * wire, -ag - wire)
        return (self.f(t) - ag - self.w2sq * x - self.cs * v, -ag - self.w1sq * y - self.cp * u)

    def free_rhs(self, t, s):
        x, v, y, u = s
        ax, ay = self._free_acc(t, x, v, y, u)
        return [v, ax, u, ay]

    def _ride_acc(self, t, x, v, side):
        c, mu, ag = self.c, self.c.mu, self.c.ground
        if self.coupled:  # the pair swings as one pendulum; the dashpot between them is idle
            return (self.f(t) - (1 + mu) * ag - (1 + mu) * self.w2sq * x - self.cs * v) / (1 + mu)
        y = x - side * c.d
        return (self.f(t) - self.w2sq * x - self.cs * v + mu * (-self.w1sq * y - self.cp * v) - (1 + mu) * ag) / (1 + mu)

    def stick_rhs(self, side):
        return lambda t, s: [s[1], self._ride_acc(t, s[0], s[1], side)]

    def contact_force(self, side):
        d = self.c.d

        def g(t, s):
            x, v = s
            y = x - side * d
            free_y = self._free_acc(t, x, v, y, v)[1]  # the particle's acceleration without the stop
            return side * (self._ride_acc(t, x, v, side) - free_y)
        return g

    def rel_acc(self, t, x, v, y, u):
        ax, ay = self._free_acc(t, x, v, y, u)
        return ax - ay
