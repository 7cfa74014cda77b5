"""Physics core against closed forms and invariants (no FMI involved)."""
import math

import pytest

from pidamper_physics import FREE, OUTSIDE, STICK, Damper, Params

G, L2 = 9.81, 1.0
W2 = math.sqrt(G / L2)
PERIOD = 2 * math.pi / W2


def record(damper):
    events = []
    damper.on_impact = lambda *a: events.append(a)
    return events


def march(damper, t_end, n, force=0.0):
    """Advance in n equal steps, returning [(t, x, v, y, u)] after each."""
    t0 = damper.t
    out = []
    for k in range(1, n + 1):
        damper.advance(t0 + (t_end - t0) * k / n, force)
        out.append((damper.t, damper.x, damper.v, damper.y, damper.u))
    return out


# ---- no contact: closed form over 100 periods ----------------------------------------

@pytest.mark.parametrize("F0,omega_ratio,phi", [(0.0, 1.0, 0.0), (0.02, 1.0, 0.0), (0.02, 1.0, math.pi / 2),
                                                (0.05, 0.7, 1.0)])
def test_no_contact_equals_closed_form_over_100_periods(F0, omega_ratio, phi):
    p = Params(mu=0.1, FR=5.0, d=1e3, e=0.2, F0=F0, Omega=omega_ratio * W2, phi=phi)
    th0, thd0 = 0.01, 0.05
    dm = Damper(p, th0, thd0)
    x0, v0, w, a, om = L2 * th0, L2 * thd0, W2, F0 / p.M, omega_ratio * W2
    worst = scale = 0.0
    for t, x, v, _, _ in march(dm, 100 * PERIOD, 3000):
        if om == w:  # secular term
            s, c = math.sin(w * t), math.cos(w * t)
            xr = x0 * c + v0 / w * s + a * (math.sin(phi) * t * s / (2 * w) +
                                            math.cos(phi) * (s - w * t * c) / (2 * w * w))
        else:
            P = a / (w * w - om * om)
            xr = ((x0 - P * math.sin(phi)) * math.cos(w * t) + (v0 - P * om * math.cos(phi)) / w * math.sin(w * t)
                  + P * math.sin(om * t + phi))
        worst = max(worst, abs(x - xr))
        scale = max(scale, abs(xr))
    assert dm.impacts == 0
    assert worst <= 1e-12 * scale


def test_resonance_envelope_grows_at_F0_over_2Mw2():
    F0 = 0.03
    p = Params(mu=0.0, d=1e3, F0=F0, Omega=W2, phi=math.pi / 2)  # cosine forcing, from rest
    dm = Damper(p)
    n = 100
    dm.advance(n * PERIOD)
    # x(t) = F0/(2 M w2) t sin(w2 t): at t = n T + T/4 it equals the envelope
    dm.advance(n * PERIOD + PERIOD / 4)
    assert dm.x == pytest.approx(F0 / (2 * p.M * W2) * dm.t, rel=1e-12)


# ---- energy bookkeeping ---------------------------------------------------------------

@pytest.mark.parametrize("form", [0, 1])
@pytest.mark.parametrize("e", [0.0, 0.2, 0.8])
def test_free_vibration_energy_balance(form, e):
    p = Params(mu=0.1, FR=5.0, d=0.1, d_angle=0.1, e=e, contact_form=form)
    dm = Damper(p, theta_dot0=0.7 * W2)
    events = record(dm)
    march(dm, 10 * PERIOD, 500)
    assert dm.impacts > 20
    assert dm.work_in == pytest.approx(0.0, abs=1e-13 * dm.energy0)
    assert dm.energy0 - dm.energy == pytest.approx(dm.dissipated, abs=1e-12 * dm.energy0)
    assert sum(ev[4] for ev in events) == pytest.approx(dm.dissipated, rel=1e-12)


def test_forced_energy_balance_at_every_output():
    p = Params(mu=0.02, FR=5.0, d=0.1, e=0.2, F0=0.0981, Omega=W2)
    dm = Damper(p)
    for k in range(1, 2001):
        dm.advance(k * 0.02, 0.01 * math.sin(3 * k * 0.02))
        assert dm.energy0 + dm.work_in - dm.energy == pytest.approx(dm.dissipated, abs=1e-12 * (1 + dm.work_in))
    assert dm.impacts > 50


