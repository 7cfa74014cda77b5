"""The fidelity levels below `nonlinear`: what each one's equations are, as segment builders.

All levels share the state (x, v, y, u): horizontal displacements and velocities of the
primary and the particle [m, m/s] measured from the (possibly accelerating) ground; the gap
is x - y, the impact law is impact.py's.  Loads per mass: fx = F/M - a_g on the primary,
fy = -a_g on the particle, plus the built-in harmonic a = F0/M on the primary.

- Linear (the paper): x'' + w2^2 x = fx, y'' + w1^2 y = fy (pivots fixed); segments.py.
- Damped: plus the dashpots 2 zeta_s w2 x' and 2 zeta_p w1 y' (per mass).
- Coupled: the particle hangs from the primary (a double pendulum, linearised):
      x'' = -(1 + mu) w2^2 x + mu w1^2 (y - x) - 2 zeta_s w2 x' + mu 2 zeta_p w1 (y' - x') + fx
      y'' = -w1^2 (y - x) - 2 zeta_p w1 (y' - x') + fy
  so the primary carries the particle's weight (with the particle locked to it, the pair
  swings at w2) and the particle dashpot acts on its motion relative to its pivot.
"""
import functools
import math

from .building_level import BuildingModel
from .impact import collide, impact_loss
from .level_model import LevelModel
from .modal import Modes, ModesError
from .modal_segments import ModalFlight, ModalStick, harmonic_work
from .nonlinear import NonlinearModel
from .params import COUPLED, LEVELS, LINEAR, ParameterError
from .segments import LinearParams, Outside, coast, flight, stick


class _Displacements(LevelModel):
    """Shared by the levels whose coordinates are the displacements x, y themselves."""

    def __init__(self, p):
        super().__init__(p)
        self.consts = LinearParams(p)  # what the linear closed forms and energy read, in C doubles when compiled

    def displacements(self, x, v, y, u):
        return x, v, y, u

    def angles(self, x, v, y, u):
        p = self.p
        r, w = self.particle_swing(x, v, y, u)
        return x / p.L2, v / p.L2, r / p.L1, w / p.L1

    def from_angles(self, theta, theta_dot, alpha, alpha_dot):
        """State (x, v, y, u) of primary angle theta and particle wire angle alpha [rad, rad/s]."""
        p = self.p
        x, v, r, w = p.L2 * theta, p.L2 * theta_dot, p.L1 * alpha, p.L1 * alpha_dot
        return (x, v, x + r, v + w) if p.fidelity == COUPLED else (x, v, r, w)

    def contact_accel(self, x, v, side, f, ground):
        """Contact force per particle mass [m/s2] while riding stop `side`; f = applied force per
        primary mass [m/s2]."""
        return self._contact(x, v, side, self.acceleration(x, v, x - side * self.p.d, v, side, f, ground), ground)

    def snap(self, x, v, y, u, side):
        """The state put exactly on stop `side` (removes rounding-level overlap)."""
        p = self.p
        return x, v, (p.cx * x - side * p.D) / p.cy, u

    def collide(self, x, v, y, u, side, e):
        """(state after, loss [J], u - v before, after) of an impact with restitution e."""
        p = self.p
        v1, u1 = collide(v, u, p.mu, e)
        return (x, v1, y, u1), impact_loss(p.M, p.mu, e, v, u), u - v, u1 - v1


class LinearModel(_Displacements):
    """The paper's model: two independent undamped oscillators (segments.py)."""

    work = None  # no dashpots: the work of the loads is the energy change (see Damper._move)

    def __init__(self, p):
        super().__init__(p)
        self.fastest = max(p.w1, p.w2, p.Omega_acting, math.sqrt((p.w2 ** 2 + p.mu * p.w1 ** 2) / (1.0 + p.mu)))
        # coast: segments.coast, measured faster than building a Flight for a piece clear of the
        # stops (the common piece of a run); not with the built-in harmonic
        self.coast = None if p.F0 else functools.partial(coast, self.consts)

    def flight(self, x, v, y, u, fc, psi, T, always_bound=False):
        return flight(self.consts, x, v, y, u, fc[0], fc[1], psi, T, always_bound)

    def outside(self, x, v, y, u, fc, psi, T, side):
        return Outside(self.consts, x, v, y, u, fc[0], fc[1], psi, T, side)

    def stick(self, x, v, side, fc, psi, T):
        return stick(self.consts, x, v, side, fc[0], fc[1], psi, T)

    def energy(self, x, v, y, u):
        return _linear_energy(self.consts, x, v, y, u)

    def particle_swing(self, x, v, y, u):
        """Particle displacement and velocity relative to its pivot [m, m/s]."""
        return y, u

    def acceleration(self, x, v, y, u, side, f, ground):
        """Primary acceleration [m/s2]; f = F/M + F0/M sin(...) [m/s2], side = stop ridden or 0."""
        p = self.p
        if not side:
            return f - p.w2 * p.w2 * x - ground
        return (f + p.mu * p.w1 * p.w1 * (side * p.d - x) - p.w2 * p.w2 * x) / (1.0 + p.mu) - ground

    def _contact(self, x, v, side, accel, ground):
        p = self.p
        return accel + p.w1 * p.w1 * (x - side * p.d) + ground

    def observables(self, x, v, y, u, side, f, ground):
        """Damper.observables of this level inline (the FMU's outputs at every step): the same
        operations in the same order as angles, acceleration and contact_accel, so the same
        values to the last bit."""
        p = self.consts
        L2, L1, ww2 = p.L2, p.L1, p.w2 * p.w2
        if not side:
            return x / L2, v / L2, y / L1, u / L1, x, y, f - ww2 * x - ground, 0.0
        a = (f + p.mu * p.w1 * p.w1 * (side * p.d - x) - ww2 * x) / (1.0 + p.mu) - ground
        return x / L2, v / L2, y / L1, u / L1, x, y, a, p.m * (a + p.w1 * p.w1 * (x - side * p.d) + ground)


