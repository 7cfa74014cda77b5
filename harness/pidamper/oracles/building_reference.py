"""An independent reference integrator (a test oracle) for a shear building with a pendulum
particle damper hung from one floor.

It deliberately shares no code with `pidamper_physics`: the building matrices, the impact law,
the chatter / stick logic and the energy bookkeeping are all written here again, on top of
numpy / scipy only, and integrated event by event with `scipy.integrate.solve_ivp` (DOP853,
rtol ~1e-12, absolute tolerances scaled to the problem).

Model (SI units)
----------------
Floors k = 1..N with masses m_k; storey k (stiffness k_k) joins floor k-1 to floor k (floor 0 is
the ground); x = floor displacements relative to the ground, v = x'.

    M = diag(m_k),  K[k][k] = k_k + k_(k+1),  K[k][k+1] = K[k+1][k] = -k_(k+1),
    C = M Phi diag(2 zeta_s w_r) Phi^T M        (Phi^T M Phi = I, from scipy.linalg.eigh(K, M)).

The particle (mass m = mu * sum m_k) hangs from floor j (1-based; 0 means the top floor N) on a
pendulum of frequency w1 = FR * w_1 (w_1 the building's first natural frequency) with a dashpot
c_p = 2 zeta_p m w1.  y = particle displacement relative to the ground, r = y - x_j, u = y'.
Free flight:

    M x'' + C x' + K x = -M 1 a_g + e_j (F + m w1^2 r + c_p r'),
    m (y'' + a_g)      = -m w1^2 r - c_p r'.

Stops at r = +-d.  Impact (when r reaches +-d moving into the stop): momentum exchanged between
the particle and floor j alone, Newton restitution e on w = u - v_j = r':

    v_j+ = v_j + m (1 + e) w / (m + m_j),   u+ = u - m_j (1 + e) w / (m + m_j),   r'+ = -e w,
    loss = 0.5 m m_j / (m + m_j) (1 - e^2) w^2.

Chatter / stick: if after an impact the free-flight relative acceleration r'' pushes r into the
stop and either |r'+| <= stick_speed * V (V a velocity scale of the problem) or the rebound height
r'+^2 / (2 |r''|) <= stick_height * d, the impact is made plastic (e = 0) and the particle rides
floor j (r = side * d, r' = 0).  While it rides, the particle and floor j move as one body, so the
wire and stop forces are internal and cancel:

    (M + m e_j e_j^T) x'' + C x' + K x = -(M 1 + m e_j) a_g + e_j F.

(NB: a constant load e_j m w1^2 r is NOT added here: the wire pulls floor j by +m w1^2 r but the
stop pushes it back by -N, and with N below those two sum to -m (x_j'' + a_g), already accounted
for by the augmented mass and ground-acceleration terms.  Adding it would create energy.)

The contact force of the stop on the particle, from the particle's equation with r'' = 0, is

    N = m (x_j'' + a_g) + m w1^2 r,

admissible while side * N <= 0 (the stop at +d pushes only toward -r, the one at -d only toward
+r); the particle is released (free flight again) when side * N crosses zero upward.

Energy: E = 0.5 v^T M v + 0.5 x^T K x + 0.5 m u^2 + 0.5 m w1^2 r^2.  Two extra ODE states carry
the loads' work W' = F v_j - a_g (1^T M v + m u) and the dashpots' dissipation
D' = v^T C v + c_p r'^2; impact losses are summed, so E(0) + W - E(t) = D + impact losses.
"""
import math

import numpy as np
import scipy.linalg
from scipy.integrate import solve_ivp

__all__ = ["simulate", "building_matrices"]


