"""Every output of a building in one call (issue 36, item 4: outputs packed once per step): the
fused lists the FMUs pack, ShearMotion.observables, YieldingMotion.observables and
Damper.building_observables, against the quantities' own methods, which compute each output on
its own path (floors, accelerations, drifts, energies and shears taken afresh), bit for bit."""
import math
import random

import pytest

from pidamper_physics import Damper, Params
from pidamper_physics.shear_motion import ShearMotion
from pidamper_physics.yielding import building_motion

H = 0.01
MASSES, STIFFNESSES, HEIGHTS = [1e5, 9e4, 8e4], [8e7, 7e7, 6e7], [3.5, 3.0, 3.0]


def _loads(rng, k):
    forces = [rng.uniform(-2e5, 2e5) for _ in range(3)]
    impulses = [(k * H + rng.uniform(0.0, H), rng.randrange(3), rng.uniform(-1e3, 1e3))] if k % 4 == 1 else []
    return forces, rng.uniform(-3.0, 3.0), impulses


def _one_by_one(core, forces):
    """The observables from the quantities' own methods, in the FMU's order."""
    x, v = core.floors()
    b, pk = core.b, core.peaks
    if isinstance(core, ShearMotion):
        energy = core.energy()
        springs = [k * (x[i] - (x[i - 1] if i else 0.0)) for i, k in enumerate(b.stiffnesses)]
        storeys = springs + [0.0] * core.n + [0.0, 0]
        totals = [energy, core.energy0 + core.work_in - energy, core.work_in, b.base_shear(x, v)]
    else:
        storeys = core.storey_forces() + core.plastic_drifts() + [core.hysteretic, core.collapsed]
        totals = [core.energy(), core.viscous, core.work_in, core.base_shear()]
    return (x + v + core.absolute_accelerations(forces, x, v) + b.drift_ratios(x) + pk.drift + pk.velocity
            + pk.acceleration + storeys + totals)


@pytest.mark.parametrize("yield_force", [0.0, 6e5, 3e5])
def test_the_fused_observables_are_the_quantities_own_values(yield_force):
    core = building_motion(MASSES, STIFFNESSES, HEIGHTS, 0.03, [yield_force] * 3, [0.05] * 3, p_delta=1)
    assert isinstance(core, ShearMotion) == (yield_force == 0.0)
    rng = random.Random(7)
    for k in range(60):
        forces, ground, impulses = _loads(rng, k)
        core.advance((k + 1) * H, forces, ground, impulses)
        fused = core.observables(forces)
        assert repr(fused) == repr(_one_by_one(core, forces))  # bit for bit, signed zeros included
    assert len(fused) == 9 * 3 + 6 and max(core.peaks.drift) > 0.0
    if yield_force == 3e5:
        assert core.hysteretic > 0.0  # the storeys yielded: the yielding branch was taken


def test_an_unyielding_building_has_the_elastic_building_observables():
    """A yielding building whose storeys never reach their yield forces moves as the elastic one:
    its observables, on the yielding code path, equal the elastic ones in the same order."""
    elastic = building_motion(MASSES, STIFFNESSES, HEIGHTS, 0.03, [0.0] * 3, [0.05] * 3)
    strong = building_motion(MASSES, STIFFNESSES, HEIGHTS, 0.03, [1e9] * 3, [0.05] * 3)
    assert not isinstance(strong, ShearMotion)
    rng = random.Random(3)
    for k in range(40):
        forces, ground, impulses = _loads(rng, k)
        elastic.advance((k + 1) * H, forces, ground, impulses)
        strong.advance((k + 1) * H, forces, ground, impulses)
        a, b = elastic.observables(forces), strong.observables(forces)
        scale = [max(abs(u), abs(w), 1e-30) for u, w in zip(a, b)]
        assert all(abs(u - w) <= 1e-9 * s for u, w, s in zip(a, b, scale)), k


