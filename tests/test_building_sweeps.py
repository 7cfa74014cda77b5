"""Property sweeps over the yielding and contact parameters of both building families and the damper
unit (issue 35): each draws at least 300 cases and runs at least 200 through; a refusal must name
its value with its rule, and every run that ran is checked against invariants it does not compute
itself: finite outputs, no storey force beyond its yield surface, no particle through a stop, the
energy balance (and the loads' work summed independently over the steps), and, for a building whose
storeys never reached their yield force, the elastic building (Fy = 0): bit for bit for the bare
building; for the damped one bit for bit where the storeys' limits stay out of reach, to rounding
where its event search watched one that never fired (impacts amplify that rounding: not compared)."""
import math
import random
import re

import pytest
from hypothesis import HealthCheck, event, given, settings, strategies as st

from pidamper_physics import Damper, ParameterError, Params
from pidamper_physics.unit import DamperUnit
from pidamper_physics.yielding import YieldingMotion, building_motion

SETTINGS = settings(max_examples=360, deadline=None, suppress_health_check=[HealthCheck.too_slow], database=None,
                    derandomize=True)
STEPS = 48
G = 9.81


def _log(lo, hi):
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda u: 10.0 ** u)


def _rule(err, rules):
    """The refusal names a value the rules know (storey indices as [k]) and gives its rule."""
    name = re.sub(r"\[\d+\]", "[k]", str(err.name))
    assert name in rules, f"unexpected refusal {err}"
    assert any(piece in err.allowed for piece in rules[name]), f"{err.name} refused without its rule: {err}"
    event(f"refused: {name}")


def _yield_force(kind, size, k, h):
    """A storey's yield force of a kind: none, tiny (a zero-strength storey), near the drifts the
    forcing reaches (a yield drift ratio of 0.5 % times `size`), or far beyond any force."""
    return {"zero": 0.0, "tiny": 10.0 ** (-40.0 + 37.0 * size), "near": k * 0.005 * h * 10.0 ** (2.0 * size - 1.0),
            "huge": 10.0 ** (12.0 + 190.0 * size)}[kind]


STOREY = st.tuples(st.sampled_from(["zero", "tiny", "near", "near", "huge"]), st.floats(0.0, 1.0),
                   st.floats(0.5, 2.0), st.floats(0.5, 2.0), st.floats(0.0, 0.3))
#: refusals at the start (the scales float arithmetic holds, a yield drift it cannot, a building
#: that would not stand under P-Delta, a zero-tangent storey without damping) and in a step
START_RULES = {"floor[k].m": ["must lie in"], "storey[k].k": ["must lie in", "would not stand"],
               "storey[k].Fy": ["yield drift"], "storey[k].b": ["needs damping"], "zeta_s": ["1 - zeta_s^2"],
               "g, M, mu, L2, FR": ["lies outside"], "mu": ["lies outside"], "d": ["lies outside"],
               "R": ["radius"], "storeys, floor[k].m, storey[k].k, mu, FR, zeta_s, zeta_p": ["distinct"],
               "mu, FR, zeta_s, zeta_p": ["distinct"]}
STEP_RULES = {"step": ["take shorter"], "a_g, F": ["range of float arithmetic"], "d": ["cannot be resolved"],
              "F, a_g": ["range of float arithmetic"]}


def _forcing(amplitude, w, phase, h):
    return [amplitude * math.sin(w * k * h + phase) for k in range(STEPS)]


# ---- the bare building (ShearBuilding<N>) -----------------------------------------------------

BARE = {"drawn": 0, "ran": 0, "elastic": 0}


def test_bare_building_sweep():
    """ShearBuilding's physics across storeys, strengths, hardening, P-Delta, damping, collapse
    limits, ground motion and floor impulses."""
    BARE.update(drawn=0, ran=0, elastic=0)
    _bare_sweep()
    assert BARE["drawn"] >= 300 and BARE["ran"] >= 200 and BARE["elastic"] >= 30, BARE


@SETTINGS
@given(storeys=st.lists(STOREY, min_size=1, max_size=4), m0=_log(1e2, 1e7), k0=_log(1e5, 1e10),
       zeta=st.one_of(st.just(0.0), st.floats(0.0, 0.3)), p_delta=st.sampled_from([0, 1]),
       theta_c=st.floats(0.01, 1.0), amplitude=_log(1e-3, 10.0), ratio=st.floats(0.3, 3.0), phase=st.floats(0, 6.3),
       per_period=_log(2.0, 200.0), kicks=st.one_of(st.just(0.0), _log(1e-3, 1.0)), seed=st.integers(0, 2 ** 16))
