"""Yielding buildings (issue 24): bilinear storeys, regimes, P-Delta, collapse, against independent
oracles: scipy's event-driven DOP853 (pidamper.oracles.yielding_reference) and closed forms."""
import cmath
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from energy_checks import assert_energy_matches
from pidamper.oracles.yielding_reference import Reference
from pidamper_physics import Damper, Params
from pidamper_physics.building import ShearBuilding
from pidamper_physics.params import ParameterError
from pidamper_physics.storeys import UNLOAD, YIELD, check_storeys
from pidamper_physics.yielding import YieldingMotion

M3, K3, FY3, H3 = [1e5] * 3, [8e7] * 3, [6e5, 5e5, 3e5], [3.0] * 3
DT = 0.01


def bare(m, k, fy, b, h, zeta, p_delta=1, theta_c=0.1):
    law = check_storeys(k, fy, b, h, m, p_delta, 9.81, theta_c)
    return YieldingMotion(ShearBuilding(m, k, zeta, h, law.geometric), law, theta_c)


def ground(seconds, sigma, seed):
    return np.random.default_rng(seed).normal(0.0, sigma, int(round(seconds / DT)) + 1)


@pytest.fixture(scope="module")
def bare_runs():
    """Ours and the reference on the 3-storey building, P-Delta on, 20 s of strong motion."""
    ags = ground(20.0, 3.0, 1)
    ours = bare(M3, K3, FY3, [0.02] * 3, H3, 0.05)
    ours.storeys.log = []
    rows = []
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, [0.0] * 3, ags[i])
        rows.append(ours.x + [ours.viscous, ours.hysteretic])
    ref = Reference(M3, K3, FY3, [0.02] * 3, H3, 0.05, p_delta=True)
    Z = ref.run(np.arange(len(ags)) * DT, lambda t: ags[int(round(t / DT))])
    return ours, np.array(rows), ref, Z


def test_bare_building_matches_the_event_driven_reference(bare_runs):
    ours, rows, ref, Z = bare_runs
    x, xr = rows[:, :3], Z[1:, :3]
    peak = np.abs(xr).max(axis=0)
    assert len(ref.events) > 150  # hundreds of yield and unload events
    assert (np.abs(x - xr).max(axis=0) / peak).max() < 1e-8
    # energies: the dashpots' and the hysteretic, each against the reference's own integral
    assert rows[-1, 3] == pytest.approx(Z[-1, -2], rel=1e-8)
    assert rows[-1, 4] == pytest.approx(Z[-1, -1], rel=1e-8)


def test_bare_building_events_agree_in_count_and_time(bare_runs):
    ours, _, ref, _ = bare_runs
    mine = [(t, i, {YIELD: "yield", UNLOAD: "unload"}[kind]) for t, i, kind in ours.storeys.log]
    assert len(mine) == len(ref.events)
    for (t, i, kind), (tr, kr, ir) in zip(mine, ref.events):
        assert (i, kind) == (ir, kr)
        assert abs(t - tr) < 1e-9


def test_energy_balance_closes_with_hysteresis(bare_runs):
    ours = bare_runs[0]
    balance = ours.energy0 + ours.work_in - ours.energy() - ours.viscous - ours.hysteretic
    assert abs(balance) < 1e-9 * ours.work_in
    assert ours.hysteretic > 0.1 * ours.work_in  # the storeys did yield hard


@pytest.fixture(scope="module")
def damped_runs():
    ags = ground(20.0, 3.0, 1)
    p = Params(storeys=3, mu=0.05, FR=1.0, d=0.02, e=0.6, fidelity=1, zeta_s=0.05, zeta_p=0.02, storey_Fy=FY3,
               storey_b=[0.02] * 3, p_delta=1, floor_m=M3, storey_k=K3)
    ours = Damper(p)
    ours.model.storeys.log = []
    modes = set()
    rows = []
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, 0.0, ags[i])
        modes.add(ours.mode)
        rows.append(ours.floors()[0] + [ours.y, ours.viscous, ours.model.storeys.hysteretic])
    ref = Reference(M3, K3, FY3, [0.02] * 3, H3, 0.05, p_delta=True,
                    damper=dict(floor=2, m=p.m, w1=p.w1, zeta_p=0.02, d=0.02, e=0.6))
    Z = ref.run(np.arange(len(ags)) * DT, lambda t: ags[int(round(t / DT))])
    return ours, np.array(rows), ref, Z, modes