def test_work_in_equals_quadrature_of_force_times_velocity():
    """W_in against Simpson's rule on F(t) v(t) over a forced run without contact."""
    F0, om = 0.2, 0.8 * W2
    p = Params(mu=0.1, d=1e3, F0=F0, Omega=om, phi=0.4)
    dm = Damper(p, 0.01, 0.1)
    n, T = 20000, 15.0
    h = T / n
    values = []
    for k in range(n + 1):
        if k:
            dm.advance(k * h, 0.05)
        force = 0.05 + F0 * math.sin(om * k * h + 0.4)
        values.append(force * dm.v)
    simpson = h / 3 * (values[0] + values[-1] + 4 * sum(values[1:-1:2]) + 2 * sum(values[2:-1:2]))
    assert dm.work_in == pytest.approx(simpson, rel=1e-10)


# ---- chatter, sticking, release ----------------------------------------------------

@pytest.mark.parametrize("e", [0.0, 0.05, 0.2, 0.5, 0.8])
def test_chatter_on_a_held_primary_follows_the_closed_form_series(e):
    """mu = 0 holds the primary at X0 (its equilibrium under F = M w2^2 X0); the particle is
    pressed on the stop at c = X0 - d and launched at V0: flights tau_k = (2/w1) atan(e^k V0/(w1 c))."""
    p = Params(mu=0.0, FR=5.0, d=0.1, e=e)
    X0, V0 = 0.15, 0.3
    c = X0 - p.d
    dm = Damper(p, theta0=X0 / L2, alpha0=c / p.L1, alpha_dot0=V0 / p.L1)
    events = record(dm)
    dm.advance(2.0, p.M * W2 ** 2 * X0)
    w1 = p.w1

    def flight(k):
        return (2 / w1) * math.atan(e ** k * V0 / (w1 * c))

    t_prev = 0.0
    for k, ev in enumerate(events[:-1]):
        # impact times resolve to position rounding / approach speed
        assert ev[0] - t_prev == pytest.approx(flight(k), abs=1e-15 + 1e-16 / abs(ev[2]))
        t_prev = ev[0]
    if e == 0.0:  # one plastic impact, then the particle rides the stop
        assert len(events) == 1 and events[0][3] == 0.0
        assert events[0][0] == pytest.approx(flight(0), abs=1e-15)
        assert dm.mode == STICK and dm.contact == 1
        return
    t_acc = sum(flight(k) for k in range(10000))
    last = events[-1]  # the collapse: rel_before is the rebound speed the tail would start with
    rebound = abs(last[2])
    assert last[3] == 0.0
    # accumulation time = collapse time + the closed-form tail it replaced
    tail = sum((2 / w1) * math.atan(e ** j * rebound / (w1 * c)) for j in range(10000))
    assert last[0] + tail == pytest.approx(t_acc, abs=1e-15 + 1e-16 / max(rebound, 1e-300) * len(events))
    # and the rebound at collapse is below the position-resolution threshold (a rise under 1e-12 m)
    assert rebound ** 2 / (2 * w1 * w1 * c) < 1e-12
    assert dm.mode == STICK and dm.contact == 1
    assert dm.x == X0 and dm.y == pytest.approx(c, abs=1e-16)


