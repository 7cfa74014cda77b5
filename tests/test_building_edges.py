"""Building FMUs at the edges of their storeys (issue 35): both families collapse by one path; a
storey that never reaches its yield force moves bit for bit as an elastic one, whatever Fy is;
yield drifts the arithmetic cannot hold are refused by name; a zero-strength storey keeps its yield
surface and its energy balance; a building driven far beyond any real one warns once, and no
building FMU speaks of a primary pendulum."""
import re

import pytest

from pidamper import find_fmu, forcing
from pidamper.running.instance import FmuInstance
from pidamper_physics import Damper, Params
from pidamper_physics.building import ShearBuilding
from pidamper_physics.shear_motion import ShearMotion
from pidamper_physics.storeys import check_storeys
from pidamper_physics.yielding import YieldingMotion

H = 0.01
M3, K3, H3 = [1e5] * 3, [8e7] * 3, [3.0] * 3
# the damped family as a bare building: a particle without mass, far from its stops
BARE_DAMPED = {"fidelity": 1, "mu": 0.0, "d": 1000.0, "angle_limit": 0.0}


def _family(damper):
    return find_fmu(storeys=3, damper=damper)


def _drive(fmu, signal, steps, names):
    rows = []
    for k in range(steps):
        fmu.set("a_g", float(signal.value(k * H)))
        fmu.do_step(k * H, H)
        rows.append([fmu.get(n) for n in names])
    return rows


# ---- one collapse path --------------------------------------------------------------------------

WEAK = {"zeta_s": 0.02, "p_delta": 1, "storey[1].Fy": 4e5, "storey[2].Fy": 5e5, "storey[3].Fy": 3e5,
        "storey[1].b": 0.0}
HELD = ["floor[1].x", "floor[3].x", "floor[1].a", "storey[1].drift_ratio", "storey[1].drift_ratio_max",
        "storey[1].force", "energy_hysteretic", "base_shear", "collapsed"]


@pytest.mark.parametrize("damper", [False, True], ids=["ShearBuilding3", "DampedShearBuilding3"])
def test_both_families_collapse_warn_hold_and_keep_the_latch(fmu_dir, damper):
    """Driven past collapse: every fmi2DoStep answers fmi2OK, one warning names the storey and the
    time, every output holds from the collapse on, and a state saved before it replays it."""
    signal = forcing.kanai_tajimi(6.0, pga=12.0, seed=3, dt=0.01)
    said = []
    values = {**WEAK, **(BARE_DAMPED if damper else {})}
    with FmuInstance(_family(damper), values, logger=lambda status, text: said.append(text)) as fmu:
        fmu.do_step(0.0, H)
        saved = fmu.fmu.getFMUstate()
        rows = [[fmu.get(n) for n in HELD]] + _drive_from(fmu, signal, 1, 600)
        first = next(k for k, row in enumerate(rows) if row[-1] == 1)
        assert all(row == rows[first] for row in rows[first:])  # held, the latch included
        assert rows[first][HELD.index("storey[1].drift_ratio_max")] == pytest.approx(0.1, rel=1e-12)
        fmu.fmu.setFMUstate(saved)
        fmu.t = H
        assert _drive_from(fmu, signal, 1, 600) == rows[1:]
        fmu.fmu.freeFMUstate(saved)
    collapses = [s for s in said if "collapsed" in s]
    assert len(collapses) == 2  # once per run
    assert "storey 1 reached the drift ratio collapse_drift = 0.1" in collapses[0]
    assert re.search(r"collapsed at t = [0-9.]+ s", collapses[0])


def _drive_from(fmu, signal, start, steps):
    rows = []
    for k in range(start, steps):
        fmu.set("a_g", float(signal.value(k * H)))
        fmu.do_step(k * H, H)
        rows.append([fmu.get(n) for n in HELD])
    return rows


# ---- a storey that never yields is an elastic one -----------------------------------------------

BIG = [1e8, 1e12, 1e15, 1e18, 1e19, 1e22, 1e150]


def _bare(fy, b=0.02, p_delta=1):
    law = check_storeys(K3, fy, [b] * 3, H3, M3, p_delta, 9.81, 0.1)
    building = ShearBuilding(M3, K3, 0.02, H3, law.geometric)
    return YieldingMotion(building, law, 0.1) if law.any_yield else ShearMotion(building)


