"""Independent solvers of the damper model built on general-purpose ODE integrators.

They share nothing with pidamper_physics but the model: the same equations, the same
impact law, and (in the "logic" variants) the same stick and release rules. They serve
as the benchmark's reference and as the methods a user would otherwise pick:

- IvpSolver(method, rtol, logic=True): scipy.integrate.solve_ivp restarted at every
  event, events located by solve_ivp (direction-aware, which gives the hysteresis a
  restart needs), a rebound too small to resolve collapses into sticking, sticking is
  integrated as one oscillator with a release event on the contact force.
- IvpSolver(method, rtol, logic=False): what a user writes first: every zero crossing
  of the gap is an impact, no direction filter, no sticking.
- Rk4Solver(steps_per_period, locate=True): fixed-step RK4 whose events are located by
  bisection on the RK4 step itself (the cross-check of the reference), or with
  locate=False the impact applied at the end of the step that detects it (what a
  fixed-step co-simulation FMU does).

Every solver returns a Trajectory: piecewise dense output with x(t), v(t), y(t) and the
impact list. Only the displacement form (|x - y| <= d) is modelled here.
"""
import math
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicHermiteSpline

from .cases import EPS_HEIGHT


class Stall(RuntimeError):
    """The solver made no useful progress (Zeno chatter, a time budget exhausted)."""


class Trajectory:
    """Piecewise dense output: pieces of (t0, t1, f(t) -> (x, v, y, u) arrays)."""

    def __init__(self):
        self.pieces = []
        self.impacts = []  # (t, side, v_rel_before)
        self.max_penetration = 0.0

    def add(self, t0, t1, fn):
        if t1 > t0:
            self.pieces.append((t0, t1, fn))

    def sample(self, t):
        """(x, v, y, u) arrays at times t (sorted); at a piece boundary the later piece wins."""
        t = np.asarray(t, dtype=float)
        out = np.full((4, len(t)), np.nan)
        starts = np.array([p[0] for p in self.pieces])
        idx = np.searchsorted(starts, t, side="right") - 1
        for k in np.unique(idx):
            if k < 0:
                continue
            sel = idx == k
            out[:, sel] = np.asarray(self.pieces[k][2](t[sel]))
        return out


def _forcing(case):
    a = case.F0 / case.M
    om, phi = case.Omega, case.phi
    held = case.held  # None, or (times, values) of a force held over each step
    if held is None:
        return lambda t: a * math.sin(om * t + phi)

    times, values = held
    def f(t):
        k = int(np.searchsorted(times, t, side="right")) - 1
        return a * math.sin(om * t + phi) + values[max(k, 0)] / case.M
    return f


class _EventDriven:
    """Shared event handling: impact law, chatter collapse into sticking, release."""

    def __init__(self, case, budget=30.0, max_events=200_000):
        self.c = case
        self.f = _forcing(case)
        self.budget = budget
        self.max_events = max_events
        self.w1sq = case.w1 ** 2
        self.w2sq = case.w2 ** 2
        mu = case.mu
        self.Wsq = (self.w2sq + mu * self.w1sq) / (1 + mu)
        scale = case.d + 2 * case.amplitude
        self.h_min = EPS_HEIGHT * scale  # rebound apex below which chatter collapses
        self.logic = True

    # ---- right-hand sides --------------------------------------------------------------

    def free_rhs(self, t, s):
        x, v, y, u = s
        ag = self.c.ground  # a base excitation acts on both bodies
        return [v, self.f(t) - self.w2sq * x - ag, u, -self.w1sq * y - ag]

    def stick_rhs(self, side):
        c, mu = self.c, self.c.mu

        def rhs(t, s):
            x, v = s
            acc = (self.f(t) + mu * self.w1sq * side * c.d - (self.w2sq + mu * self.w1sq) * x) / (1 + mu) - c.ground
            return [v, acc]
        return rhs

    def contact_force(self, side):
        """side * N / m along the stick motion (positive while riding)."""
        c, mu = self.c, self.c.mu

        def g(t, s):
            x = s[0]
            acc = (self.f(t) + mu * self.w1sq * side * c.d - (self.w2sq + mu * self.w1sq) * x) / (1 + mu) - c.ground
            return side * (acc + self.w1sq * (x - side * c.d) + c.ground)
        return g

    def rel_acc(self, t, x, v, y, u):
        """Relative acceleration z'' of the free motion."""
        return (self.f(t) - self.w2sq * x) + self.w1sq * y

    # ---- impact law ---------------------------------------------------------------------

    def collide(self, v, u, e):
        mu = self.c.mu
        vc = (v + mu * u) / (1 + mu)
        w = u - v
        return vc + mu * e * w / (1 + mu), vc - e * w / (1 + mu)

    def after_impact(self, t, x, v, y, u, side, traj):
        """Apply the law; return ('free', state) or ('stick', state)."""
        c = self.c
        traj.impacts.append((t, side, u - v))
        v, u = self.collide(v, u, c.e)
        if self.logic:
            q2 = -side * self.rel_acc(t, x, v, y, u)  # second derivative of the gap guard
            rebound = -side * (v - u)
            if q2 < 0 and rebound * rebound <= -2.0 * q2 * self.h_min:
                vc = (v + c.mu * u) / (1 + c.mu)
                if u != v:
                    traj.impacts.append((t, side, 0.0))
                return "stick", (x, vc)
        return "free", (x, v, y, u)

    def check_budget(self, started, traj):
        if time.process_time() - started > self.budget:
            raise Stall(f"time budget of {self.budget} s exhausted at {len(traj.impacts)} impacts")
        if len(traj.impacts) > self.max_events:
            raise Stall(f"more than {self.max_events} impacts")


