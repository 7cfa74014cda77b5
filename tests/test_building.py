"""The damper on a shear building (storeys >= 1), checked against independent oracles:
scipy.linalg.expm of the bare building's state matrix, an event-driven solve_ivp integration with
its own impact and stick logic (pidamper/oracles/building_reference.py), and the `coupled` level it must
reproduce at one storey.  (That the pendulum levels are unchanged by any change is tools/equivalence.py's
to show, against the revision it names; their oracles are in test_levels.py and test_nonlinear.py.)"""
import math

import numpy as np
import pytest
import scipy.linalg

from pidamper.oracles.building_reference import simulate
from pidamper_physics import Damper, ParameterError, Params
from pidamper_physics.building import ShearBuilding

MASSES = [1.0e5, 1.2e5, 0.9e5, 1.1e5, 1.0e5, 0.8e5, 1.3e5, 1.0e5, 0.9e5, 1.2e5]
STIFF = [2.0e8, 1.6e8, 1.2e8, 1.8e8, 1.5e8, 1.1e8, 1.9e8, 1.4e8, 1.3e8, 1.7e8]


def building(n, **values):
    return Params(storeys=n, floor_m=MASSES[:n], storey_k=STIFF[:n], **values)


@pytest.mark.parametrize("n,fidelity,zeta", [(3, 0, 0.0), (3, 1, 0.05), (10, 0, 0.0), (10, 2, 0.03)])
def test_bare_building_against_expm(n, fidelity, zeta):
    """mu = 0 and stops out of reach: the floors follow exp(A t) under held F and a_g."""
    p = building(n, mu=0.0, d=100.0, fidelity=fidelity, zeta_s=zeta)
    rng = np.random.default_rng(n)
    x0, v0 = rng.normal(0, 0.01, n), rng.normal(0, 0.1, n)
    core = Damper(p, floors0=(list(x0), list(v0)))
    F, ag = 2.0e5, 0.8
    b = ShearBuilding(MASSES[:n], STIFF[:n], zeta)
    Mi = np.diag(1.0 / np.array(MASSES[:n]))
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ np.array(b.K), -Mi @ np.array(b.C)]])
    load = np.zeros(2 * n)
    load[n:] = -ag
    load[n + n - 1] += F / MASSES[n - 1]  # the force acts on the damper floor, the top one
    z0 = np.concatenate([x0, v0])
    for t in (0.05, 0.7, 2.5):
        core.advance(t, F, ag)
        E = scipy.linalg.expm(A * t)
        want = E @ z0 + np.linalg.solve(A, (E - np.eye(2 * n)) @ load)
        xs, vs = core.floors()
        assert np.abs(np.array(xs + vs) - want).max() <= 1e-11 * np.abs(want).max()


def test_one_storey_reproduces_the_coupled_level():
    """The coupled level's primary (M, L2, zeta_s) is a 1-storey building with floor mass M, storey
    stiffness M (1 + mu) g / L2, FR / sqrt(1 + mu) and zeta_s / sqrt(1 + mu): same state to rounding,
    through hundreds of impacts and sticking."""
    g, M, mu, L2, FR, d, e, zs, zp = 9.81, 2.0, 0.1, 1.3, 1.0, 0.01, 0.4, 0.02, 0.05
    coupled = Damper(Params(g=g, M=M, mu=mu, L2=L2, FR=FR, d=d, e=e, fidelity=2, zeta_s=zs, zeta_p=zp),
                     theta_dot0=0.5)
    s = math.sqrt(1.0 + mu)
    pb = Params(g=g, mu=mu, FR=FR / s, d=d, e=e, fidelity=2, zeta_s=zs / s, zeta_p=zp, storeys=1, floor_m=[M],
                storey_k=[M * (1.0 + mu) * g / L2])
    one = Damper(pb, floors0=([0.0], [0.5 * L2]))
    modes = set()
    for k in range(1, 2001):
        t = 0.01 * k
        force, ground = 0.3 * math.sin(2.0 * t), 0.2 * math.cos(3.1 * t)
        coupled.advance(t, force, ground)
        one.advance(t, force, ground)
        modes.add(one.mode)
        scale = 1.0 + abs(coupled.v)
        for a, b in ((coupled.x, one.x), (coupled.v, one.v), (coupled.y, one.y), (coupled.u, one.u)):
            assert abs(a - b) <= 1e-11 * scale
        assert one.impacts == coupled.impacts
    assert coupled.impacts > 200 and modes == {0, 1}
    assert one.energy == pytest.approx(coupled.energy, rel=1e-12)
    assert one.dissipated == pytest.approx(coupled.dissipated, rel=1e-12)
    assert one.viscous == pytest.approx(coupled.viscous, rel=1e-10)


def _reference_case(n, **kw):
    values = dict(mu=0.05, FR=1.0, d=0.004, e=0.5, zeta_s=0.02, zeta_p=0.01)
    values.update(kw)
    return values