def _bare_run(core, signal, steps=600):
    rows = []
    for k in range(steps):
        core.advance((k + 1) * H, [0.0] * 3, float(signal.value(k * H)))
        x, v = core.floors()
        rows.append(x + v + core.absolute_accelerations([0.0] * 3) + core.peaks.drift + core.peaks.velocity
                    + core.peaks.acceleration)
    return rows


@pytest.mark.parametrize("fy", BIG)
def test_a_bare_building_whose_storeys_never_yield_is_the_elastic_one(fy):
    """Every storey given a yield force it never reaches: bit for bit the elastic building
    (ShearMotion) in displacement, velocity, acceleration and the running maxima."""
    signal = forcing.kanai_tajimi(6.0, pga=3.0, seed=3, dt=0.01)
    elastic = _bare_run(_bare([0.0] * 3), signal)
    strong = _bare([fy] * 3)
    assert isinstance(strong, YieldingMotion)
    assert _bare_run(strong, signal) == elastic
    assert strong.storeys.events == 0


@pytest.mark.parametrize("fy", BIG)
def test_a_storey_that_never_yields_beside_yielding_ones_is_an_elastic_one(fy):
    """Storeys 1 and 2 yield; storey 3 with any yield force it never reaches moves bit for bit as
    with none (before, its yield surface set the event search's rounding level for all: 1e18 moved
    the roof by 1e-4, 1e19 by 15 %, 1e20 collapsed the building)."""
    signal = forcing.kanai_tajimi(6.0, pga=3.0, seed=3, dt=0.01)
    elastic = _bare([6e5, 5e5, 0.0])
    reference = _bare_run(elastic, signal)
    assert elastic.storeys.events > 10  # the others do yield
    strong = _bare([6e5, 5e5, fy])
    assert _bare_run(strong, signal) == reference
    assert strong.storeys.collapsed == 0


@pytest.mark.parametrize("fy", [1e12, 1e19, 1e22])
def test_the_damped_family_is_its_elastic_self_too(fy):
    """DampedShearBuilding's core with the particle at work: storey 3 strong beyond reach moves
    bit for bit as an elastic storey, the others yielding."""
    signal = forcing.kanai_tajimi(4.0, pga=3.0, seed=3, dt=0.01)

    def run(fy3):
        p = Params(storeys=3, fidelity=1, zeta_s=0.02, mu=0.05, FR=0.95, d=0.02, e=0.6, p_delta=1,
                   storey_Fy=[6e5, 5e5, fy3])
        core = Damper(p)
        rows = []
        for k in range(400):
            core.advance((k + 1) * H, 0.0, float(signal.value(k * H)))
            rows.append(core.building_outputs(0.0, float(signal.value(k * H))) + (core.y, core.u, core.impacts))
        return rows, core

    reference, elastic = run(0.0)
    assert elastic.model.storeys.events > 10 and elastic.impacts >= 5
    assert run(fy)[0] == reference


@pytest.mark.parametrize("damper", [False, True], ids=["ShearBuilding3", "DampedShearBuilding3"])
def test_a_strong_storey_through_the_fmu_is_the_elastic_one(fmu_dir, damper):
    signal = forcing.kanai_tajimi(3.0, pga=3.0, seed=3, dt=0.01)
    names = ["floor[1].x", "floor[3].x", "floor[2].a", "storey[1].drift_ratio_max", "floor[3].v_abs_max",
             "collapsed"]
    base = {"zeta_s": 0.02, **(BARE_DAMPED if damper else {})}
    with FmuInstance(_family(damper), base) as fmu:
        elastic = _drive(fmu, signal, 300, names)
    with FmuInstance(_family(damper), {**base, **{f"storey[{k}].Fy": 1e19 for k in (1, 2, 3)}}) as fmu:
        assert _drive(fmu, signal, 300, names) == elastic


@pytest.mark.parametrize("damper", [False, True])
@pytest.mark.parametrize("fy, k", [(1e160, 8e7), (1e-300, 8e7), (1e300, 1.0)])
def test_a_yield_drift_beyond_the_arithmetic_is_refused_by_name(fmu_dir, damper, fy, k):
    from pidamper.running import isolated

    values = {"storey[2].Fy": fy, "storey[2].k": k, **(BARE_DAMPED if damper else {})}
    text = isolated.call("pidamper.benchmarks.fatal_checks:bad_values", str(_family(damper)), values)
    assert text is not None and f"storey[2].Fy = {fy!r} is not allowed" in text and "yield drift" in text
    assert "d = " not in text