def test_sticking_and_release_follow_the_combined_oscillator():
    """Start riding stop +1 (e = 0): x = xe + (x0 - xe) cos Wt + v0/W sin Wt until N = 0."""
    mu, FR, d = 0.1, 5.0, 0.1
    p = Params(mu=mu, FR=FR, d=d, e=0.0)
    w1, w2 = p.w1, p.w2
    x0, v0 = 0.3, 0.2
    dm = Damper(p, theta0=x0 / L2, theta_dot0=v0 / L2, alpha0=(x0 - d) / p.L1, alpha_dot0=v0 / p.L1)
    W = math.sqrt((w2 ** 2 + mu * w1 ** 2) / (1 + mu))
    xe = mu * w1 ** 2 * d / ((1 + mu) * W ** 2)
    # contact force per particle mass N/m = (w1^2 - W^2)(x - xe) + w1^2 (xe - d): zero when
    # (x0 - xe) cos Wt + v0/W sin Wt = K
    K = -w1 ** 2 * (xe - d) / (w1 ** 2 - W ** 2)
    R = math.hypot(x0 - xe, v0 / W)
    phase = math.atan2(v0 / W, x0 - xe)
    t_release = (phase + math.acos(K / R)) / W
    assert 0 < t_release < 2 * math.pi / W
    events = record(dm)
    n = 400
    step = 1.2 * t_release / n
    released = None
    for k in range(1, n + 1):
        dm.advance(k * step)
        t = dm.t
        if dm.mode == STICK:
            x_ref = xe + (x0 - xe) * math.cos(W * t) + v0 / W * math.sin(W * t)
            assert dm.x == pytest.approx(x_ref, abs=1e-14)
            assert dm.y == pytest.approx(dm.x - d, abs=1e-16)
            assert dm.contact_force() > 0
        elif released is None:
            released = t
    assert released is not None and released - step < t_release <= released
    assert not events  # neither the start nor the release is an impact
    # find the release instant to machine precision by bisection on the mode
    lo, hi = released - step, released
    for _ in range(60):
        dm = Damper(p, theta0=x0 / L2, theta_dot0=v0 / L2, alpha0=(x0 - d) / p.L1, alpha_dot0=v0 / p.L1)
        mid = 0.5 * (lo + hi)
        dm.advance(mid)
        if dm.mode == STICK:
            lo = mid
        else:
            hi = mid
    assert lo == pytest.approx(t_release, abs=1e-12)


@pytest.mark.timeout(60)
@pytest.mark.parametrize("e", [0.0, 0.05, 0.2, 0.5, 0.8, 1.0])
def test_no_livelock_and_no_penetration(e):
    p = Params(mu=0.1, FR=5.0, d=0.1, e=e)
    dm = Damper(p, theta_dot0=0.7 * W2)
    worst = 0.0
    for t, x, v, y, u in march(dm, 30 * PERIOD, 3000):
        worst = max(worst, abs(x - y) - p.d)
    assert dm.impacts > 50
    assert worst <= 1e-15
    assert dm.energy0 + dm.work_in - dm.energy == pytest.approx(dm.dissipated, abs=1e-12 * dm.energy0)


# ---- grazing -----------------------------------------------------------------------

def test_grazing_contact_at_1e_12_is_found_inside_one_long_step():
    """Particle at rest at 0; primary oscillates about the stop position x = d (F = M w2^2 d)
    with amplitude R, so it reaches the stop at speed R w2 = 1e-12 with zero acceleration."""
    p = Params(mu=0.1, FR=5.0, d=0.1, e=0.5)
    R = 1e-12 / W2
    dm = Damper(p, theta0=(p.d - R) / L2)
    events = record(dm)
    dm.advance(10.0, p.M * W2 ** 2 * p.d)  # one 10 s communication step
    assert events, "the 1e-12 m/s contact was missed"
    t, side, rel_before, rel_after, _ = events[0]
    assert side == 1
    assert t == pytest.approx(math.pi / (2 * W2), abs=1e-3)  # a 1e-12 m/s contact: time to rounding / speed
    assert -rel_before == pytest.approx(1e-12, rel=1e-3)  # u - v = -(approach speed)
    assert rel_after == pytest.approx(-0.5 * rel_before, rel=1e-9)


def test_exact_touch_with_zero_speed_is_not_an_impact():
    """x = d cos(w2 t), particle at rest at 0: the gap closes to exactly zero at rest, every period."""
    p = Params(mu=0.1, FR=5.0, d=0.1, e=0.5)
    dm = Damper(p, theta0=p.d / L2)
    dm.advance(5 * PERIOD + 0.123)  # one long step over five touches
    assert dm.impacts == 0 and dm.mode == FREE
    assert dm.x == pytest.approx(p.d * math.cos(W2 * dm.t), abs=1e-14)
    assert dm.y == 0.0


# ---- symmetry and invariants -------------------------------------------------------