def _bare_sweep(storeys, m0, k0, zeta, p_delta, theta_c, amplitude, ratio, phase, per_period, kicks, seed):
    BARE["drawn"] += 1
    n = len(storeys)
    m = [m0 * f for _, _, f, _, _ in storeys]
    k = [k0 * f for _, _, _, f, _ in storeys]
    hs = [3.0] * n
    fy = [_yield_force(kind, size, kk, 3.0) for (kind, size, *_), kk in zip(storeys, k)]
    b = [s[4] for s in storeys]
    try:
        core = building_motion(m, k, hs, zeta, fy, b, p_delta, G, theta_c)
        elastic = building_motion(m, k, hs, zeta, [0.0] * n, b, p_delta, G, theta_c)
    except ParameterError as err:
        _rule(err, START_RULES)
        return
    w1 = elastic.b.w_1
    h = 2.0 * math.pi / w1 / per_period
    ground = _forcing(amplitude * G, ratio * w1, phase, h)
    rng = random.Random(seed)
    impulses = [[(h * (i + rng.random()), rng.randrange(n), kicks * m[-1] * amplitude * G / w1 * rng.uniform(-1, 1))]
                if kicks and rng.random() < 0.2 else [] for i in range(STEPS)]
    try:
        rows, work, scale = _run_bare(core, ground, impulses, h)
    except ParameterError as err:
        _rule(err, STEP_RULES)
        return
    BARE["ran"] += 1
    yielding = isinstance(core, YieldingMotion)
    if yielding:
        _check_balance(core, work, scale, any(impulses))
        assert not core.collapsed or "reached the drift ratio" in core.storeys.collapse_reason  # never for want of modes
    never = not yielding or core.storeys.events == 0
    event(f"ran: {'yielding' if yielding and not never else 'elastic'}")
    if never:  # no storey reached its yield force (nor the collapse limit): the elastic building
        BARE["elastic"] += 1
        assert _run_bare(elastic, ground, impulses, h)[0] == rows


def _run_bare(core, ground, impulses, h):
    """Rows of (x, v, peaks) per step; the loads' work summed as (F - m a_g) dx over the steps;
    the largest energy and work of the run (the balance's rounding scale)."""
    rows, work, zero = [], 0.0, [0.0] * core.n
    masses = core.b.masses
    scale = 0.0
    for i, (ag, kicks) in enumerate(zip(ground, impulses)):
        x0 = core.floors()[0]
        core.advance((i + 1) * h, zero, ag, kicks)
        x, v = core.floors()
        work -= ag * sum(mk * (b - a) for mk, a, b in zip(masses, x0, x))
        scale = max(scale, core.energy(), abs(core.work_in), abs(work))
        values = x + v + core.peaks.drift + core.peaks.velocity + core.peaks.acceleration
        assert all(map(math.isfinite, values))
        if isinstance(core, YieldingMotion):
            _check_surfaces(core)
        rows.append(values)
    return rows, work, scale


def _check_surfaces(core):
    """No storey's elastic-perfectly-plastic spring carries more than (1 - b) Fy."""
    law = core.storeys.law
    for i, (force, d) in enumerate(zip(core.storey_forces(), core.drifts())):
        if law.yields[i]:
            epp = force - law.b[i] * law.k[i] * d
            assert abs(epp) <= (1.0 - law.b[i]) * law.Fy[i] * (1.0 + 1e-9) + 1e-12 * law.k[i] * abs(d)


def _check_balance(core, work, scale, kicked):
    """E(0) + work_in = E + viscous + hysteretic, and work_in is the loads' work summed over the
    steps (impulses' work is not observable from the steps: checked without them)."""
    scale = max(scale, core.energy0, core.viscous, core.hysteretic, 1e-300)
    assert core.energy0 + core.work_in - core.energy() - core.viscous - core.hysteretic == pytest.approx(
        0.0, abs=1e-9 * scale)
    if not kicked:
        assert core.work_in == pytest.approx(work, abs=1e-9 * scale)


# ---- the damped building (DampedShearBuilding<N>) ------------------------------------------------

DAMPED = {"drawn": 0, "ran": 0, "elastic": 0, "far": 0}


def test_damped_building_sweep():
    """The particle on a yielding building across the storeys' strengths and the contact:
    clearance, restitution, its laws from the materials, mass and tuning."""
    DAMPED.update(drawn=0, ran=0, elastic=0, far=0)
    _damped_sweep()
    assert DAMPED["drawn"] >= 300 and DAMPED["ran"] >= 200 and DAMPED["far"] >= 10, DAMPED