@pytest.mark.parametrize("damper_floor", [0, 2])
def test_many_impacts_against_solve_ivp(damper_floor):
    """3 storeys, harmonic ground motion near the first mode: floors and particle follow the
    independent event-driven integration through every impact."""
    v = _reference_case(3)
    p = building(3, fidelity=1, damper_floor=damper_floor, **v)
    w = p.building.w_1

    def ag(t):
        return 2.0 * math.sin(w * t)

    times = np.arange(1, 301) * 0.01
    core = Damper(p)
    impacts = []
    core.on_impact = lambda t, side, before, after, loss: impacts.append((t, before))
    # the core holds a_g over each step: the reference is fed the same held signal
    held = simulate(MASSES[:3], STIFF[:3], v["zeta_s"], v["mu"], v["FR"], v["d"], v["e"], v["zeta_p"], times[-1],
                    damper_floor=damper_floor, a_g=lambda t: ag(0.01 * math.floor(t / 0.01 + 1e-9)),
                    sample_times=times)
    xs = []
    for t in times:
        core.advance(t, 0.0, ag(t - 0.01))
        xs.append(core.floors()[0] + [core.y - core.x])
    xs = np.array(xs)
    assert np.abs(xs[:, :3] - held["x"]).max() <= 1e-8 * np.abs(held["x"]).max()
    assert np.abs(xs[:, 3] - held["r"]).max() <= 1e-7 * v["d"]
    # impacts above a relative speed of 1 mm/s (chatter tails below it depend on each method's
    # stick threshold): the same ones, at the same instants
    ours = [t for t, w in impacts if abs(w) > 1e-3]
    theirs = [t for t, _, w, _, _ in held["impacts"] if abs(w) > 1e-3]
    assert len(ours) == len(theirs) > 50
    assert np.abs(np.array(ours) - np.array(theirs)).max() <= 1e-9
    assert core.viscous == pytest.approx(held["viscous"], rel=1e-8)


def test_sticking_against_solve_ivp():
    """A large held ground acceleration presses the particle on a stop of the top floor: it rides it
    (contact = +-1) and the floors follow the reference's riding phase."""
    v = _reference_case(3, e=0.0, d=0.002)
    p = building(3, fidelity=1, **v)
    times = np.arange(1, 101) * 0.01
    ref = simulate(MASSES[:3], STIFF[:3], v["zeta_s"], v["mu"], v["FR"], v["d"], v["e"], v["zeta_p"], times[-1],
                   a_g=3.0, sample_times=times)
    core = Damper(p)
    contact = []
    xs = []
    for t in times:
        core.advance(t, 0.0, 3.0)
        contact.append(core.contact)
        xs.append(core.floors()[0])
    assert ref["stick"] and any(contact)
    assert np.abs(np.array(xs) - ref["x"]).max() <= 1e-6 * np.abs(ref["x"]).max()
    assert core.dissipated == pytest.approx(ref["impact_loss"], rel=1e-6)


def test_energy_balance_closes_with_the_building():
    """E(0) + work of F and a_g - E(t) = impacts + dashpots, where the dashpots' share comes from the
    reference's integral of v^T C v + c_p r'^2 (not from the balance itself)."""
    v = _reference_case(3)
    p = building(3, fidelity=2, **v)
    core = Damper(p)
    for k in range(1, 201):
        core.advance(0.01 * k, 1.0e5, 1.5)
    ref = simulate(MASSES[:3], STIFF[:3], v["zeta_s"], v["mu"], v["FR"], v["d"], v["e"], v["zeta_p"], 2.0,
                   a_g=1.5, F=1.0e5)
    assert core.impacts > 5
    assert core.energy == pytest.approx(ref["energy"], rel=1e-7)
    assert core.work_in == pytest.approx(ref["work"], rel=1e-7)
    assert core.viscous == pytest.approx(ref["viscous"], rel=1e-6)
    gap = core.energy0 + core.work_in - core.energy - core.viscous - core.dissipated
    assert abs(gap) <= 1e-12 * (core.energy + abs(core.work_in))


def test_base_shear_balances_the_floor_forces():
    """Newton for the whole system: base shear = F - sum m_k a_k (absolute) - m a_particle."""
    v = _reference_case(4)
    p = building(4, fidelity=1, damper_floor=3, **v)
    core = Damper(p)
    checked = set()
    for k in range(1, 301):
        F, ag = 5.0e4 * math.sin(0.05 * k), 2.0 * math.sin(0.07 * k)
        core.advance(0.01 * k, F, ag)
        xs, acc, drifts, shear = core.building_outputs(F, ag)
        r, rdot = core.y - core.x, core.u - core.v
        particle = -p.w1 ** 2 * r - 2.0 * p.zeta_p * p.w1 * rdot + core.contact_force(F, ag) / p.m
        expected = F - sum(m * a for m, a in zip(MASSES, acc)) - p.m * particle
        assert shear == pytest.approx(expected, rel=1e-9, abs=1e-9 * abs(F))
        assert drifts == pytest.approx([xs[0]] + [xs[i] - xs[i - 1] for i in range(1, 4)], abs=1e-18)
        checked.add(core.contact)
    assert len(checked) >= 2  # free and riding both seen