def test_mirror_symmetry():
    p = Params(mu=0.1, FR=5.0, d=0.1, e=0.2, F0=0.05, Omega=W2, phi=0.3)
    q = Params(mu=0.1, FR=5.0, d=0.1, e=0.2, F0=-0.05, Omega=W2, phi=0.3)
    a = Damper(p, 0.05, 0.9, 0.2, -1.0)
    b = Damper(q, -0.05, -0.9, -0.2, 1.0)
    for k in range(1, 401):
        force = 0.02 * math.cos(0.7 * k)
        a.advance(k * 0.025, force)
        b.advance(k * 0.025, -force)
        assert (b.x, b.v, b.y, b.u) == pytest.approx((-a.x, -a.v, -a.y, -a.u), abs=1e-13)
    assert a.impacts == b.impacts > 10


@pytest.mark.timeout(120)
def test_elastic_impacts_conserve_energy_over_10000_impacts():
    p = Params(mu=0.1, FR=5.0, d=0.1, e=1.0)
    dm = Damper(p, theta_dot0=0.7 * W2)
    while dm.impacts < 10000:
        dm.advance(dm.t + PERIOD)
    assert dm.dissipated == 0.0
    assert dm.energy == pytest.approx(dm.energy0, rel=1e-11)


# ---- angle form as printed ---------------------------------------------------------

@pytest.mark.timeout(60)
def test_angle_form_passes_through_and_never_hangs():
    p = Params(mu=0.1, FR=5.0, d_angle=0.1, e=0.2, contact_form=1)
    dm = Damper(p, theta_dot0=0.7 * W2)
    events = record(dm)
    outside = 0
    for k in range(1, 4001):
        dm.advance(k * 20 * PERIOD / 4000)
        outside += dm.mode == OUTSIDE
    assert len(events) == dm.impacts > 20
    assert outside > 0  # the non-separating rule was exercised
    for t, side, before, after, loss in events:
        assert after * before <= 0 or abs(after) <= abs(before)  # restitution never adds relative speed


# ---- bad input ---------------------------------------------------------------------

@pytest.mark.parametrize("kwargs,name", [({"g": 0.0}, "g"), ({"M": -1.0}, "M"), ({"L2": float("nan")}, "L2"),
                                         ({"FR": 0.0}, "FR"), ({"d": 0.0}, "d"), ({"d_angle": -1.0}, "d_angle"),
                                         ({"mu": -0.1}, "mu"), ({"e": 1.5}, "e"), ({"e": -0.1}, "e"),
                                         ({"contact_form": 2}, "contact_form"), ({"Omega": -1.0}, "Omega"),
                                         ({"F0": float("inf")}, "F0")])
def test_invalid_parameters_name_value_and_rule(kwargs, name):
    with pytest.raises(ValueError) as err:
        Params(**kwargs)
    assert str(err.value).startswith(f"{name} = ")
    assert "allowed" in str(err.value)


def test_initial_penetration_and_bad_steps_are_refused():
    p = Params(d=0.1)
    with pytest.raises(ValueError, match="penetrates"):
        Damper(p, theta0=0.2)
    dm = Damper(p, theta_dot0=1.0)
    dm.advance(1.0)
    with pytest.raises(ValueError, match="t_end"):
        dm.advance(0.5)
    with pytest.raises(ValueError, match="F = nan"):
        dm.advance(2.0, float("nan"))
    assert dm.t == 1.0


def test_dense_output_equals_stepping_to_each_time():
    """dense() evaluates the closed-form pieces at the output times; stepping restarts at each."""
    times = [k * 0.013 for k in range(1, 1500)]
    a = Damper(Params(e=0.3), theta_dot0=0.7 * W2)
    rows = a.dense(times)
    b = Damper(Params(e=0.3), theta_dot0=0.7 * W2)
    for t, row in zip(times, rows):
        b.advance(t)
        assert row == pytest.approx((b.x, b.v, b.y, b.u), abs=1e-12)
    assert a.impacts == b.impacts > 50 and a.t == b.t


