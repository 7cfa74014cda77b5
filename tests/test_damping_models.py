"""The buildings' damping models (issue 37, item 4): modal (every elastic mode at zeta_s, the matrix
kept while storeys yield), Rayleigh on the initial stiffness, Rayleigh on the tangent stiffness of
the storeys' current regime; against the independent event-driven reference (scipy's DOP853, its
own matrices: pidamper.oracles.yielding_reference) and OpenSees's `rayleigh`."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from energy_checks import assert_energy_matches
from pidamper.oracles.yielding_reference import Reference
from pidamper_physics import Damper, Params
from pidamper_physics.params import ParameterError, check_building
from pidamper_physics.shear_motion import ShearMotion
from pidamper_physics.yielding import YieldingMotion, building_motion

M3, K3, FY3, B3, H3 = [1e5] * 3, [8e7] * 3, [6e5, 5e5, 3e5], [0.02] * 3, [3.0] * 3
DT = 0.01
NAMES = {0: "modal", 1: "rayleigh-initial", 2: "rayleigh-tangent"}


def ground(steps, sigma, seed):
    return np.random.default_rng(seed).normal(0.0, sigma, steps + 1)


def _bare_run(damping, ags, zeta=0.05):
    ours = building_motion(M3, K3, H3, zeta, FY3, B3, p_delta=1, damping=damping)
    rows = []
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, [0.0] * 3, ags[i])
        rows.append(ours.x + [ours.viscous, ours.hysteretic])
    return ours, np.array(rows)


@pytest.mark.parametrize("damping", [1, 2])
def test_the_yielding_building_matches_the_reference_under_rayleigh_damping(damping):
    """8 s of strong motion on the 3-storey building with P-Delta, dozens of yield and unload
    events: floors, the dashpots' and the hysteretic energy against the reference to 1e-8, the
    energy balance closed."""
    ags = ground(800, 3.0, 3)
    ours, rows = _bare_run(damping, ags)
    ref = Reference(M3, K3, FY3, B3, H3, 0.05, p_delta=True, damping=NAMES[damping])
    Z = ref.run(np.arange(len(ags)) * DT, lambda t: ags[int(round(t / DT))])
    assert len(ref.events) > 60
    x, xr = rows[:, :3], Z[1:, :3]
    assert (np.abs(x - xr).max(axis=0) / np.abs(xr).max(axis=0)).max() < 1e-8
    assert rows[-1, 3] == pytest.approx(Z[-1, -2], rel=1e-8)
    assert rows[-1, 4] == pytest.approx(Z[-1, -1], rel=1e-8)
    balance = ours.energy0 + ours.work_in - ours.energy() - ours.viscous - ours.hysteretic
    assert abs(balance) < 1e-9 * ours.work_in


def test_tangent_damping_takes_the_yielding_storeys_dashpots_away():
    """Under Rayleigh on the tangent a yielding storey's stiffness-proportional dashpot shrinks with
    its tangent: the dashpots take less energy than under the initial stiffness (the same record;
    3 % less here: the storeys yield for short stretches)."""
    ags = ground(800, 3.0, 3)
    initial, tangent = _bare_run(1, ags)[0], _bare_run(2, ags)[0]
    assert tangent.hysteretic > 0.2 * tangent.work_in  # the storeys yielded hard
    assert tangent.viscous < 0.98 * initial.viscous


@pytest.mark.parametrize("damping", [1, 2])
def test_the_damped_building_matches_the_reference_under_rayleigh_damping(damping):
    """The 3-storey yielding building with the pendulum damper on its roof under either Rayleigh
    model: floors and particle against the reference with its particle, to 1e-8."""
    ags = ground(800, 3.0, 1)
    p = Params(storeys=3, mu=0.05, FR=1.0, d=0.02, e=0.6, fidelity=1, zeta_s=0.05, zeta_p=0.02, storey_Fy=FY3,
               storey_b=B3, p_delta=1, floor_m=M3, storey_k=K3, damping=damping)
    ours = Damper(p)
    modes, rows = set(), []
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, 0.0, ags[i])
        modes.add(ours.mode)
        rows.append(ours.floors()[0] + [ours.y, ours.viscous, ours.model.storeys.hysteretic])
    ref = Reference(M3, K3, FY3, B3, H3, 0.05, p_delta=True, damping=NAMES[damping],
                    damper=dict(floor=2, m=p.m, w1=p.w1, zeta_p=0.02, d=0.02, e=0.6))
    Z = ref.run(np.arange(len(ags)) * DT, lambda t: ags[int(round(t / DT))])
    rows = np.array(rows)
    assert modes == {0} and ours.impacts > 10
    x, xr = rows[:, :4], Z[1:, [0, 1, 2, 6]]
    assert (np.abs(x - xr).max(axis=0) / np.abs(xr).max(axis=0)).max() < 1e-8
    assert rows[-1, 4] == pytest.approx(Z[-1, -2], rel=1e-8)
    assert rows[-1, 5] == pytest.approx(Z[-1, -1], rel=1e-8)


def test_rayleigh_gives_each_elastic_mode_its_ratio():
    """The elastic building (ShearMotion, by modes) started in mode r decays at that mode's
    Rayleigh ratio a0 / 2 w_r + a1 w_r / 2, zeta_s at modes 1 and 3: the envelope over a few
    cycles against exp(-zeta_r w_r t)."""
    m, k, h, zeta = [1.2e5, 1.0e5, 0.8e5, 0.8e5], [9e7, 8e7, 6e7, 5e7], [3.0] * 4, 0.04
    b = check_building(m, k, zeta, h, None, 1)
    w = b.omegas
    a1 = 2 * zeta / (w[0] + w[2])
    a0 = a1 * w[0] * w[2]
    for r in range(4):
        expected = a0 / (2 * w[r]) + a1 * w[r] / 2
        assert b.zetas[r] == pytest.approx(expected, rel=1e-13)
        motion = ShearMotion(b)
        phi = [b.shapes[i][r] for i in range(4)]
        motion.set_floors(phi, [0.0] * 4)
        t_d = 2 * math.pi / (w[r] * math.sqrt(1 - expected ** 2))
        motion.advance(3 * t_d, [0.0] * 4, 0.0)  # three damped periods later: the same shape, decayed
        x = motion.floors()[0]
        assert x[3] / phi[3] == pytest.approx(math.exp(-expected * w[r] * 3 * t_d), rel=1e-9)
    assert b.zetas[0] == pytest.approx(zeta, rel=1e-13) and b.zetas[2] == pytest.approx(zeta, rel=1e-13)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(damping=st.integers(1, 2), fy=st.floats(5e4, 6e5), b=st.floats(0.0, 0.3), zeta=st.floats(0.01, 0.1),
       p_delta=st.integers(0, 1), sigma=st.floats(2.0, 8.0), seed=st.integers(0, 10 ** 6))
def test_drawn_rayleigh_runs_match_the_reference_and_balance(damping, fy, b, zeta, p_delta, sigma, seed):
    """Over 60 drawn 2-storey yielding runs under either Rayleigh model (0.5 s of random ground
    motion held per 0.01 s): the hysteretic and the dashpots' energy each agree with the reference's
    integrals, and E(0) + work_in = E + viscous + hysteretic closes to 1e-9 of the input."""
    m, k, h = [1e5, 1e5], [8e7, 6e7], [3.0, 3.0]
    ys, bs = [fy, 0.7 * fy], [b, b]
    ours = building_motion(m, k, h, zeta, ys, bs, p_delta=p_delta, collapse_drift=1.0, damping=damping)
    ags = ground(50, sigma, seed)
    for i in range(len(ags) - 1):
        ours.advance((i + 1) * DT, [0.0, 0.0], ags[i])
    assume(not ours.collapsed)  # a regime whose modes coincide stops the building with its reason
    ref = Reference(m, k, ys, bs, h, zeta, p_delta=bool(p_delta), damping=NAMES[damping])
    Z = ref.run(np.arange(len(ags)) * DT, lambda t: ags[int(round(t / DT))])
    assert_energy_matches(ours, Z)


@pytest.mark.parametrize("damping", [-1, 3, 1.5, True, "2"])
def test_a_damping_model_outside_the_three_is_refused_by_name(damping):
    """By the bare building, the damped one and the pendulum's Params alike (where it has no use)."""
    for make in (lambda: building_motion(M3, K3, H3, 0.05, FY3, B3, damping=damping),
                 lambda: Params(storeys=3, fidelity=1, zeta_s=0.02, damping=damping), lambda: Params(damping=damping)):
        with pytest.raises(ParameterError, match=r"damping = .* is not allowed: it must be 0 \(modal"):
            make()


