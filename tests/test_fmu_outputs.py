"""The adapters' outputs computed once per state (issue 36, item 4), in process (the model classes
driven as pythonfmu and the native layer drive them): reads through Python are served from one
flat tuple computed at the first read after a change, and the native layer's buffer is not packed
again after a step that changed nothing the outputs read (a building at rest, the same inputs).
The oracle: the outputs computed afresh from the model's state after every call."""
import struct

import pytest
from pythonfmu import Integer, Real

from pidamper_fmu.building_slave import ShearBuilding3
from pidamper_fmu.damped_building_slave import DampedShearBuilding3
from pidamper_fmu.slave import PendulumImpactDamper

H = 0.01


def _model(cls, native):
    model = cls(instance_name="t", resources="/tmp")
    if native:
        assert model._native_attach(len(model.vars) - 1)
    model.setup_experiment(0.0)
    model.exit_initialization_mode()
    return model


def _computed(model):
    """value references and kinds of the computed variables (outputs and locals but the record)."""
    names = {row[0] for row in model.COMPUTED}
    return [(vr, type(var)) for vr, var in model.vars.items() if var.name in names]


def _fresh(model):
    return model._outputs() if hasattr(model, "_outputs") else model._computed(model._core)


def _buffer(model, vrs):
    data = model._buffer.cast("d")
    return tuple(data[vr] for vr, _ in vrs)


def _counting(monkeypatch, cls, name):
    calls = []
    original = getattr(cls, name)

    def counted(self, *args):
        calls.append(1)
        return original(self, *args)

    monkeypatch.setattr(cls, name, counted)
    return calls


def _read(model, vrs, one_call):
    reals = [vr for vr, kind in vrs if kind is Real]
    ints = [vr for vr, kind in vrs if kind is Integer]
    if one_call:
        return model.get_real(reals), model.get_integer(ints)
    return [model.get_real([vr])[0] for vr in reals], [model.get_integer([vr])[0] for vr in ints]


def _split(values, vrs):
    return ([float(v) for v, (_, kind) in zip(values, vrs) if kind is Real],
            [int(v) for v, (_, kind) in zip(values, vrs) if kind is Integer])


@pytest.mark.parametrize("cls, compute", [(DampedShearBuilding3, "_live_outputs"), (PendulumImpactDamper, "_live_outputs"),
                                          (ShearBuilding3, "_computed")])
@pytest.mark.parametrize("one_call", [True, False])
def test_reads_through_python_compute_the_outputs_once_per_state(monkeypatch, cls, compute, one_call):
    model = _model(cls, native=False)
    vrs = _computed(model)
    force = "F" if cls is not ShearBuilding3 else "F[3]"
    vr_force = next(vr for vr, var in model.vars.items() if var.name == force)
    calls = _counting(monkeypatch, cls, compute)
    for k in range(6):
        if k == 3:
            model.set_real([vr_force], [2e4])  # a feedthrough input: the outputs change without a step
            assert _read(model, vrs, one_call) == _split(_fresh(model), vrs)
        model.do_step(k * H, H)
        before = len(calls)
        assert _read(model, vrs, one_call) == _split(_fresh(model), vrs)
        assert _read(model, vrs, one_call) == _split(_fresh(model), vrs)
        assert len(calls) - before == 1 + 2  # one for both reads, one per _fresh
    state = model._get_fmu_state()
    model.do_step(6 * H, H)
    moved = _read(model, vrs, True)
    model._set_fmu_state(state)
    assert _read(model, vrs, True) == _split(_fresh(model), vrs) != moved


@pytest.mark.parametrize("cls, forces", [(DampedShearBuilding3, ("F", "a_g")), (ShearBuilding3, ("F[3]", "a_g"))])
def test_the_buffer_is_not_packed_again_while_a_building_rests(monkeypatch, cls, forces):
    model = _model(cls, native=True)
    vrs = _computed(model)
    vr = {var.name: vr for vr, var in model.vars.items()}
    pushes = _counting(monkeypatch, cls, "_push")
    # zero input: rest; -0.0; a read through Python (the layer writes it into the buffer); a force
    # read before the step then taken back; the force; rest again (moving: packed every step)
    plan = [{}, {}, {}, {forces[0]: -0.0}, {forces[0]: 0.0}, "pull", {}, {forces[0]: 5e4, "pull": True},
            {forces[0]: 0.0}, {}, {forces[0]: 3e4}, {forces[0]: 0.0}, {}]
    packed = []
    for k, step in enumerate(plan):
        if step == "pull" or (isinstance(step, dict) and step.pop("pull", False)):
            if isinstance(step, dict):
                model.set_real([vr[name] for name in step], list(step.values()))
            reals, ints = _read(model, vrs, True)
            data = model._buffer.cast("d")  # as fmi2_entry.c's pull does
            for (v, kind), value in zip([p for p in vrs if p[1] is Real], reals):
                data[v] = value
            step = {forces[0]: 0.0} if step != "pull" else {}
        if step:
            model.set_real([vr[name] for name in step], list(step.values()))
        before = len(pushes)
        assert model._native_step(k * H, H) != 2  # done (1: with the log line of exit_initialization_mode)
        packed.append(len(pushes) - before)
        assert struct.pack(f"{len(vrs)}d", *_buffer(model, vrs)) == struct.pack(
            f"{len(vrs)}d", *(float(v) for v in _fresh(model))), k
    assert packed == [1, 0, 0, 1, 1, 1, 0, 1, 0, 0, 1, 1, 1]


@pytest.mark.parametrize("cls, force", [(DampedShearBuilding3, "F"), (ShearBuilding3, "F[3]")])
def test_an_input_set_between_steps_at_rest_repacks_the_buffer(monkeypatch, cls, force):
    """A building at rest: an input set to another value (even one taken back before the step) or to
    the same bits again: the buffer holds the outputs afresh after every step."""
    model = _model(cls, native=True)
    vrs = _computed(model)
    vr = {var.name: vr for vr, var in model.vars.items()}[force]
    pushes = _counting(monkeypatch, cls, "_push")
    plan = [(), (), ((vr, 7e3), (vr, 0.0)), (), ((vr, 0.0),), ((vr, -0.0),), ((vr, -0.0),), ((vr, 0.0),), ()]
    packed = []
    for k, sets in enumerate(plan):
        for ref, value in sets:
            model.set_real([ref], [value])
        before = len(pushes)
        assert model._native_step(k * H, H) != 2
        packed.append(len(pushes) - before)
        assert struct.pack(f"{len(vrs)}d", *_buffer(model, vrs)) == struct.pack(
            f"{len(vrs)}d", *(float(v) for v in _fresh(model))), k
    assert packed == [1, 0, 1, 0, 0, 1, 0, 1, 0]