@pytest.mark.timeout(60)
@pytest.mark.parametrize("t0", [1e6, 1e12])
def test_motion_does_not_depend_on_the_start_time(t0):
    """Unforced motion is invariant under a time shift.  At t0 = 1e12 s one ulp of the clock is
    1.2e-4 s, so most chatter impacts lie within one ulp of the current time: the state must still
    move to each of them (no stall) and end where the same run from t0 = 0 ends."""
    runs = []
    for start in (0.0, t0):
        dm = Damper(Params(mu=0.1, FR=5.0, d=0.1, e=0.2), theta_dot0=0.7 * W2, t0=start)
        sticks = 0
        for k in range(1, 2001):
            dm.advance(start + k * 0.01)
            sticks += dm.contact != 0
        assert dm.t == start + 20.0
        runs.append((dm.impacts, sticks, dm.x, dm.v, dm.y, dm.u, dm.dissipated))
    (n0, s0, *z0, d0), (n1, s1, *z1, d1) = runs
    assert n1 == n0 > 200 and s1 == s0 > 100
    assert z1 == pytest.approx(z0, abs=1e-12) and d1 == pytest.approx(d0, rel=1e-12)


@pytest.mark.parametrize("fidelity", [0, 1, 2, 3])
@pytest.mark.parametrize("side", [0, 1, -1])
def test_observables_equal_the_separate_methods(fidelity, side):
    """Damper.observables (the FMU's outputs in one call, inline for the linear level) gives the
    values of angles, displacements, acceleration and contact_force to the last bit."""
    from pidamper_physics.damper import STICK

    extra = {"zeta_s": 0.02, "zeta_p": 0.03} if fidelity in (1, 2) else {}
    for F0, force, ground in ((0.0, 0.3, 0.0), (0.2, -0.7, 1.3)):
        params = Params(fidelity=fidelity, F0=F0, Omega=2.9, phi=0.4, d=0.05, FR=2.0, **extra)
        core = Damper(params, 0.01, -0.02, 0.0, 0.3, t0=1.7)
        core.x, core.v, core.y, core.u = 0.031, -0.12, 0.031 - 0.05 * side, 0.27
        if side:
            core.mode, core.side = STICK, side
        theta, theta_dot, alpha, alpha_dot = core.angles()
        x, _, y, _ = core.displacements()
        expected = (theta, theta_dot, alpha, alpha_dot, x, y, core.acceleration(force, ground),
                    core.contact_force(force, ground))
        assert core.observables(force, ground) == expected
        assert (expected[-1] != 0.0) == bool(side)


@pytest.mark.parametrize("case", ["no contact", "impacts and sticking", "resonance reaching the stops",
                                  "long steps", "ground motion", "angle form"])
def test_coasting_fast_path_equals_the_segment_path_bit_for_bit(case):
    """The linear level's segment-free flight (LinearModel.coast, taken when no stop is within
    reach) gives the states, clock and bookkeeping of the general path (a Flight segment per
    piece) to the last bit, step after step; runs that reach the stops switch between both."""
    w2 = math.sqrt(9.81)
    values, h, n, a0 = {"d": 10.0}, 0.01, 3000, 0.7 * w2
    if case == "impacts and sticking":
        values = {}
    if case == "resonance reaching the stops":  # coasts while small, then impacts
        values, a0 = {"e": 0.5}, 0.0
    if case == "long steps":
        values, h, n = {"d": 0.3}, 3.0, 60
    if case == "angle form":
        values = {"contact_form": 1, "d_angle": 0.5}
    runs, coasted = [], []
    for fast in (True, False):
        core = Damper(Params(**values), 0.0, a0, 0.0, 0.0)
        model_coast, count = core._coaster, [0]

        def counting(*args):
            state = model_coast(*args)
            count[0] += state is not None
            return state

        core._coaster = counting if fast else None
        states = []
        for k in range(1, n + 1):
            force = 0.05 * math.sin(w2 * k * h) if case == "resonance reaching the stops" else 0.05
            ground = 0.4 * math.cos(1.3 * k * h) if case == "ground motion" else 0.0
            core.advance(k * h, force, ground)
            states.append(core.get_state())
        runs.append(states)
        coasted.append(count[0])
    assert runs[0] == runs[1]
    impacts = runs[0][-1]["impacts"]
    assert (impacts > 20) == (case in ("impacts and sticking", "resonance reaching the stops", "long steps",
                                       "angle form"))
    assert (coasted[0] > 100) == (case != "long steps"), coasted  # the fast path was taken (between impacts too: its Taylor reach is tight)