@SETTINGS
@given(storeys=st.lists(STOREY, min_size=1, max_size=3), zeta=st.floats(0.0, 0.2), zeta_p=st.floats(0.0, 0.2),
       fidelity=st.sampled_from([1, 2]), p_delta=st.sampled_from([0, 1]), theta_c=st.floats(0.01, 1.0),
       mu=st.one_of(st.just(0.0), _log(1e-3, 0.3)), FR=st.floats(0.5, 1.5), d_rel=_log(1e-3, 10.0),
       e=st.floats(0.0, 1.0), law=st.sampled_from([0, 0, 1, 2, 3]), R=_log(1e-3, 0.3), amplitude=_log(1e-3, 5.0),
       ratio=st.floats(0.5, 2.0), phase=st.floats(0, 6.3), per_period=_log(4.0, 100.0))
def _damped_sweep(storeys, zeta, zeta_p, fidelity, p_delta, theta_c, mu, FR, d_rel, e, law, R, amplitude, ratio,
                  phase, per_period):
    DAMPED["drawn"] += 1
    n = len(storeys)
    m = [1e5 * f for _, _, f, _, _ in storeys]
    k = [8e7 * f for _, _, _, f, _ in storeys]
    fy = [_yield_force(kind, size, kk, 3.0) for (kind, size, *_), kk in zip(storeys, k)]
    d = d_rel * amplitude * G * sum(m) / k[0] + 1e-6
    values = dict(storeys=n, fidelity=fidelity, zeta_s=zeta, zeta_p=zeta_p, p_delta=p_delta, collapse_drift=theta_c,
                  mu=mu, FR=FR, d=d, e=e, floor_m=m, storey_k=k, storey_b=[s[4] for s in storeys],
                  restitution=law, R=R if law else 0.0)
    try:
        core = Damper(Params(**values, storey_Fy=fy))
        elastic = Damper(Params(**values))
    except ParameterError as err:
        _rule(err, START_RULES)
        return
    core.bound_work()
    elastic.bound_work()
    w1 = core.p.building.w_1
    h = 2.0 * math.pi / w1 / per_period
    ground = _forcing(amplitude * G, ratio * w1, phase, h)
    try:
        rows, scale = _run_damped(core, ground, h)
    except ParameterError as err:
        _rule(err, STEP_RULES)
        return
    DAMPED["ran"] += 1
    storeys_state = core.model.storeys
    assert not core.halted or "reached the drift ratio" in storeys_state.collapse_reason  # never for want of modes
    never = storeys_state is None or storeys_state.events == 0
    event(f"ran: {'elastic' if never else 'yielding'}, {'with' if core.impacts else 'no'} impacts")
    if never:
        DAMPED["elastic"] += 1
        theirs = _run_damped(elastic, ground, h)[0]
        if storeys_state is None:  # no storey can yield: the same model
            assert theirs == rows
        elif _far(storeys_state, elastic):  # the storeys' limits out of every piece's reach: bit for bit
            DAMPED["far"] += 1
            event("elastic: far from the limits, bit for bit")
            assert theirs == rows
        elif not core.impacts:  # the event search watched a limit that never fired: to rounding
            event("elastic: near a limit, to rounding")
            for mine, twin in zip(rows, theirs):
                assert twin == pytest.approx(mine, rel=1e-9, abs=1e-9 * max(map(abs, mine)) + 1e-300)
            assert elastic.energy == pytest.approx(core.energy, abs=1e-9 * scale)
        else:  # impacts amplify that rounding (a chatter's count may differ by one): nothing to compare
            event("elastic: near a limit, with impacts")


def _far(storeys, elastic):
    """Whether every storey's yield and collapse limits lie beyond 100 times its largest drift of
    the elastic run: a piece (at most one period of the fastest mode) cannot bring a guard nearer
    than 2 pi n times the largest drift, so no storey guard is ever watched."""
    law = storeys.law
    for i, (ratio, h) in enumerate(zip(elastic.model.peaks.drift, storeys.heights)):
        reach = min(law.reach[i], storeys.theta_c * h) if law.yields[i] else storeys.theta_c * h
        if not reach > 100.0 * ratio * h:
            return False
    return True