class IvpSolver(_EventDriven):
    """solve_ivp restarted at each event (see the module doc)."""

    def __init__(self, case, method="DOP853", rtol=1e-9, logic=True, budget=30.0, max_step=None):
        super().__init__(case, budget)
        self.method, self.rtol, self.logic = method, rtol, logic
        self.max_step = max_step or np.inf  # a step no longer than a grazing dip cannot skip it
        self.atol = rtol * 1e-2 * (case.d + case.amplitude)

    def solve(self, t_end):
        c = self.c
        traj = Trajectory()
        t, mode, state = 0.0, "free", (c.x0, c.v0, c.y0, c.u0)
        started = time.process_time()
        # a held input jumps at its sample times: integrate from jump to jump
        breaks = list(c.held[0][1:]) if c.held is not None else []
        k = 0
        while t < t_end:
            self.check_budget(started, traj)
            while k < len(breaks) and breaks[k] <= t:
                k += 1
            stop = min(t_end, breaks[k]) if k < len(breaks) else t_end
            if mode == "free":
                t, mode, state = self._free(t, state, stop, traj)
            else:
                t, mode, state = self._stick(t, state, mode, stop, traj)
            if state is None:  # reached `stop` without an event: continue from its end state
                state = self._end_state
        return traj

    def _events(self):
        d = self.c.d
        up = lambda t, s: d - (s[0] - s[2])
        down = lambda t, s: d + (s[0] - s[2])
        for ev in (up, down):
            ev.terminal = True
            ev.direction = -1 if self.logic else 0
        return up, down

    def _free(self, t, state, t_end, traj):
        if self.logic:
            t, state = self._leave_stop(t, state, t_end, traj)
            if t >= t_end:
                self._end_state = state
                return t_end, "free", None
        up, down = self._events()
        sol = solve_ivp(self.free_rhs, (t, t_end), state, method=self.method, rtol=self.rtol, atol=self.atol,
                        events=(up, down), dense_output=True, max_step=self.max_step)
        if not sol.success:
            raise Stall(sol.message)
        t1 = sol.t[-1]
        traj.add(t, t1, sol.sol)
        if sol.status != 1:
            self._end_state = tuple(sol.y[:, -1])
            return t_end, "free", None
        side = 1 if len(sol.t_events[0]) else -1
        x, v, y, u = sol.y_events[0 if side > 0 else 1][0]
        gap = side * (x - y) - self.c.d
        traj.max_penetration = max(traj.max_penetration, gap)
        if t1 <= t and self.logic:
            raise Stall("an event at the restart time: no progress")
        if side * (v - u) <= 0 and not self.logic:
            traj.impacts.append((t1, side, u - v))  # a 'crossing' of a separating pair
            return t1, "free", (x, v, y, u)
        mode, new = self.after_impact(t1, x, v, y, u, side, traj)
        return t1, (mode, side) if mode == "stick" else "free", new

    def _leave_stop(self, t, state, t_end, traj):
        """Hysteresis at a restart on a stop: integrate without events for rebound / B2, half
        the shortest possible return time (B2 bounds the relative acceleration), so the gap is
        clearly open and the return to the stop is a clean + to - crossing of the guard."""
        c = self.c
        x, v, y, u = state
        for side in (1, -1):
            gap = c.d - side * (x - y)
            if abs(gap) > 1e-9 * c.d:
                continue
            rebound = -side * (v - u)
            if rebound > 0:
                held = 0.0 if c.held is None else float(np.max(np.abs(c.held[1]))) / c.M
                b2 = (self.w1sq * math.hypot(y, u / c.w1) + self.w2sq * math.hypot(x, v / c.w2)
                      + 4.0 * (abs(c.F0) / c.M + held))
                t1 = min(t + rebound / b2, t_end)
                sol = solve_ivp(self.free_rhs, (t, t1), state, method=self.method, rtol=self.rtol, atol=self.atol,
                                dense_output=True)
                traj.add(t, t1, sol.sol)
                return t1, tuple(sol.y[:, -1])
        return t, state

    def _stick(self, t, state, mode, t_end, traj):
        side = mode[1]
        release = self.contact_force(side)
        release.terminal, release.direction = True, -1
        d = self.c.d
        sol = solve_ivp(self.stick_rhs(side), (t, t_end), state, method=self.method, rtol=self.rtol,
                        atol=self.atol, events=release, dense_output=True)
        if not sol.success:
            raise Stall(sol.message)
        t1 = sol.t[-1]
        dense = sol.sol
        traj.add(t, t1, lambda tt, dense=dense: _stick_state(dense(tt), side, d))
        if sol.status != 1:
            self._end_state = tuple(sol.y[:, -1])
            return t_end, mode, None
        x, v = sol.y_events[0][0]
        if t1 <= t:
            raise Stall("a release at the restart time: no progress")
        return t1, "free", (x, v, x - side * d, v)


