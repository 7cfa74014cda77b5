"""The energy check the building tests share: ours against an independent reference's integrals."""
import pytest


def assert_energy_matches(ours, integrals):
    """The hysteretic and the dashpots' energy of `ours` (a building motion after its run) each agree
    with the reference's (the last row of its integrals: ..., viscous, hysteretic) to 1e-7 of the
    input, and E(0) + work_in = E + viscous + hysteretic closes to 1e-9 of it."""
    scale = ours.work_in + abs(ours.energy0)
    assert ours.hysteretic == pytest.approx(integrals[-1, -1], abs=1e-7 * scale)
    assert ours.viscous == pytest.approx(integrals[-1, -2], abs=1e-7 * scale)
    balance = ours.energy0 + ours.work_in - ours.energy() - ours.viscous - ours.hysteretic
    assert abs(balance) <= 1e-9 * scale