def test_damped_building_matches_the_event_driven_reference(damped_runs):
    ours, rows, ref, Z, modes = damped_runs
    assert modes == {0}  # free flight between impacts: the reference has no sticking
    impacts = [e for e in ref.events if e[1] == "impact"]
    assert len(impacts) == ours.impacts > 30
    assert len(ref.events) - len(impacts) > 150
    x, xr = rows[:, :4], Z[1:, [0, 1, 2, 6]]
    assert (np.abs(x - xr).max(axis=0) / np.abs(xr).max(axis=0)).max() < 1e-8
    assert rows[-1, 4] == pytest.approx(Z[-1, -2], rel=1e-8)
    assert rows[-1, 5] == pytest.approx(Z[-1, -1], rel=1e-8)
    balance = ours.energy0 + ours.work_in - ours.energy - ours.viscous - ours.dissipated - rows[-1, 5]
    assert abs(balance) < 1e-9 * ours.work_in


def test_damped_building_storey_events_agree(damped_runs):
    ours, _, ref, _, _ = damped_runs
    mine = [(t, i, {YIELD: "yield", UNLOAD: "unload"}[kind]) for t, i, kind in ours.model.storeys.log]
    theirs = [e for e in ref.events if e[1] != "impact"]
    assert len(mine) == len(theirs)
    for (t, i, kind), (tr, kr, ir) in zip(mine, theirs):
        assert (i, kind) == (ir, kr) and abs(t - tr) < 1e-9


# ---- one storey against piecewise closed forms ------------------------------------------------

def _one_storey(b, p_delta, zeta, x0, v0, regime):
    """A single storey put in `regime` at drift x0, velocity v0 (yielding: its plastic drift follows)."""
    m, k, fy, h = 1e5, 8e7, 4e5, 3.0
    ym = bare([m], [k], [fy], [b], [h], zeta, p_delta=p_delta, theta_c=1.0)
    state = ym.get_state()
    state["x"], state["v"] = [x0], [v0]
    state["storeys"]["regime"] = [regime]
    state["storeys"]["dp"] = [x0 - regime * fy / k] if regime else [0.0]
    ym.set_state(state)
    return ym, m, k, fy, ym.b.C[0][0], ym.storeys.law.geometric[0]


@pytest.mark.parametrize("b, p_delta", [(0.0, 0), (0.0, 1), (0.02, 1)])
def test_one_yielding_storey_follows_its_closed_form(b, p_delta):
    """Yielding up from drift x0 at speed v0: m x'' + c x' + kt x = -(1 - b) Fy with kt = b k - P/h,
    zero (polynomial-exponential) or negative (cosh / sinh growth), until the drift velocity reverses."""
    x0, v0 = 0.005, 0.3
    ym, m, k, fy, c, kg = _one_storey(b, p_delta, 0.05, x0, v0, 1)
    kt = b * k - kg
    rhs = -(1 - b) * fy / m
    cm, km = c / m, kt / m
    disc = cmath.sqrt(0.25 * cm * cm - km)
    r1, r2 = -0.5 * cm + disc, -0.5 * cm - disc  # distinct: real (kt <= 0) or a complex pair
    xp = rhs / km if km else None

    def closed(t):
        if km == 0.0:  # x'' + c x' = rhs: x0 + (rhs / c) t + (v0 - rhs / c)(1 - exp(-c t)) / c
            return x0 + rhs / cm * t + (v0 - rhs / cm) * -math.expm1(-cm * t) / cm
        a1 = (v0 - r2 * (x0 - xp)) / (r1 - r2)
        a2 = (x0 - xp) - a1
        return xp + (a1 * cmath.exp(r1 * t) + a2 * cmath.exp(r2 * t)).real

    t = 0.0
    for step in np.linspace(0.002, 0.02, 10):
        t += step
        ym.advance(t, [0.0])
        if ym.storeys.regime[0] != 1:
            break
        assert ym.x[0] == pytest.approx(closed(t), rel=1e-12, abs=1e-12 * abs(x0))
    assert t > 0.02  # at least a few points were compared while it yielded