def _stick_state(xv, side, d):
    x, v = xv
    return np.array([x, v, x - side * d, v])


def _gap(state):
    return state[0] - state[2]


def _add_hermite(traj, piece, solver):
    """Cubic Hermite dense output over one smooth piece (positions from their velocities,
    velocities from their accelerations)."""
    if len(piece) < 2:
        return
    T = np.array([p[0] for p in piece])
    S = np.array([p[1] for p in piece]).T
    keep = np.concatenate([[True], np.diff(T) > 0])
    T, S = T[keep], S[:, keep]
    if len(T) < 2:
        return
    acc = np.array([solver.free_rhs(t, S[:, k])[1] for k, t in enumerate(T)])
    splines = (CubicHermiteSpline(T, S[0], S[1]), CubicHermiteSpline(T, S[1], acc),
               CubicHermiteSpline(T, S[2], S[3]), CubicHermiteSpline(T, S[3], -solver.w1sq * S[2]))
    traj.add(T[0], T[-1], lambda tt: np.array([sp(tt) for sp in splines]))


class Rk4Solver(_EventDriven):
    """Fixed-step RK4; events located by bisection on the step, or applied at its end."""

    def __init__(self, case, steps_per_period=10_000, locate=True, budget=60.0):
        super().__init__(case, budget)
        self.h = 2 * math.pi / max(case.w1, case.w2) / steps_per_period
        self.locate = locate
        self.logic = locate

    @staticmethod
    def _rk4(f, t, s, h):
        k1 = np.asarray(f(t, s))
        k2 = np.asarray(f(t + h / 2, s + h / 2 * k1))
        k3 = np.asarray(f(t + h / 2, s + h / 2 * k2))
        k4 = np.asarray(f(t + h, s + h * k3))
        return s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)

    def solve(self, t_end):
        c, d = self.c, self.c.d
        traj = Trajectory()
        t, mode = 0.0, "free"
        s = np.array([c.x0, c.v0, c.y0, c.u0], dtype=float)
        piece = [(t, s.copy())]
        started = time.process_time()
        n = 0

        def close(new_state):  # an event: the piece ends, the next starts from new_state
            nonlocal piece
            _add_hermite(traj, piece, self)
            piece = [(t, np.asarray(new_state, dtype=float).copy())]

        while t < t_end - 1e-15 * max(1.0, t_end):
            n += 1
            if n % 1000 == 0:
                self.check_budget(started, traj)
            h = min(self.h, t_end - t)
            if mode == "free":
                new = self._rk4(self.free_rhs, t, s, h)
                z = new[0] - new[2]
                side = 1 if z > d else (-1 if z < -d else 0)
                if side and side * (new[1] - new[3]) > 0:
                    if self.locate:
                        h = self._bisect(lambda hh: d - side * _gap(self._rk4(self.free_rhs, t, s, hh)), h)
                        new = self._rk4(self.free_rhs, t, s, h)
                    else:
                        traj.max_penetration = max(traj.max_penetration, side * z - d)
                    t += h
                    piece.append((t, new.copy()))
                    kind, st = self.after_impact(t, new[0], new[1], new[2], new[3], side, traj)
                    if kind == "stick":
                        mode, s = ("stick", side), np.array(st)
                        close(_stick_state(s, side, d))
                    else:
                        s = np.array(st)
                        close(s)
                    continue
                s, t = new, t + h
                piece.append((t, s.copy()))
            else:
                side = mode[1]
                rhs, g = self.stick_rhs(side), self.contact_force(side)
                new = self._rk4(rhs, t, s, h)
                if g(t + h, new) < 0:
                    h = self._bisect(lambda hh: g(t + hh, self._rk4(rhs, t, s, hh)), h)
                    new = self._rk4(rhs, t, s, h)
                    t += h
                    s = np.array([new[0], new[1], new[0] - side * d, new[1]])
                    piece.append((t, s.copy()))
                    mode = "free"
                    close(s)
                    continue
                s, t = new, t + h
                piece.append((t, _stick_state(s, side, d)))
        _add_hermite(traj, piece, self)
        return traj

    @staticmethod
    def _bisect(g, h):
        """Largest step in (0, h] at which g is still >= 0 (g(0) >= 0 > g(h))."""
        lo, hi = 0.0, h
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            if not lo < mid < hi:
                break
            if g(mid) >= 0:
                lo = mid
            else:
                hi = mid
        return hi
