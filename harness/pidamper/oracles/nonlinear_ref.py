"""Independent reference of the nonlinear level: the double pendulum written with its mass
matrix and generalised forces (numpy), integrated by solve_ivp (DOP853 or Radau) restarted at
every impact, each impact applied with the generalised Newton law dq' = M^-1 J^T lambda.  It
shares nothing with pidamper_physics.nonlinear; it has no sticking (use it on cases whose
rebounds stay resolvable).

Coordinates q = (theta, phi): primary and particle wire angles; gap z = -L1 sin(phi), stops at
z = +-d; horizontal loads per mass fx (primary, with F0 sin(Omega t + phi0)) and fy (particle).
"""
import math

import numpy as np
from scipy.integrate import solve_ivp


class NonlinearReference:
    def __init__(self, p, fx=0.0, fy=0.0, method="DOP853", rtol=1e-13):
        self.p, self.fx, self.fy, self.method, self.rtol = p, fx, fy, method, rtol
        self.cs = 2 * p.zeta_s * p.w2 * p.M  # N s/m on the bob's horizontal velocity
        self.cp = 2 * p.zeta_p * p.w1 * p.m  # on the particle's velocity relative to the bob
        self.impacts = []

    def mass(self, q):
        p = self.p
        c = math.cos(q[0] - q[1])
        return np.array([[(p.M + p.m) * p.L2 ** 2, p.m * p.L2 * p.L1 * c], [p.m * p.L2 * p.L1 * c, p.m * p.L1 ** 2]])

    def rhs(self, t, s):
        p = self.p
        th, ph, dth, dph = s
        # positions xb = L2 sin th, yp = xb + L1 sin ph; heights -L2 cos th, -L2 cos th - L1 cos ph
        jb = np.array([p.L2 * math.cos(th), 0.0])  # d xb / dq
        jp = np.array([p.L2 * math.cos(th), p.L1 * math.cos(ph)])  # d yp / dq
        vb, vp = jb @ [dth, dph], jp @ [dth, dph]
        fb = p.M * (self.fx + p.F0 / p.M * math.sin(p.Omega * t + p.phi)) - self.cs * vb + self.cp * (vp - vb)
        fp = p.m * self.fy - self.cp * (vp - vb)
        Q = jb * fb + jp * fp
        Q -= np.array([(p.M + p.m) * p.g * p.L2 * math.sin(th), p.m * p.g * p.L1 * math.sin(ph)])
        # velocity terms of the mass matrix: d/dt(M q') - dT/dq
        k = p.m * p.L2 * p.L1 * math.sin(th - ph)
        Q -= np.array([k * dph ** 2, -k * dth ** 2])
        acc = np.linalg.solve(self.mass((th, ph)), Q)
        return [dth, dph, acc[0], acc[1]]

    def solve(self, theta0, phi0, dtheta0, dphi0, t_end):
        """Dense pieces [(t0, t1, sol)] and self.impacts [(t, side)] up to t_end."""
        p = self.p
        state, t, pieces = np.array([theta0, phi0, dtheta0, dphi0], float), 0.0, []

        def gap_up(t, s):
            return p.d + p.L1 * math.sin(s[1])  # d - z

        def gap_down(t, s):
            return p.d - p.L1 * math.sin(s[1])

        for ev in (gap_up, gap_down):
            ev.terminal, ev.direction = True, -1
        while t < t_end:
            sol = solve_ivp(self.rhs, (t, t_end), state, method=self.method, rtol=self.rtol,
                            atol=self.rtol * 1e-2, events=(gap_up, gap_down), dense_output=True)
            pieces.append((t, sol.t[-1], sol.sol))
            if sol.status != 1:
                break
            side = 1 if len(sol.t_events[0]) else -1
            t = sol.t[-1]
            state = self._impact(sol.y[:, -1], side)
            self.impacts.append((t, side))
        return pieces

    def _impact(self, s, side):
        p = self.p
        q, dq = s[:2], s[2:]
        J = np.array([0.0, -p.L1 * math.cos(q[1])])  # dz/dq
        Minv = np.linalg.inv(self.mass(q))
        lam = -(1 + p.e) * (J @ dq) / (J @ Minv @ J)
        return np.concatenate([q, dq + Minv @ J * lam])


def sample(pieces, times):
    """(theta, phi, theta', phi') rows at times from the pieces (later piece wins at a boundary)."""
    out = []
    for t in times:
        for t0, t1, sol in reversed(pieces):
            if t0 <= t <= t1:
                out.append(sol(t))
                break
    return np.array(out)