# ---- a zero-strength storey -------------------------------------------------------------------

@pytest.mark.parametrize("fy", [1e-30, 1e-120])
def test_a_zero_strength_storey_keeps_its_surface_and_its_balance(fy):
    """Fy far below any force the storey carries: its elastic-perfectly-plastic spring never
    carries more than (1 - b) Fy (it yields at once each way), and the energy balance closes to
    rounding.  Before, the two yield surfaces lay within the event search's rounding level, only
    one was watched, and the storey overshot the other by micrometres (hundreds of newtons, 3e-9
    of the work lost from the balance)."""
    signal = forcing.kanai_tajimi(6.0, pga=4.0, seed=1, dt=0.005, omega_g=12.0, zeta_g=0.6)
    core = _bare([fy, 0.0, 0.0], p_delta=0)
    law = core.storeys.law
    worst = 0.0
    for k in range(1200):
        core.advance((k + 1) * 0.005, [0.0] * 3, float(signal.value(k * 0.005)))
        d = core.drifts()[0]
        worst = max(worst, abs(core.storey_forces()[0] - law.b[0] * law.k[0] * d))
    assert core.storeys.events > 6
    assert worst <= (1.0 - law.b[0]) * fy + 1e-9  # the EPP part: within rounding of the drift (1e-17 m k)
    balance = core.energy() + core.viscous + core.hysteretic - core.energy0 - core.work_in
    assert abs(balance) < 1e-13 * core.work_in


# ---- far outside the model's meaning --------------------------------------------------------------

@pytest.mark.parametrize("damper", [False, True], ids=["ShearBuilding3", "DampedShearBuilding3"])
def test_a_building_far_beyond_any_real_one_warns_once(fmu_dir, damper):
    """Drift ratios of 1-2 (floors metres apart): one warning through the FMI logger naming the
    storey, its drift ratio and drift_limit, none about a pendulum; drift_limit = 0 silences it,
    and the warning's latch is part of the FMU state."""
    signal = forcing.kanai_tajimi(4.0, pga=600.0, seed=3, dt=0.01)
    said = []
    values = {"zeta_s": 0.02, **(BARE_DAMPED if damper else {})}
    with FmuInstance(_family(damper), values, logger=lambda status, text: said.append((status, text))) as fmu:
        before = fmu.fmu.getFMUstate()
        rows = _drive(fmu, signal, 400, ["storey[1].drift_ratio_max"])
        assert rows[-1][0] > 1.0
        after = fmu.fmu.getFMUstate()
        fmu.fmu.setFMUstate(before)  # not yet warned: it warns again
        _drive(fmu, signal, 400, [])
        fmu.fmu.setFMUstate(after)  # warned: it does not
        fmu.do_step(4.0, H)
        for saved in (before, after):
            fmu.fmu.freeFMUstate(saved)
    drift = [(status, text) for status, text in said if "drift_limit" in text]
    assert [status for status, _ in drift] == [1, 1]  # fmi2Warning, once per run
    warnings = [text for _, text in drift]
    assert re.search(r"storey 1's drift ratio reached 0\.2\d* .* beyond drift_limit = 0\.2", warnings[0])
    assert not any("primary" in text or "theta" in text for _, text in said)
    with FmuInstance(_family(damper), {**values, "drift_limit": 0.0},
                     logger=lambda status, text: said.append((status, text))) as fmu:
        _drive(fmu, signal, 400, [])
    assert len([text for status, text in said if "drift_limit" in text]) == 2


def test_the_particle_alone_is_watched_for_large_swings_on_a_building(fmu_dir):
    """DampedShearBuilding's small-angle warning names the particle (a real pendulum), never the
    building's theta (the damper floor's x / L2, no pendulum)."""
    signal = forcing.kanai_tajimi(6.0, pga=3.0, seed=3, dt=0.01)
    said = []
    with FmuInstance(_family(True), {"fidelity": 1, "zeta_s": 0.02, "mu": 0.05, "d": 0.1},
                     logger=lambda status, text: said.append(text)) as fmu:
        rows = _drive(fmu, signal, 600, ["theta", "alpha"])
    assert max(abs(r[0]) for r in rows) > 0.4 and max(abs(r[1]) for r in rows) > 0.4  # both past the limit
    swings = [s for s in said if "small-angle" in s or "largest swings" in s]
    assert swings and all("particle" in s and "primary" not in s for s in swings)
