"""An independent event-driven reference (a test oracle) for yielding shear buildings: scipy's
DOP853 at rtol 1e-12 on M x'' + C x' + F(x) = f - M 1 a_g, with its own hysteresis bookkeeping
(each storey's EPP spring: elastic with its plastic drift held, or yielding at +-(1 - b) Fy), yield,
unload and impact event functions, and optionally the particle damper hung from a floor (Newton's
impact law between the particle and that floor; no chatter-to-sticking logic: cases that stick are
outside its reach).  The dashpots' energy (integral of x'^T C x') and the hysteretic energy
(integral of f_p d delta_p) are integrated as two extra states.

It shares nothing with pidamper_physics but the problem statement: matrices by numpy, damping
C = M Phi diag(2 zeta w) Phi^T M from scipy.linalg.eigh(K - K_G, M) ("modal"), or Rayleigh
a0 M + a1 K with zeta at the first mode and the min(3, N)-th on K - K_G ("rayleigh-initial") or on
the current regimes' tangent ("rayleigh-tangent"), P_k = g (masses above storey k, the particle's
on its floor included)."""
import numpy as np
import scipy.linalg
from scipy.integrate import solve_ivp


class Reference:
    def __init__(self, m, k, Fy, b, h, zeta, p_delta=False, g=9.81, damper=None, damping="modal"):
        """damper: None or dict(floor j (0-based), m, w1, zeta_p, d, e); damping: "modal",
        "rayleigh-initial" or "rayleigh-tangent"."""
        self.m, self.k, self.Fy, self.b, self.h = (np.asarray(a, float) for a in (m, k, Fy, b, h))
        n = self.n = len(m)
        carried = self.m.copy()
        if damper is not None:
            carried[damper["floor"]] += damper["m"]
        P = g * np.cumsum(carried[::-1])[::-1] if p_delta else np.zeros(n)
        self.kg = P / self.h
        keff = self.k - self.kg
        D = np.eye(n) - np.eye(n, k=-1)  # drift = D x
        K = D.T @ np.diag(keff) @ D
        M = np.diag(self.m)
        w2, phi = scipy.linalg.eigh(K, M)
        self.damping, self.M = damping, M
        if damping == "modal":
            self.C = M @ phi @ np.diag(2 * zeta * np.sqrt(w2)) @ phi.T @ M
        else:
            w1, wj = np.sqrt(w2[0]), np.sqrt(w2[min(3, n) - 1])
            self.rayleigh = (2 * zeta * w1 * wj / (w1 + wj), 2 * zeta / (w1 + wj))
            self.C = self.rayleigh[0] * M + self.rayleigh[1] * K
        self.D = D
        self.damper = damper
        self.dp = np.zeros(n)
        self.s = np.zeros(n, int)
        self.events = []  # (t, kind, storey or side)
        # solve_ivp sees a guard's sign only at its step ends: a guard that dips below zero and back
        # within one step (a storey grazing its yield surface) would be missed; short steps see it
        self.max_step = 5e-4

    def damping_matrix(self):
        """C of the current regimes (Rayleigh on the tangent: a0 M + a1 D^T diag(kt - P/h) D)."""
        if self.damping != "rayleigh-tangent":
            return self.C
        kt = np.where(self.s == 0, self.k, self.b * self.k) - self.kg
        return self.rayleigh[0] * self.M + self.rayleigh[1] * (self.D.T @ np.diag(kt) @ self.D)

    def spring(self, drift):
        """Storey forces (bilinear springs + P-Delta) at the drifts, in the current regimes."""
        k, b = self.k, self.b
        fp = np.where(self.s == 0, (1 - b) * k * (drift - self.dp), self.s * (1 - b) * self.Fy)
        return b * k * drift + fp - self.kg * drift

    def rhs(self, t, z, ag, F):
        n = self.n
        x, v = z[:n], z[n:2 * n]
        C = self.damping_matrix()
        f = self.D.T @ self.spring(self.D @ x) + C @ v
        acc = (F - f) / self.m - ag
        rate = self.D @ v
        fp = np.where(self.s == 0, 0.0, self.s * (1 - self.b) * self.Fy)
        energies = [v @ C @ v, fp @ rate]  # dashpots, hysteresis
        if self.damper is None:
            return np.concatenate([v, acc, energies])
        dm = self.damper
        j, mp, w1, cp = dm["floor"], dm["m"], dm["w1"], 2 * dm["zeta_p"] * dm["w1"]
        y, u = z[2 * n], z[2 * n + 1]
        r, rd = y - x[j], u - v[j]
        energies[0] += mp * cp * rd * rd
        acc[j] += mp * (w1 * w1 * r + cp * rd) / self.m[j]
        return np.concatenate([v, acc, [u, -ag - w1 * w1 * r - cp * rd], energies])

    def run(self, t_grid, ag_of, F_of=None):
        """Integrate over the grid (loads held on each interval); returns the states at the grid:
        x (n), v (n), [y, u with the damper], then the dashpots' and the hysteretic energy [J]."""
        n = self.n
        size = 2 * n + (2 if self.damper else 0) + 2
        z = np.zeros(size)
        out = [z.copy()]
        for t0, t1 in zip(t_grid[:-1], t_grid[1:]):
            ag = ag_of(t0)
            F = np.zeros(n) if F_of is None else F_of(t0)
            z = self._interval(t0, t1, z, ag, F)
            out.append(z.copy())
        return np.array(out)

    #: whether the run has ended (a subclass's collapse): the intervals left are not integrated
    stopped = False

    def _interval(self, t0, t1, z, ag, F):
        t = t0
        while t < t1 and not self.stopped:
            evs = self._events_at(t, z, ag, F)
            sol = solve_ivp(self.rhs, (t, t1), z, method="DOP853", rtol=1e-12, atol=1e-15, events=evs,
                            args=(ag, F), max_step=self.max_step)
            hit = [(te[0], i) for i, te in enumerate(sol.t_events) if len(te)]
            if not hit:
                return sol.y[:, -1]
            te, i = min(hit)
            z = sol.y_events[i][0].copy()
            t = te
            self._handle(evs[i].tag, t, z)
        return z

    def _events_at(self, t, z, ag, F):
        """The event functions of the interval starting at (t, z)."""
        return self._event_functions(ag, F)

    def _event_functions(self, ag, F):
        n = self.n
        fns = []
        if self.damper is not None:
            j, d = self.damper["floor"], self.damper["d"]
            for sg in (1, -1):  # the gap x_j - y reaching +-d
                fns.append(self._fn(lambda t, z, *_, sg=sg: d - sg * (z[j] - z[2 * n]), ("impact", j, sg)))
        for i in range(n):
            if self.Fy[i] <= 0:
                continue
            D = self.Fy[i] / self.k[i]
            if self.s[i] == 0:
                for sg in (1, -1):
                    fns.append(self._fn(lambda t, z, *_, i=i, sg=sg, D=D: D - sg * ((self.D @ z[:n])[i] - self.dp[i]),
                                        ("yield", i, sg)))
            else:
                fns.append(self._fn(lambda t, z, *_, i=i: self.s[i] * (self.D @ z[n:2 * n])[i], ("unload", i, 0)))
        return fns

    @staticmethod
    def _fn(f, tag):
        f.terminal = True
        f.direction = -1
        f.tag = tag
        return f

    def _handle(self, tag, t, z):
        kind, k, sg = tag
        n = self.n
        if kind == "impact":  # Newton's law between the particle and floor j
            dm = self.damper
            mp, mj, e = dm["m"], self.m[k], dm["e"]
            w = z[2 * n + 1] - z[n + k]
            z[n + k] += mp * (1 + e) * w / (mp + mj)
            z[2 * n + 1] -= mj * (1 + e) * w / (mp + mj)
            self.events.append((t, kind, sg))
            self._decide(z, t)
            return
        drift = (self.D @ z[:n])[k]
        if kind == "yield":
            self.s[k] = sg
        else:  # elastic again, a hair (1e-12 of the elastic range) inside the surface it left: the
            # restarted integration then sees its yield guard start positive, so a quick re-yield
            # at the same surface (within the first step) is a sign change it cannot miss
            self.dp[k] = drift - self.s[k] * self.Fy[k] / self.k[k] * (1.0 - 1e-12)
            self.s[k] = 0
        self.events.append((t, kind, k))

    def _decide(self, z, t):
        """Regimes after a velocity jump: a yielding storey whose drift velocity reversed unloads."""
        n = self.n
        drift, rate = self.D @ z[:n], self.D @ z[n:2 * n]
        for i in range(n):
            if self.s[i] != 0 and self.s[i] * rate[i] < 0:
                self.dp[i] = drift[i] - self.s[i] * self.Fy[i] / self.k[i] * (1.0 - 1e-12)
                self.s[i] = 0
