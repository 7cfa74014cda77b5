"""The exact monolithic reference the co-simulations are measured against, and their error."""
import numpy as np


def reference(scn, times):
    """Floor displacements [m] at `times` (rows) of the exact monolithic model: THE function the
    measurements compare with.  The physics core's building level (Damper with storeys, when it
    accepts the scenario), else `ivp_reference`.  Returns (x, source)."""
    from pidamper_physics import ParameterError

    try:
        return monolithic_reference(scn, times), "monolithic core (Damper with storeys)"
    except (ImportError, TypeError, AttributeError, NotImplementedError, ParameterError) as err:
        return ivp_reference(scn, times), (f"independent event-driven integration (scipy DOP853, rtol 1e-12; the "
                                           f"core's building level is not usable here: {err})")


def monolithic_reference(scn, times):
    """Floor displacements at `times` by the physics core (Params(storeys=...) + Damper.floors())."""
    from pidamper_physics import Damper, Params

    params = Params(mu=scn.mu, FR=scn.FR, g=scn.g, d=scn.d, e=scn.e, zeta_s=scn.zeta_s, zeta_p=scn.zeta_p,
                    fidelity=1 if (scn.zeta_s or scn.zeta_p) else 0, storeys=scn.storeys,
                    damper_floor=scn.damper_floor, floor_m=list(scn.floor_m), storey_k=list(scn.storey_k))
    core = Damper(params)
    out = []
    for t in times:
        if core.t < scn.pulse_time < t:
            core.advance(scn.pulse_time, 0.0, scn.pulse)
        core.advance(t, 0.0, scn.pulse if t <= scn.pulse_time else 0.0)
        out.append(list(core.floors()[0]))
    return np.array(out)


def ivp_reference(scn, times, rtol=1e-12):
    """Floor displacements at `times` by an independent event-driven integration of the
    monolithic model: DOP853 (rtol 1e-12) between impacts, impacts located as events and resolved
    by the two-body Newton law between floor j and the particle (momentum exchanged with floor j
    only).  Refuses a scenario that chatters (it has no sticking rule)."""
    from scipy.integrate import solve_ivp

    b = scn.building
    n, j = b.n, scn.j
    M, K, C = np.array(b.masses), np.array(b.K), np.array(b.C)
    m, w1, d, e = scn.m, scn.w1, scn.d, scn.e
    cp = 2.0 * scn.zeta_p * w1
    mj = M[j]
    mu = m * mj / (m + mj)

    def rhs(t, z, ag):
        x, v, r, rd = z[:n], z[n:2 * n], z[2 * n], z[2 * n + 1]
        f = -(C @ v) - (K @ x)
        f[j] += m * (w1 * w1 * r + cp * rd)
        absolute = f / M
        return np.concatenate([v, absolute - ag, [rd, -w1 * w1 * r - cp * rd - absolute[j]]])

    def stop_plus(t, z, ag):
        return z[2 * n] - d

    def stop_minus(t, z, ag):
        return z[2 * n] + d

    stop_plus.terminal = stop_minus.terminal = True
    stop_plus.direction, stop_minus.direction = 1.0, -1.0
    atol = np.concatenate([np.full(2 * n, 1e-15), [1e-15, 1e-14]])
    pieces = []
    z = np.zeros(2 * n + 2)
    t = 0.0
    t_end = float(np.max(times))
    impacts = 0
    for t_to, ag in ((min(scn.pulse_time, t_end), scn.pulse), (t_end, 0.0)):
        while t < t_to:
            sol = solve_ivp(rhs, (t, t_to), z, method="DOP853", rtol=rtol, atol=atol, args=(ag,),
                            events=(stop_plus, stop_minus), dense_output=True)
            if sol.status == -1:
                raise RuntimeError(f"reference integration failed at t = {t}: {sol.message}")
            pieces.append((t, sol.t[-1], sol.sol))
            t, z = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1:  # an impact
                side = 1.0 if len(sol.t_events[0]) else -1.0
                w = z[2 * n + 1]
                if abs(w) < 1e-6:
                    raise RuntimeError(f"the reference has no sticking rule: a grazing or chattering impact at "
                                       f"t = {t} (approach speed {w!r} m/s)")
                J = mu * (1.0 + e) * w
                z[n + j] += J / mj
                z[2 * n + 1] = -e * w
                z[2 * n] = side * d
                impacts += 1
    out = np.zeros((len(times), n))
    for i, tq in enumerate(times):
        for t0, t1, sol in pieces:
            if t0 <= tq <= t1 and t1 > t0:
                out[i] = sol(tq)[:n]
                break
        else:
            out[i] = 0.0 if tq <= 0.0 else pieces[-1][2](pieces[-1][1])[:n]
    ivp_reference.impacts = impacts
    return out


def error(run, scn, grid=0.01, ref=None):
    """max |x_k(t) - x_ref,k(t)| / max |x_ref| over the floors and the points t of a `grid` [s]
    common to every step compared (the relative error of the displacement history)."""
    times = np.arange(1, int(round(scn.stop_time / grid)) + 1) * grid
    if ref is None:
        ref, _ = reference(scn, times)
    return float(np.max(np.abs(run.at(times) - ref)) / np.max(np.abs(ref)))
