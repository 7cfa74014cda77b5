"""The protocol between Damper and a fidelity level: what a level model provides.

Damper keeps the state (x, v, y, u) [m, m/s or rad, rad/s, as the level defines them], the mode
and the clock, and asks its level for everything physical through the methods below.  A level
subclasses LevelModel and overrides what it has; the optional hooks default to None (absent), so
Damper reads them without probing.  State the level keeps itself (a building's other floors, the
nonlinear integrator's next step) is saved and restored through get_state / set_state only.

Loads: `fc` = (load per mass on the primary, on the particle) [m/s2], held over a call; `psi` [rad]
the phase of the built-in harmonic at the piece's start; `side` +1 / -1 names a stop; `f` the
applied force per primary mass [m/s2] at an instant, `ground` the ground acceleration [m/s2].
Segments follow the guard protocol of events.py.
"""
import math

#: the integrator's next step [s] that Damper states carry for every level (0: none)
NO_HINT = 0.0


class LevelModel:
    """Base of the level models (see the module doc); `p` is the Params, `fastest` [rad/s] the
    fastest motion of the level (it sets Damper's longest piece)."""

    fastest = math.inf
    #: cost of one piece in closed-form pieces (Damper.bound_work divides its cap by it)
    piece_weight = 1
    #: coast(x, v, y, u, fx, fy, T): the free-flight state after T when no stop is within reach,
    #: else None, without building a segment: an innermost fast path, or None
    coast = None
    #: observables(x, v, y, u, side, f, ground): Damper.observables inline, or None
    observables = None
    #: work(seg, tau, before, after, fc, psi, e_change) -> (work of the loads, work of the
    #: dashpots) [J] over a piece, or None: no dashpots, the energy change is the loads' work
    work = None
    #: follow(seg, tau): carry the level's own state along a piece the Damper takes, or None
    follow = None
    #: resting(): True when the level's own state is at rest (stepping.at_rest), so that a piece
    #: with the Damper's state at rest and no load changes nothing but rest_piece(tau, a_g)'s
    #: books; None: the level never skips its pieces
    resting = None
    #: a yielding building that collapsed holds its state (building_level.BuildingModel)
    collapsed = False

    def __init__(self, p):
        self.p = p

    # ---- state the level keeps itself ---------------------------------------------------

    def get_state(self):
        """The level's own part of a Damper state (JSON-safe)."""
        return {"step_hint": NO_HINT}

    def set_state(self, state):
        """Restore get_state()'s keys from a Damper state (checked before anything changes)."""

    # ---- segments -------------------------------------------------------------------------

    def flight(self, x, v, y, u, fc, psi, T, always_bound=False):
        """Free flight over [0, T], T in s (bounds and noise always built when always_bound)."""
        raise NotImplementedError

    def stick(self, x, v, side, fc, psi, T):
        """The particle riding stop `side` over [0, T] (guard: its contact force)."""
        raise NotImplementedError

    def outside(self, x, v, y, u, fc, psi, T, side):
        """Angle form: the pair passed through stop `side` (guard: the overlap)."""
        raise NotImplementedError(f"{type(self).__name__} has no angle form")

    # ---- contact --------------------------------------------------------------------------

    def snap(self, x, v, y, u, side):
        """The state put exactly on stop `side` (removes rounding-level overlap)."""
        raise NotImplementedError

    def collide(self, x, v, y, u, side, e):
        """(state after, loss [J], relative velocity before, after) of an impact of restitution e."""
        raise NotImplementedError

    def approach(self, x, v, y, u):
        """(relative velocity [m/s] the impact law acts on, the impact's reduced mass [kg]): the
        particle on the primary, m* = M mu / (1 + mu)."""
        p = self.p
        return u - v, p.M * p.mu / (1.0 + p.mu)

    # ---- observables ----------------------------------------------------------------------

    def energy(self, x, v, y, u):
        """Mechanical energy [J] of the state (relative to the ground)."""
        raise NotImplementedError

    def displacements(self, x, v, y, u):
        """(x, x', y, y'): horizontal positions and velocities of primary and particle [m, m/s]."""
        raise NotImplementedError

    def angles(self, x, v, y, u):
        """(theta, theta', alpha, alpha') [rad, rad/s]."""
        raise NotImplementedError

    def from_angles(self, theta, theta_dot, alpha, alpha_dot):
        """The state (x, v, y, u) of the given angles [rad, rad/s]."""
        raise NotImplementedError

    def particle_swing(self, x, v, y, u):
        """Particle displacement and velocity relative to its pivot [m, m/s]."""
        raise NotImplementedError

    def acceleration(self, x, v, y, u, side, f, ground):
        """Primary acceleration [m/s2] relative to the ground (side: the stop ridden, or 0)."""
        raise NotImplementedError

    def contact_accel(self, x, v, side, f, ground):
        """Contact force per particle mass [m/s2] while riding stop `side`."""
        raise NotImplementedError
