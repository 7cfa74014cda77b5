"""A building at rest under no load skips its pieces (issue 36, item 3): the oracle is the closed
form (at rest it stays at rest: every state value and output zero, the clock on) and the full step
(the same run with the skip turned off), compared bit for bit on the whole state (reprs, so the
sign of a zero counts), before and after the rest."""
import json
import math

import pytest

from pidamper_physics import Damper, Params
from pidamper_physics.shear_motion import ShearMotion, make_building

H = 0.01


class _FullShearMotion(ShearMotion):
    """A ShearMotion that never skips (the compiled class's own methods cannot be patched)."""

    def _resting(self, forces, ground):
        return False


def _full(monkeypatch):
    """Turn the skip off: every step takes its pieces."""
    monkeypatch.setattr(Damper, "_resting", lambda self, loads: False)
    monkeypatch.setitem(globals(), "ShearMotion", _FullShearMotion)


def _damper(fidelity=1):
    p = Params.from_variables({"storeys": 3, "fidelity": fidelity, "zeta_s": 0.02 if fidelity else 0.0,
                               "zeta_p": 0.01 if fidelity else 0.0})
    return Damper(p, 0.0, 0.0, 0.0, 0.0, 0.0)


def _damper_run(inputs, start=None):
    core = _damper()
    if start is not None:
        core.set_state(start)
    rows = []
    for k, (force, ground) in enumerate(inputs):
        core.advance(start["t"] + (k + 1) * H if start else (k + 1) * H, force, ground)
        rows.append((json.dumps(core.get_state()), core.observables(force, ground), core.building_outputs(force, ground),
                     core.still))
    return rows


# zero input, then a force, then zero input again (moving: no rest), with a -0.0 input among them
INPUTS = [(0.0, 0.0)] * 5 + [(-0.0, -0.0)] * 2 + [(1e5, 0.3)] * 3 + [(0.0, 0.0)] * 3


def test_a_building_at_rest_stays_at_rest_and_its_outputs_are_zero():
    core = _damper()
    for k in range(50):
        core.advance((k + 1) * H)
        assert core.still and core.pieces == 1
        assert (core.x, core.v, core.y, core.u, core.energy, core.work_in) == (0.0,) * 6
        assert core.model.others == [0.0] * 4
        xs, acc, drifts, shear = core.building_outputs()
        assert xs + acc + drifts + [shear] == [0.0] * 10
        assert core.model.peaks.get_state() == {"drift": [0.0] * 3, "velocity": [0.0] * 3,
                                                "acceleration": [0.0] * 3, "v_ground": 0.0}
    assert core.t == 50 * H


@pytest.mark.parametrize("fidelity", [0, 1, 2])
def test_the_skip_is_the_full_step_bit_for_bit(monkeypatch, fidelity):
    skipped = []
    core = _damper(fidelity)
    for k, (force, ground) in enumerate(INPUTS):
        core.advance((k + 1) * H, force, ground)
        skipped.append(core.still)
        skipped[-1] = (skipped[-1], json.dumps(core.get_state()), repr(core.building_outputs(force, ground)))
    _full(monkeypatch)
    core = _damper(fidelity)
    for k, (force, ground) in enumerate(INPUTS):
        core.advance((k + 1) * H, force, ground)
        assert not core.still
        assert (json.dumps(core.get_state()), repr(core.building_outputs(force, ground))) == skipped[k][1:], k
    assert [s[0] for s in skipped] == [True] * 7 + [False] * 6  # the rest was skipped, the motion not


def test_a_rest_after_a_ground_motion_raises_the_velocity_peaks_as_the_full_step(monkeypatch):
    """The floors at rest but the ground moving at v_g: the absolute velocity |v_g| may exceed the
    maxima, and the full step raises them to it."""
    start = _damper().get_state()
    start["peaks"] = {"drift": [0.0] * 3, "velocity": [0.1, 0.5, 0.2], "acceleration": [0.0] * 3, "v_ground": -0.3}
    start["t"] = 2.0
    skipped = _damper_run([(0.0, 0.0)] * 3 + [(0.0, 0.2)] * 2, dict(start))
    assert [r[3] for r in skipped] == [False, True, True, False, False]  # the first step raised two maxima
    assert json.loads(skipped[0][0])["peaks"]["velocity"] == [0.3, 0.5, 0.3]
    _full(monkeypatch)
    assert [r[:3] for r in _damper_run([(0.0, 0.0)] * 3 + [(0.0, 0.2)] * 2, dict(start))] == [r[:3] for r in skipped]


def test_a_negative_zero_state_takes_the_full_step_once():
    start = _damper().get_state()
    start["others"] = [0.0, -0.0, 0.0, 0.0]
    rows = _damper_run([(0.0, 0.0)] * 3, start)
    assert [r[3] for r in rows] == [False, True, True]
    assert json.loads(rows[0][0])["others"] == [0.0] * 4


def _bare_run(inputs, q=None, peaks=None):
    motion = ShearMotion(make_building([1e5] * 3, [8e7] * 3, 0.02, [3.0] * 3))
    if q is not None:
        motion.q, motion.qd = list(q), list(q)
    if peaks is not None:
        motion.peaks.set_state(peaks)
    rows = []
    for k, (forces, ground, impulses) in enumerate(inputs):
        motion.advance((k + 1) * H, forces, ground, impulses)
        x, v = motion.floors()
        rows.append((json.dumps(motion.get_state()), repr((x, v, motion.absolute_accelerations(forces, x, v),
                                                           motion.energy())), motion.still))
    return rows


BARE = ([([0.0] * 3, 0.0, ())] * 4 + [([0.0, -0.0, 0.0], -0.0, [(0.035, 1, 0.0)])]
        + [([0.0] * 3, 0.0, [(0.055, 2, 10.0)])] + [([0.0, 0.0, 1e5], 0.0, ())] + [([0.0] * 3, 0.3, ())] * 2
        + [([0.0] * 3, 0.0, ())] * 2)


def test_a_bare_building_at_rest_skips_and_equals_the_full_step(monkeypatch):
    skipped = _bare_run(BARE)
    assert [r[2] for r in skipped] == [True] * 5 + [False] * 6  # an impulse, a force, the ground end the rest
    assert all(json.loads(r[0])["q"] == [0.0] * 3 for r in skipped[:5])
    peaks = {"drift": [0.0] * 3, "velocity": [0.0, 0.4, 0.0], "acceleration": [0.0] * 3, "v_ground": 0.25}
    raised = _bare_run(BARE, peaks=peaks)
    assert [r[2] for r in raised][:2] == [False, True] and json.loads(raised[0][0])["peaks"]["velocity"] == \
        [0.25, 0.4, 0.25]
    signed = _bare_run(BARE[:2], q=[0.0, -0.0, 0.0])
    assert [r[2] for r in signed] == [False, True]
    _full(monkeypatch)
    full = _bare_run(BARE)
    assert not any(r[2] for r in full)  # every step took its pieces
    assert [r[:2] for r in full] == [r[:2] for r in skipped]
    assert [r[:2] for r in _bare_run(BARE, peaks=peaks)] == [r[:2] for r in raised]
    assert [r[:2] for r in _bare_run(BARE[:2], q=[0.0, -0.0, 0.0])] == [r[:2] for r in signed]
    assert math.copysign(1.0, json.loads(signed[0][0])["q"][1]) == 1.0