def _run_damped(core, ground, h):
    rows = []
    p = core.p
    scale = core.energy0
    for i, ag in enumerate(ground):
        core.advance((i + 1) * h, 0.0, ag)
        xs, accs, drifts, shear = core.building_outputs(0.0, ag)
        values = list(xs) + list(accs) + [core.y, core.u, core.impacts] + core.model.peaks.drift
        assert all(map(math.isfinite, values + [shear, core.energy]))
        assert abs(core.x - core.y) <= p.d * (1.0 + 1e-9) + 1e-12 * (abs(core.x) + abs(core.y))
        rows.append(values)
        scale = max(scale, core.energy, abs(core.work_in))
    storeys = core.model.storeys
    hysteretic = 0.0 if storeys is None else storeys.hysteretic
    scale = max(scale, core.dissipated, core.viscous, hysteretic, 1e-300)
    assert core.energy0 + core.work_in - core.energy - core.dissipated - core.viscous - hysteretic == pytest.approx(
        0.0, abs=1e-9 * scale)
    return rows, scale


# ---- the damper unit (PendulumImpactDamperUnit) ---------------------------------------------------

UNIT = {"drawn": 0, "ran": 0}
UNIT_RULES = {"m": ["must be", "lie in"], "M_s": ["> 0", "lie in"], "L1": ["lie in", "> 0"], "d": ["> 0", "lie in"],
              "g, L1": ["lies outside"], "R": ["radius"], "zeta_p": ["[0, 1)"], "r_0": ["within the stops"]}
UNIT_STEP_RULES = {"step": ["take shorter"], "a_s": ["range of float arithmetic"], "d": ["cannot be resolved"]}


def test_unit_sweep():
    """The unit alone across its mass against the structure's, wire, clearance, restitution and
    its laws, dashpot, coupling mode and the attachment's motion: the particle's energy in the
    attachment's frame changes only by the held acceleration's work, the impacts' jumps (as the
    unit reports them) and, with a dashpot, a loss."""
    UNIT.update(drawn=0, ran=0)
    _unit_sweep()
    assert UNIT["drawn"] >= 300 and UNIT["ran"] >= 200, UNIT


@SETTINGS
@given(m=_log(1e-3, 1e4), M_ratio=st.one_of(_log(1.01, 1e4), _log(1.01, 1e4), _log(1.01, 1e4), _log(0.9, 1.01)),
       L1=_log(1e-3, 1e2), d=_log(1e-9, 1.0), e=st.floats(0.0, 1.0),
       zeta_p=st.one_of(st.just(0.0), st.floats(0.0, 0.3)), aware=st.sampled_from([0, 1]),
       law=st.sampled_from([0, 0, 1, 2, 3]), R=_log(1e-3, 0.3), amplitude=_log(1e-2, 1e2), ratio=st.floats(0.3, 3.0),
       phase=st.floats(0, 6.3), per_period=_log(2.0, 200.0), r0=st.floats(-1.02, 1.02))
def _unit_sweep(m, M_ratio, L1, d, e, zeta_p, aware, law, R, amplitude, ratio, phase, per_period, r0):
    UNIT["drawn"] += 1
    try:
        unit = DamperUnit(m=m, M_s=m * M_ratio, L1=L1, d=d, e=e, zeta_p=zeta_p, impulse_aware=aware, r_0=r0 * d,
                          restitution=law, R=R if law else 0.0)
    except ParameterError as err:
        _rule(err, UNIT_RULES)
        return
    unit.bound_work()
    jumps = []
    unit.on_impact = lambda t, side, J, before, after, loss: jumps.append(0.5 * m * (after * after - before * before))
    w = unit.w
    h = 2.0 * math.pi / w / per_period
    accel = _forcing(amplitude * w * w * d, ratio * w, phase, h)

    def energy():
        return 0.5 * m * (unit.rd * unit.rd + w * w * unit.r * unit.r)

    e0, work = energy(), 0.0
    scale = e0
    try:
        for i, a_s in enumerate(accel):
            r_start = unit.r
            unit.advance((i + 1) * h, a_s)
            work -= m * a_s * (unit.r - r_start)
            scale = max(scale, energy(), abs(work))
            assert all(map(math.isfinite, (unit.r, unit.rd, unit.F_s, unit.J_s, unit.t_J, unit.dissipated)))
            assert abs(unit.r) <= d * (1.0 + 1e-9)
    except ParameterError as err:
        _rule(err, UNIT_STEP_RULES)
        return
    UNIT["ran"] += 1
    event(f"ran: {'with' if unit.impacts else 'no'} impacts, dashpot {'on' if zeta_p else 'off'}")
    scale = max(scale, sum(abs(j) for j in jumps), 1e-300)
    lost = e0 + work + sum(jumps) - energy()  # what the dashpot took
    assert lost == pytest.approx(0.0, abs=1e-9 * scale) if zeta_p == 0.0 else lost >= -1e-9 * scale