def test_rayleigh_that_overdamps_a_mode_is_refused():
    """Ten uniform storeys, zeta_s = 0.5 at modes 1 and 3: modes 8 to 10 would be overdamped (the
    first of them is named)."""
    with pytest.raises(ParameterError, match=r"zeta_s, damping.*mode 8 the ratio 1\.05"):
        check_building([1e5] * 10, [8e7] * 10, 0.5, [3.0] * 10, None, 1)


def test_the_default_is_today_s_modal_damping_bit_for_bit():
    """damping = 0 (the default) builds the very matrix the modal model always had."""
    a = check_building(M3, K3, 0.05, H3)
    b = check_building(M3, K3, 0.05, H3, None, 0)
    assert a.C == b.C and a.zetas == [0.05] * 3 and a.rayleigh is None
    assert isinstance(building_motion(M3, K3, H3, 0.05, FY3, B3, damping=2), YieldingMotion)


@pytest.mark.parametrize("damping", [1, 2])
def test_opensees_converges_to_each_rayleigh_model(damping):
    """OpenSees (`rayleigh` with betaKinit or betaK, the zeroLength springs with -doRayleigh 1,
    P-Delta springs included; Newmark, Newton) on the same building and held record converges to
    ours as its step falls (pidamper.benchmarks.damping_peer): its roof error shrinks at least
    threefold per fourfold shorter step (its events fall at its steps: first order) and ends below
    5e-3 of the peak."""
    from pidamper.benchmarks.damping_peer import roof_errors

    errors = roof_errors(damping, (2e-3, 5e-4, 1.25e-4))
    assert errors[1] < errors[0] / 3 and errors[2] < errors[1] / 3 and errors[2] < 5e-3, errors