def building_matrices(masses, stiffnesses, zeta_s):
    """(M, K, C, omegas, Phi) of the bare shear building (see the module doc)."""
    m = np.asarray(masses, dtype=float)
    k = np.asarray(stiffnesses, dtype=float)
    n = len(m)
    if not 1 <= n <= 10 or len(k) != n:
        raise ValueError("need 1..10 storeys, one mass and one stiffness each")
    if np.any(m <= 0) or np.any(k <= 0):
        raise ValueError("masses and stiffnesses must be positive")
    M = np.diag(m)
    K = np.zeros((n, n))
    kk = np.append(k, 0.0)
    for i in range(n):
        K[i, i] = kk[i] + kk[i + 1]
        if i + 1 < n:
            K[i, i + 1] = K[i + 1, i] = -kk[i + 1]
    lam, phi = scipy.linalg.eigh(K, M)  # phi^T M phi = I
    omegas = np.sqrt(np.maximum(lam, 0.0))
    C = M @ phi @ np.diag(2.0 * zeta_s * omegas) @ phi.T @ M
    C = 0.5 * (C + C.T)
    return M, K, C, omegas, phi


def _as_function(value):
    if callable(value):
        return lambda t: float(value(t))
    c = float(value)
    return lambda t: c


class _Model:
    def __init__(self, masses, stiffnesses, zeta_s, mu, FR, d, e, zeta_p, damper_floor, a_g, F):
        self.M, self.K, self.C, self.omegas, self.phi = building_matrices(masses, stiffnesses, zeta_s)
        self.mk = np.diag(self.M).copy()
        self.n = n = len(self.mk)
        if not 0 <= damper_floor <= n:
            raise ValueError(f"damper_floor must lie in 0..{n}")
        self.j = (damper_floor or n) - 1  # 0-based
        if not (mu > 0 and FR > 0 and d > 0 and 0 <= e <= 1 and zeta_p >= 0):
            raise ValueError("need mu > 0, FR > 0, d > 0, 0 <= e <= 1, zeta_p >= 0")
        self.m = mu * self.mk.sum()
        self.w1 = FR * self.omegas[0]
        self.cp = 2.0 * zeta_p * self.m * self.w1
        self.d, self.e = float(d), float(e)
        self.ag, self.F = _as_function(a_g), _as_function(F)
        self.maug = self.mk.copy()
        self.maug[self.j] += self.m

    # state layout: [x (n), v (n), r, rdot, W, D]
    def split(self, s):
        n = self.n
        return s[:n], s[n:2 * n], s[2 * n], s[2 * n + 1]

    def free_acc(self, t, s):
        """(x'', y'' [absolute-frame minus ground], r'') in free flight."""
        x, v, r, rd = self.split(s)
        ag, F = self.ag(t), self.F(t)
        f = -self.C @ v - self.K @ x - self.mk * ag
        f[self.j] += F + self.m * self.w1 ** 2 * r + self.cp * rd
        xdd = f / self.mk
        ydd = -ag - self.w1 ** 2 * r - self.cp / self.m * rd
        return xdd, ydd, ydd - xdd[self.j]

    def stick_acc(self, t, s):
        x, v, _, _ = self.split(s)
        ag, F = self.ag(t), self.F(t)
        f = -self.C @ v - self.K @ x - self.maug * ag
        f[self.j] += F
        return f / self.maug

    def contact_force(self, t, s):
        """N of the stop on the particle while riding (r = +-d, r' = 0)."""
        xdd = self.stick_acc(t, s)
        r = self.split(s)[2]
        return self.m * (xdd[self.j] + self.ag(t)) + self.m * self.w1 ** 2 * r

    def rhs_free(self, t, s):
        x, v, r, rd = self.split(s)
        xdd, _, rdd = self.free_acc(t, s)
        u = v[self.j] + rd
        work = self.F(t) * v[self.j] - self.ag(t) * (self.mk @ v + self.m * u)
        visc = v @ self.C @ v + self.cp * rd * rd
        return np.concatenate((v, xdd, [rd, rdd, work, visc]))

    def rhs_stick(self, t, s):
        x, v, _, _ = self.split(s)
        xdd = self.stick_acc(t, s)
        work = self.F(t) * v[self.j] - self.ag(t) * (self.mk @ v + self.m * v[self.j])
        visc = v @ self.C @ v
        return np.concatenate((v, xdd, [0.0, 0.0, work, visc]))

    def energy(self, s):
        x, v, r, rd = self.split(s)
        u = v[self.j] + rd
        return (0.5 * v @ self.M @ v + 0.5 * x @ self.K @ x
                + 0.5 * self.m * u * u + 0.5 * self.m * self.w1 ** 2 * r * r)

    def collide(self, s, side, e):
        """Post-impact state, (w_before, w_after, loss)."""
        s = s.copy()
        n, j, m, mj = self.n, self.j, self.m, self.mk[self.j]
        vj = s[n + j]
        w = s[2 * n + 1]
        if side * w < 0.0:  # grazing with rounding: nothing to exchange
            w = 0.0
        u = vj + w
        vj_new = vj + m * (1.0 + e) * w / (m + mj)
        u_new = u - mj * (1.0 + e) * w / (m + mj)
        s[n + j] = vj_new
        s[2 * n] = side * self.d
        s[2 * n + 1] = -e * w  # = u_new - vj_new, without the rounding of the difference
        loss = 0.5 * m * mj / (m + mj) * (1.0 - e * e) * w * w
        return s, (w, -e * w, loss, vj, u, vj_new, u_new)