def test_negative_tangent_grows_to_collapse_at_its_limit():
    """b k - P/h < 0: the yielding storey runs away; the collapse is located at the limit drift."""
    law_b, theta_c = 0.0, 0.05
    m, k, fy, h = 1e5, 8e7, 4e5, 3.0
    ym = bare([m], [k], [fy], [law_b], [h], 0.02, p_delta=1, theta_c=theta_c)
    reasons = []
    ym.on_collapse = lambda t, reason: reasons.append((t, reason))
    t = 0.0
    while not ym.collapsed and t < 10:
        t += 0.01
        ym.advance(t, [0.0], 8.0 if t <= 1.0 else 0.0)
    assert ym.collapsed and "storey 1" in reasons[0][1]
    assert abs(ym.x[0]) == pytest.approx(theta_c * h, rel=1e-12)
    held = (list(ym.x), ym.hysteretic, ym.peaks.drift[0])
    ym.advance(t + 1.0, [0.0], 5.0)
    assert (list(ym.x), ym.hysteretic, ym.peaks.drift[0]) == held  # every value holds
    assert ym.t == t + 1.0


# ---- bad input -----------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, name", [
    (dict(storey_Fy=[-1.0, 0, 0]), "storey[1].Fy"),
    (dict(storey_Fy=[1e5, 1e5, 1e5], storey_b=[0.0, 1.0, 0.0]), "storey[2].b"),
    (dict(storey_Fy=[1e5, 1e5, 1e5], collapse_drift=0.0), "collapse_drift"),
    (dict(storey_Fy=[1e5, 1e5, 1e5], collapse_drift=1.5), "collapse_drift"),
    (dict(p_delta=1, storey_k=[8e7, 8e7, 1e5]), "storey[3].k"),
    (dict(storey_Fy=[1e5, 1e5, 1e5], storey_b=[0.0] * 3, zeta_s=0.0), "storey[1].b"),
])
def test_bad_yielding_parameters_are_refused_by_name(kwargs, name):
    base = dict(storeys=3, fidelity=1, zeta_s=0.05, floor_m=M3, storey_k=K3)
    with pytest.raises(ParameterError) as err:
        Params(**{**base, **kwargs})
    assert err.value.name == name


def test_elastic_storeys_keep_the_elastic_core():
    """Fy = 0 everywhere: no storey law at all (the elastic code path, bit for bit)."""
    p = Params(storeys=3, floor_m=M3, storey_k=K3, storey_b=[0.5] * 3)
    assert p.law is None and Damper(p).model.storeys is None


# ---- stress: dense events ------------------------------------------------------------------------

def test_a_thousand_events_per_second_stay_exact_and_balanced():
    """A weak first storey (yield drift 25 um) shaken at 300 Hz (held per 1e-4 s): more than 1000
    yield and unload events per simulated second, against the reference; the balance closes."""
    fy, dt, steps = [2e3, 2e3, 2e3], 1e-4, 1000
    ags = [200.0 * math.cos(2 * math.pi * 300 * i * dt) for i in range(steps + 1)]
    ours = bare(M3, K3, fy, [0.02] * 3, H3, 0.05)
    xs = []
    for i in range(steps):
        ours.advance((i + 1) * dt, [0.0] * 3, ags[i])
        xs.append(list(ours.x))
    assert ours.storeys.events >= 1000 * steps * dt
    ref = Reference(M3, K3, fy, [0.02] * 3, H3, 0.05, p_delta=True)
    Z = ref.run(np.arange(steps + 1) * dt, lambda t: ags[int(round(t / dt))])
    assert len(ref.events) == ours.storeys.events
    xr = Z[1:, :3]
    assert (np.abs(np.array(xs) - xr).max(axis=0) / np.abs(xr).max(axis=0)).max() < 1e-8
    balance = ours.energy0 + ours.work_in - ours.energy() - ours.viscous - ours.hysteretic
    assert abs(balance) < 1e-9 * ours.work_in