@pytest.mark.parametrize("fy", [0.0, 2e5])
def test_the_damper_building_observables_are_the_building_outputs(fy):
    params = dict(storeys=3, fidelity=1, zeta_s=0.02, mu=0.05, FR=1.0, d=0.01)
    if fy:
        params.update(storey_Fy=[fy] * 3, storey_b=[0.05] * 3)
    core = Damper(Params(**params), 0.0, 0.0, 0.0, 0.0)
    for k in range(150):
        force, ground = 1e4 * math.sin(0.3 * k), 3.0 * math.sin(6.0 * k * H)
        core.advance((k + 1) * H, force, ground)
        xs, acc, drifts, shear = core.building_outputs(force, ground)
        ratios, drift_max, v_max, a_max = core.model.peak_outputs(drifts)
        storeys = core.model.storeys
        if storeys is None:
            springs = [s * d for s, d in zip(core.p.building.stiffnesses, drifts)] + [0.0] * 3 + [0.0, 0]
        else:
            springs = storeys.forces(drifts) + storeys.zero_force_drifts(drifts) + [storeys.hysteretic,
                                                                                    storeys.collapsed]
        expected = xs + acc + drifts + [shear] + ratios + drift_max + v_max + a_max + springs
        assert repr(core.building_observables(force, ground)) == repr(expected)
    assert core.impacts > 0 and (storeys is None or storeys.hysteretic > 0.0)


@pytest.mark.parametrize("yield_force", [0.0, 3e5])
def test_the_building_fmu_names_each_observable(yield_force):
    """ShearBuilding3's outputs by name against the core's quantities (the FMU packs observables()
    in the order of its variables: a shifted or swapped entry fails here)."""
    from pidamper_fmu.building_slave import ShearBuilding3

    model = ShearBuilding3(instance_name="t", resources="/tmp")
    by_name = {var.name: vr for vr, var in model.vars.items()}
    model.set_real([by_name[f"storey[{k}].Fy"] for k in (1, 2, 3)], [yield_force] * 3)
    model.setup_experiment(0.0)
    model.exit_initialization_mode()
    rng = random.Random(5)
    for k in range(30):
        forces, ground, _ = _loads(rng, k)
        model.set_real([by_name[f"F[{i}]"] for i in (1, 2, 3)] + [by_name["a_g"]], forces + [ground])
        model.do_step(k * H, H)
    core = model._core
    value = {name: model.get_real([vr])[0] if name != "collapsed" else model.get_integer([vr])[0]
             for name, vr in by_name.items() if name in {row[0] for row in model.COMPUTED}}
    x, v = core.floors()
    a = core.absolute_accelerations(forces, x, v)
    pk = core.peaks
    for i in range(3):
        k = i + 1
        assert value[f"floor[{k}].x"] == x[i] and value[f"floor[{k}].v"] == v[i] and value[f"floor[{k}].a"] == a[i]
        assert value[f"storey[{k}].drift_ratio"] == core.b.drift_ratios(x)[i]
        assert value[f"storey[{k}].drift_ratio_max"] == pk.drift[i]
        assert value[f"floor[{k}].v_abs_max"] == pk.velocity[i] and value[f"floor[{k}].a_abs_max"] == pk.acceleration[i]
    assert value["work_in"] == core.work_in and value["base_shear"] != 0.0
    if yield_force:
        assert [value[f"storey[{k}].force"] for k in (1, 2, 3)] == core.storey_forces()
        assert value["energy_hysteretic"] == core.hysteretic > 0.0 and value["base_shear"] == core.base_shear()
        assert value["energy"] == core.energy() and value["energy_viscous"] == core.viscous
    else:
        assert value["energy"] == core.energy() and value["energy_viscous"] == core.energy0 + core.work_in - value["energy"]
        assert value["base_shear"] == core.b.base_shear(x, v) and value["energy_hysteretic"] == 0.0
    assert value["collapsed"] == 0
