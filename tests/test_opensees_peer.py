"""OpenSees as the peer (issue 24): the same yielding 3-storey building with P-Delta in OpenSees
(zeroLength Steel01 storeys, a parallel negative spring for P-Delta, modalDamping, Newmark average
acceleration, Newton), both driven by the identical held ground motion.  OpenSees's error against
our exact solution falls with its step (about first order: its Newton steps do not locate the yield
and unload instants, and the held input's jumps cost Newmark an order) and is small at dt = 1e-5 s:
the proof that both model the same building."""
import numpy as np

from pidamper.oracles import opensees as peer
from pidamper_physics.building import ShearBuilding
from pidamper_physics.storeys import check_storeys
from pidamper_physics.yielding import YieldingMotion

M, K, FY, B, H, ZETA = [1e5] * 3, [8e7] * 3, [6e5, 5e5, 3e5], [0.02] * 3, [3.0] * 3, 0.02
DT_RECORD, STOP = 0.01, 6.0


def pulse():
    """2 m/s2 on [0.5, 0.8) s, held per 0.01 s sample (loads start after rest)."""
    return np.array([2.0 if 50 <= i < 80 else 0.0 for i in range(int(round(STOP / DT_RECORD)))])


def ours(samples):
    law = check_storeys(K, FY, B, H, M, 1, 9.81, 0.1)
    motion = YieldingMotion(ShearBuilding(M, K, ZETA, H, law.geometric), law, 0.1)
    roof = [0.0]
    for i, a in enumerate(samples):
        motion.advance((i + 1) * DT_RECORD, [0.0] * 3, a)
        roof.append(motion.x[2])
    assert motion.storeys.events >= 4  # the storeys yielded and unloaded
    return np.array(roof)


def test_opensees_converges_to_our_yielding_building():
    """OpenSees runs in a child process (running.isolated, hard_exit: see there why)."""
    from pidamper.running import isolated

    assert isolated.call("pidamper.oracles.opensees:available", hard_exit=True) is None  # the test extra has it
    samples = pulse()
    exact = ours(samples)
    peak = np.abs(exact).max()
    steps, errors = [1e-3, 1e-4, 1e-5], []
    for dt in steps:
        x = isolated.call("pidamper.oracles.opensees:roof_history", M, K, FY, B, H, ZETA, True, samples.tolist(),
                          DT_RECORD, dt, STOP, hard_exit=True)
        errors.append(np.abs(np.array(x) - exact).max() / peak)
    order = np.polyfit(np.log10(steps), np.log10(errors), 1)[0]
    assert 0.8 <= order <= 2.2, (errors, order)
    assert errors[-1] <= 1e-4, errors


def test_staircase_holds_each_sample_over_its_interval():
    times, values = peer.staircase([1.0, 2.0, 3.0], 0.5)
    assert times == [0.0, 0.5, 0.5, 1.0, 1.0, 1.5]
    assert values == [1.0, 1.0, 2.0, 2.0, 3.0, 3.0]