class ModalModel(_Displacements):
    """Damped or coupled level: closed form by modes (modal.py, modal_segments.py)."""

    def __init__(self, p):
        super().__init__(p)
        self.coupled = p.fidelity == COUPLED
        w1, w2, mu = p.w1, p.w2, p.mu
        cs, cp = 2.0 * p.zeta_s * w2, 2.0 * p.zeta_p * w1  # dashpots per mass of their body
        if self.coupled:
            K = [[(1.0 + mu) * w2 * w2 + mu * w1 * w1, -mu * w1 * w1], [-w1 * w1, w1 * w1]]
            C = [[cs + mu * cp, -mu * cp], [-cp, cp]]
            ks, cs1 = w2 * w2, cs / (1.0 + mu)
        else:
            K = [[w2 * w2, 0.0], [0.0, w1 * w1]]
            C = [[cs, 0.0], [0.0, cp]]
            ks, cs1 = (w2 * w2 + mu * w1 * w1) / (1.0 + mu), (cs + mu * cp) / (1.0 + mu)
        try:
            self.free = (Modes(K, C), K, C)
            self.ride = (Modes([[ks]], [[cs1]]), [[ks]], [[cs1]])
        except ModesError as err:
            raise ParameterError("mu, FR, zeta_s, zeta_p", (mu, p.FR, p.zeta_s, p.zeta_p),
                                 f"the {LEVELS[p.fidelity]} level needs distinct modes: {err}") from None
        self.K, self.C, self.ks, self.cs1, self.cp = K, C, ks, cs1, cp
        self.fastest = max(self.free[0].fastest, self.ride[0].fastest, p.Omega_acting)

    def flight(self, x, v, y, u, fc, psi, T, always_bound=False):
        p = self.p
        return ModalFlight(self.free, (x, y, v, u), fc, p.F0 / p.M, p.Omega, psi, T, p.D, always_bound)

    def stick(self, x, v, side, fc, psi, T):
        p = self.p
        ww1 = p.w1 * p.w1
        fy = fc[1]
        b = self._ride_load(side, fc[0], fy)
        if self.coupled:
            contact = (-self.ks, -self.cs1, b - ww1 * side * p.d - fy)
        else:
            contact = (ww1 - self.ks, self.cp - self.cs1, b - ww1 * side * p.d - fy)
        return ModalStick(self.ride, [x, v], 0, side, p.d, [b], p.F0 / p.M / (1.0 + p.mu), p.Omega, psi, T,
                          ([contact[0]], [contact[1]], contact[2]))

    def _ride_load(self, side, fx, fy):
        """Held load per mass [m/s2] of the pair riding stop `side` (its 1-DOF equation's b)."""
        p = self.p
        held = fx + p.mu * fy if self.coupled else p.mu * p.w1 * p.w1 * side * p.d + fx + p.mu * fy
        return held / (1.0 + p.mu)

    def energy(self, x, v, y, u):
        p = self.p
        if self.coupled:
            r = y - x
            return 0.5 * p.M * (v * v + (1.0 + p.mu) * p.w2 * p.w2 * x * x) + 0.5 * p.m * (u * u + p.w1 * p.w1 * r * r)
        return _linear_energy(self.consts, x, v, y, u)

    def particle_swing(self, x, v, y, u):
        return (y - x, u - v) if self.coupled else (y, u)

    def acceleration(self, x, v, y, u, side, f, ground):
        if side:
            return self._ride_accel(x, v, side, f, ground)
        K, C = self.K, self.C
        return f - ground - K[0][0] * x - K[0][1] * y - C[0][0] * v - C[0][1] * u

    def _ride_accel(self, x, v, side, f, ground):
        return self._ride_load(side, f - ground, -ground) - self.ks * x - self.cs1 * v

    def _contact(self, x, v, side, accel, ground):
        p = self.p
        ww1 = p.w1 * p.w1
        if self.coupled:
            return accel - ww1 * side * p.d + ground
        return accel + ww1 * (x - side * p.d) + self.cp * v + ground

    def work(self, seg, tau, before, after, fc, psi, e_change):
        p = self.p
        held = p.M * fc[0] * (after[0] - before[0]) + p.m * fc[1] * (after[2] - before[2])
        w = held + p.M * harmonic_work(seg, tau, p.F0 / p.M, p.Omega, psi, _primary_velocity)
        return w, w - e_change


def _linear_energy(p, x, v, y, u):
    """LinearModel.energy: the two oscillators' energy [J]; p = segments.LinearParams (typed in the compiled
    build: levels.pxd)."""
    M, m, w2, w1 = p.M, p.m, p.w2, p.w1
    return 0.5 * M * (v * v + w2 * w2 * x * x) + 0.5 * m * (u * u + w1 * w1 * y * y)


def _primary_velocity(seg, tau):
    return seg.positions(tau)[1]


def model_for(p):
    """The level model of Params p (the nonlinear one lives in nonlinear.py)."""
    if p.storeys:
        return BuildingModel(p)
    if p.fidelity == LINEAR:
        return LinearModel(p)
    if p.fidelity > COUPLED:
        return NonlinearModel(p)
    return ModalModel(p)