@pytest.mark.parametrize("values,name,rule", [
    ({"storeys": 11}, "storeys", "an integer in 0..10"),
    ({"storeys": 3, "damper_floor": 4}, "damper_floor", "an integer in 0..storeys = 3"),
    ({"storeys": 3, "fidelity": 3}, "fidelity", "the nonlinear level (3) is for the pendulum primary only"),
    ({"storeys": 2, "contact_form": 1}, "contact_form", "needs the displacement form 0"),
    ({"storeys": 2, "floor_m": [1e5, 0.0]}, "floor[2].m", "(> 0)"),
    ({"storeys": 2, "storey_k": [-1.0]}, "storey[1].k", "(> 0)"),
])
def test_bad_building_refused_by_name(values, name, rule):
    """Each refusal names the parameter and states its own rule."""
    with pytest.raises(ParameterError) as err:
        Params(**values)
    assert err.value.name == name
    assert rule in err.value.allowed


def test_state_round_trip_keeps_the_other_floors():
    p = building(5, fidelity=1, **_reference_case(5))
    core = Damper(p)
    core.advance(0.5, 1e5, 1.0)
    saved = core.get_state()
    core.advance(1.0, 1e5, 1.0)
    after = core.floors()
    twin = Damper(p)
    twin.set_state(saved)
    twin.advance(1.0, 1e5, 1.0)
    assert twin.floors() == after
    saved["others"] = saved["others"][:-1]
    with pytest.raises(ParameterError):
        twin.set_state(saved)


# ---- the FMU ----------------------------------------------------------------------------------

FMU_BUILDING = {"storeys": 4, "damper_floor": 3, "fidelity": 1, "zeta_s": 0.02, "zeta_p": 0.01, "mu": 0.05,
                "FR": 0.95, "d": 0.004, "e": 0.5, **{f"floor[{k}].m": MASSES[k - 1] for k in range(1, 11)},
                **{f"storey[{k}].k": STIFF[k - 1] for k in range(1, 11)}}


def test_fmu_building_outputs_follow_the_core(fmu_dir):
    """DampedShearBuilding4.fmu, bit for bit with the core at every step: angles, every floor's
    outputs, the base shear, the drift ratios and the running maxima; exactly four floors'
    variables, none of the pendulum primary's."""
    import fmpy

    from pidamper import CoreStepper, FmuStepper, find_fmu, forcing

    path = find_fmu(storeys=4)
    assert path == fmu_dir / "DampedShearBuilding4.fmu"
    names = {v.name for v in fmpy.read_model_description(str(path)).modelVariables}
    assert {"floor[4].m", "storey[4].h", "storey[4].drift_ratio_max"} <= names
    assert not names & {"floor[5].m", "floor[5].x", "storeys", "M", "L2", "theta_0", "contact_form", "d_angle"}
    signal = forcing.kanai_tajimi(3.0, pga=3.0, seed=2, dt=0.01)
    names = [f"floor[{k}].{f}" for k in range(1, 5) for f in ("x", "a", "v_abs_max", "a_abs_max")] + \
        [f"storey[{k}].{f}" for k in range(1, 5) for f in ("drift", "drift_ratio", "drift_ratio_max")] + ["base_shear"]
    with FmuStepper(path, FMU_BUILDING, forcing=signal) as fmu, \
            CoreStepper(FMU_BUILDING, forcing=signal) as core:
        for k in range(1, 301):
            fmu.advance(0.01 * k)
            core.advance(0.01 * k)
            assert fmu.read() == core.read()
            assert [fmu.get(n) for n in names] == [core.get(n) for n in names]
        assert fmu.get("impacts") == core.get("impacts") > 10
        assert fmu.get("x") == core.get("floor[3].x")  # x is the damper floor's displacement
        assert fmu.get("storey[2].drift_ratio_max") >= abs(fmu.get("storey[2].drift_ratio")) > 0.0


@pytest.mark.parametrize("values,expected", [
    ({"storeys": 12}, "storeys = 12"),
    ({"storeys": 3, "damper_floor": 5}, "damper_floor = 5"),
    ({"storeys": 3, "fidelity": 3}, "fidelity = 3"),
    ({"storeys": 2, "floor[2].m": 0.0}, "floor[2].m = 0.0"),
    ({"storeys": 2, "storey[1].k": float("inf")}, "storey[1].k = inf"),
    ({"storeys": 3, "storey[2].h": 0.0}, "storey[2].h = 0.0"),
    ({"storeys": 1, "storey[1].h": -3.0}, "storey[1].h = -3.0"),
])
def test_fmu_refuses_a_bad_building_by_name(fmu_dir, values, expected):
    from pidamper import find_fmu
    from pidamper.running import isolated

    if values["storeys"] > 10:  # no such FMU: find_fmu names the range
        with pytest.raises(ValueError, match=r"storeys = 12 is not allowed: an integer in 1\.\.10"):
            find_fmu(storeys=values["storeys"])
        return
    path = find_fmu(storeys=values["storeys"])
    values = {k: v for k, v in values.items() if k != "storeys"}
    text = isolated.call("pidamper.benchmarks.fatal_checks:bad_values", str(path), values)
    assert text is not None and expected in text and "not allowed" in text and "status 3 (error)" in text