# ---- energy over drawn yielding runs ---------------------------------------------------------------

@settings(max_examples=200, deadline=None, derandomize=True)
@given(fy=st.floats(5e4, 6e5), b=st.floats(0.0, 0.3), zeta=st.floats(0.01, 0.1), p_delta=st.integers(0, 1),
       sigma=st.floats(2.0, 8.0), seed=st.integers(0, 10 ** 6))
def test_hysteretic_and_dashpot_energies_match_the_reference(fy, b, zeta, p_delta, sigma, seed):
    """Over 200 drawn 2-storey yielding runs (0.5 s of random ground motion held per 0.01 s): the
    hysteretic and the dashpots' energy each agree with the reference's integrals, and the balance
    E(0) + work_in = E + viscous + hysteretic closes to 1e-9 of the input."""
    m, k, h = [1e5, 1e5], [8e7, 6e7], [3.0, 3.0]
    ys, bs = [fy, 0.7 * fy], [b, b]
    ours = bare(m, k, ys, bs, h, zeta, p_delta=p_delta, theta_c=1.0)
    ags = ground(0.5, sigma, seed)
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, [0.0, 0.0], ags[i])
    # a regime whose modes coincide (b = zeta^2 makes both yielding modes critically damped: a
    # defective pair, no modal closed form) stops the building with its reason; not a run to compare
    assume(not ours.collapsed)
    ref = Reference(m, k, ys, bs, h, zeta, p_delta=bool(p_delta))
    Z = ref.run(np.arange(len(ags)) * DT, lambda t: ags[int(round(t / DT))])
    assert_energy_matches(ours, Z)


def test_a_regime_without_modes_collapses_with_its_reason():
    """b = zeta^2 with proportional damping: both storeys yielding together are critically damped
    (a defective pair of modes): the building stops there, with the reason, never a NaN."""
    m, k, h = [1e5, 1e5], [8e7, 6e7], [3.0, 3.0]
    ours = bare(m, k, [5e4, 3.5e4], [0.0625 ** 2] * 2, h, 0.0625, p_delta=0, theta_c=1.0)
    reasons = []
    ours.on_collapse = lambda t, reason: reasons.append(reason)
    ags = ground(0.5, 2.0, 0)
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, [0.0, 0.0], ags[i])
        assert all(map(math.isfinite, ours.x + ours.v))
    assert ours.collapsed and "coincide" in reasons[0] and "(1, 1)" in reasons[0]


def test_a_mechanism_of_two_zero_tangent_storeys_matches_the_reference():
    """b = 0 without P-Delta: both storeys yielding together have K_t = 0 (a double zero
    eigenvalue, semi-simple under damping): against the reference."""
    m, k, h, fy = [1e5, 1e5], [8e7, 6e7], [3.0, 3.0], [5e4, 3.5e4]
    ours = bare(m, k, fy, [0.0, 0.0], h, 0.0625, p_delta=0, theta_c=1.0)
    ags = ground(0.5, 2.0, 0)
    regimes = set()
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, [0.0, 0.0], ags[i])
        regimes.add(tuple(ours.storeys.regime))
    assert {(1, 1), (-1, -1)} & regimes
    ref = Reference(m, k, fy, [0.0, 0.0], h, 0.0625)
    Z = ref.run(np.arange(len(ags)) * DT, lambda t: ags[int(round(t / DT))])
    assert np.abs(np.array(ours.x) - Z[-1, :2]).max() < 1e-9 * np.abs(Z[:, :2]).max()
    assert ours.hysteretic == pytest.approx(Z[-1, -1], rel=1e-9)