@pytest.mark.parametrize("damper", [False, True])
def test_both_building_fmus_take_the_damping_model(fmu_dir, damper):
    """ShearBuilding3 and DampedShearBuilding3 with `damping = 2` run the tangent model: bit for bit
    with the core built with it, and not with the modal one (the parameter reaches the physics)."""
    from pidamper import find_fmu, forcing
    from pidamper.running.instance import FmuInstance

    values = {"zeta_s": 0.05, "p_delta": 1, "damping": 2, **{f"storey[{k}].Fy": fy for k, fy in zip((1, 2, 3), FY3)},
              **{f"storey[{k}].k": 8e7 for k in (1, 2, 3)}}
    if damper:
        values.update({"fidelity": 1, "mu": 0.05, "FR": 0.95, "d": 0.02, "e": 0.5})
        params = {k: v for k, v in values.items() if "[" not in k}
        cores = [Damper(Params(storeys=3, storey_Fy=FY3, storey_k=K3, **{**params, "damping": d})) for d in (2, 0)]
    else:
        cores = [building_motion(M3, K3, H3, 0.05, FY3, B3, p_delta=1, damping=d) for d in (2, 0)]
    signal = forcing.kanai_tajimi(4.0, pga=3.0, seed=3, dt=0.01)
    with FmuInstance(find_fmu(storeys=3, damper=damper), values) as fmu:
        for k in range(1, 401):
            a = float(signal.value(0.01 * (k - 1)))
            fmu.set("a_g", a)
            fmu.do_step(0.01 * (k - 1), 0.01)
            t = 0.01 * (k - 1) + 0.01  # the step's end as the host's clock has it
            for core in cores:
                core.advance(t, 0.0, a) if damper else core.advance(t, [0.0] * 3, a)
        roofs = [core.floors()[0][2] for core in cores]
        assert fmu.get("floor[3].x") == roofs[0] != roofs[1]