def _scales(model, t_end, x0, v0, r0, rdot0):
    """Length, velocity and energy scales for the absolute tolerances and thresholds."""
    ts = np.linspace(0.0, t_end, 33)
    ag = max(abs(model.ag(t)) for t in ts)
    F = max(abs(model.F(t)) for t in ts)
    load = model.maug * ag
    load[model.j] += F
    static = np.linalg.solve(model.K, load)
    w_lo = min(model.omegas[0], model.w1)
    L = max(np.max(np.abs(x0)), abs(r0), np.max(np.abs(v0)) / w_lo, abs(rdot0) / w_lo,
            np.max(np.abs(static)), ag / model.w1 ** 2)
    if not L > 0:
        L = model.d if math.isfinite(model.d) else 1.0
    Lr = min(L, model.d)
    V = Lr * max(model.omegas[0], model.w1)
    Escale = (model.mk.sum() + model.m) * (L * model.omegas[0]) ** 2 + model.m * V * V
    return L, Lr, V, Escale


def simulate(masses, stiffnesses, zeta_s, mu, FR, d, e, zeta_p, t_end, damper_floor=0,
             a_g=0.0, F=0.0, x0=None, v0=None, r0=0.0, rdot0=0.0, sample_times=None, rtol=1e-12,
             stick_speed=1e-9, stick_height=1e-12, max_events=100_000):
    """Integrate the building + pendulum particle damper from t = 0 to t_end (see the module doc).

    masses, stiffnesses: N floor masses [kg] and storey stiffnesses [N/m] (floor / storey 1 first);
    zeta_s: modal damping ratio of every building mode; mu: particle mass / building mass;
    FR: pendulum frequency / the building's first frequency; d: stop clearance [m];
    e: restitution; zeta_p: pendulum damping ratio; damper_floor: 1-based floor the pendulum hangs
    from (0 = top); a_g [m/s^2] and F [N, on the damper floor]: floats or callables of t;
    x0, v0: floor displacements / velocities (default 0); r0, rdot0: particle relative to its
    pivot (|r0| <= d); sample_times: increasing times in [0, t_end] at which to report;
    rtol: solver tolerance; stick_speed (x velocity scale) and stick_height (x d): the chatter
    thresholds; max_events: cap on the phase switches (impacts, apex re-arms, stick / release;
    about two per impact), a RuntimeError beyond it (guards against Zeno loops).

    Returns a dict:
      't'            sample_times, or the solver's points of every phase (an event time appears twice:
                     before and after the jump)
      'x', 'v'       len(t) x N floor displacements / velocities
      'r', 'rdot'    particle relative to the pivot; 'u' its velocity relative to the ground
      'N'            contact force of the stop on the particle (0 in free flight)
      'side'         +1 / -1 while riding the stop at +d / -d, 0 in free flight
      'energy_t', 'work_t', 'viscous_t', 'impact_loss_t'   bookkeeping at every sample
      'impacts'      list of (t, side, w_before, w_after, loss), w = r' (= u - v_j) just before / after
      'impact_states' list of (v_j before, u before, v_j after, u after), one per impact
      'stick'        list of (t_start, t_end, side) riding phases
      'energy0'      E(0); and at t_end: 'energy', 'work', 'viscous', 'impact_loss',
      'dissipated'   = viscous + impact_loss, so energy0 + work - energy - dissipated ~ 0
      'balance'      energy0 + work - energy - dissipated
      'w', 'w1', 'm', 'M', 'K', 'C'   building frequencies, pendulum frequency, particle mass, matrices
    """
    model = _Model(masses, stiffnesses, zeta_s, mu, FR, d, e, zeta_p, damper_floor, a_g, F)
    n, j = model.n, model.j
    t_end = float(t_end)
    if not t_end > 0.0:
        raise ValueError("t_end must be positive")
    x0 = np.zeros(n) if x0 is None else np.asarray(x0, dtype=float)
    v0 = np.zeros(n) if v0 is None else np.asarray(v0, dtype=float)
    if x0.shape != (n,) or v0.shape != (n,):
        raise ValueError("x0 and v0 need one value per floor")
    if abs(r0) > model.d:
        raise ValueError("|r0| must not exceed d")
    L, Lr, V, Escale = _scales(model, t_end, x0, v0, r0, rdot0)
    vtol = stick_speed * V
    hstick = stick_height * model.d
    atol = np.concatenate((np.full(n, rtol * L), np.full(n, rtol * L * model.omegas[0]),
                           [rtol * Lr, rtol * V], [rtol * Escale, rtol * Escale]))
    w_hi = max(model.omegas[-1], model.w1)
    max_step = 2.0 * math.pi / w_hi / 4.0

    s = np.concatenate((x0, v0, [float(r0), float(rdot0), 0.0, 0.0]))
    energy0 = model.energy(s)
    segments = []   # (t0, t1, OdeSolution, side) side 0 = free flight
    impacts, impact_states, sticks = [], [], []
    impact_loss = 0.0
    events = 0

    def impact(t, s, side):
        """Apply the impact law at the stop `side`; return (state, phase side, disarmed side)."""
        nonlocal impact_loss
        post, info = model.collide(s, side, model.e)
        _, _, rdd = model.free_acc(t, post)
        rd = post[2 * n + 1]
        into = side * rdd > 0.0
        chatter = into and (abs(rd) <= vtol or rd * rd <= 2.0 * abs(rdd) * hstick)
        phase = 0
        if chatter:
            plastic, pinfo = model.collide(s, side, 0.0)
            if side * model.contact_force(t, plastic) < 0.0:
                post, info, phase = plastic, pinfo, side
        w, wa, loss = info[:3]
        impacts.append((float(t), side, float(w), float(wa), float(loss)))
        impact_states.append(tuple(float(q) for q in info[3:]))
        impact_loss += loss
        return post, phase, side

    # the initial phase
    t = sticks_start = 0.0
    phase, disarmed = 0, 0
    if abs(r0) == model.d:
        side = 1 if r0 > 0 else -1
        if side * rdot0 > 0.0:
            s, phase, disarmed = impact(t, s, side)
        elif rdot0 == 0.0 and side * model.contact_force(t, s) < 0.0:
            phase = side
        else:
            disarmed = side

    while t < t_end:
        events += 1
        if events > max_events:
            raise RuntimeError(f"more than {max_events} events (impacts, apex re-arms, stick / release) by "
                               f"t = {float(t)!r} ({len(impacts)} impacts, {len(sticks)} stick phases): a Zeno "
                               "chatter the stick thresholds did not catch, or raise max_events")
        if phase == 0:
            evs = []
            for side in (1, -1):
                if side == disarmed:
                    # just left this stop: it can only be hit again after the particle has turned
                    # back toward it, so watch the apex (side * r' crossing 0 upward) instead of the
                    # gap, whose sign need not change within a step around a short bounce
                    ev = (lambda side: lambda tt, ss: side * ss[2 * n + 1])(side)
                else:
                    ev = (lambda side: lambda tt, ss: side * ss[2 * n] - model.d)(side)
                ev.terminal, ev.direction = True, 1
                evs.append(ev)
            sol = solve_ivp(model.rhs_free, (t, t_end), s, method="DOP853", rtol=rtol, atol=atol,
                            dense_output=True, events=evs, max_step=max_step)
        else:
            rel = lambda tt, ss: phase * model.contact_force(tt, ss)
            rel.terminal, rel.direction = True, 1
            evs = [rel]
            sol = solve_ivp(model.rhs_stick, (t, t_end), s, method="DOP853", rtol=rtol, atol=atol,
                            dense_output=True, events=evs, max_step=max_step)
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp failed at t = {float(t)!r}: {sol.message}")
        t1, s1 = sol.t[-1], sol.y[:, -1].copy()
        if t1 > t:
            segments.append((t, t1, sol.sol, phase, sol.t))
        t = t1
        if sol.status == 0:  # reached t_end
            if phase:
                sticks.append((float(sticks_start), float(t), phase))
            s = s1
            break
        fired = [k for k, te in enumerate(sol.t_events) if len(te)]
        k = fired[0]
        if phase:  # release
            s1[2 * n], s1[2 * n + 1] = phase * model.d, 0.0
            sticks.append((float(sticks_start), float(t), phase))
            s, disarmed, phase = s1, phase, 0
            continue
        side = 1 if k == 0 else -1
        if side == disarmed:  # the apex: re-arm the side last touched
            s, disarmed = s1, 0
            continue
        s, phase, disarmed = impact(t, s1, side)
        if phase:
            sticks_start = t
            s[2 * n], s[2 * n + 1] = phase * model.d, 0.0
            disarmed = 0

    # sampling
    if sample_times is None:
        ts, seg_of = [], []
        for idx, (_, _, _, _, tpts) in enumerate(segments):
            ts.extend(tpts)
            seg_of.extend([idx] * len(tpts))
        ts = np.asarray(ts)
    else:
        ts = np.asarray(sample_times, dtype=float)
        if np.any(np.diff(ts) < 0) or (len(ts) and (ts[0] < 0 or ts[-1] > t_end)):
            raise ValueError("sample_times must be increasing and inside [0, t_end]")
        starts = np.array([seg[0] for seg in segments])
        seg_of = np.clip(np.searchsorted(starts, ts, side="right") - 1, 0, len(segments) - 1)
    states = np.empty((len(ts), 2 * n + 4))
    Ns = np.zeros(len(ts))
    sides = np.zeros(len(ts), dtype=int)
    loss_t = np.zeros(len(ts))
    imp_t = np.array([imp[0] for imp in impacts])
    imp_loss = np.cumsum([imp[4] for imp in impacts])
    for i, (tt, idx) in enumerate(zip(ts, seg_of)):
        a, b, dense, ph, _ = segments[idx]
        st = dense(min(max(tt, a), b))
        if ph:
            st[2 * n], st[2 * n + 1] = ph * model.d, 0.0
            Ns[i] = model.contact_force(tt, st)
            sides[i] = ph
        states[i] = st
        # impacts strictly before this segment's start, plus those at its start
        c = np.searchsorted(imp_t, a, side="right") if len(imp_t) else 0
        loss_t[i] = imp_loss[c - 1] if c else 0.0
    x, v = states[:, :n], states[:, n:2 * n]
    r, rd = states[:, 2 * n], states[:, 2 * n + 1]
    energy = model.energy(s)
    return {
        "t": ts, "x": x, "v": v, "r": r, "rdot": rd, "u": v[:, j] + rd, "N": Ns, "side": sides,
        "energy_t": np.array([model.energy(st) for st in states]), "work_t": states[:, 2 * n + 2],
        "viscous_t": states[:, 2 * n + 3], "impact_loss_t": loss_t,
        "impacts": impacts, "impact_states": impact_states, "stick": sticks,
        "energy0": energy0, "energy": energy, "work": s[2 * n + 2], "viscous": s[2 * n + 3],
        "impact_loss": impact_loss, "dissipated": s[2 * n + 3] + impact_loss,
        "balance": energy0 + s[2 * n + 2] - energy - s[2 * n + 3] - impact_loss,
        "w": model.omegas, "w1": model.w1, "m": model.m, "M": model.M, "K": model.K, "C": model.C,
    }
