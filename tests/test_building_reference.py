"""Checks of the reference integrator `building_reference` (the oracle) against closed forms:
linear flight against matrix exponentials, one impact against the impact law applied by hand,
the energy balance through many impacts, and a particle riding a stop under a held a_g."""
import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

from pidamper.oracles.building_reference import simulate

MASSES = [2.0e3, 1.8e3, 1.5e3]
STIFF = [4.0e5, 3.5e5, 3.0e5]


def linear_model(masses, stiffnesses, zeta_s, mu, FR, zeta_p, floor):
    """(A, first building frequency, particle mass) of the (N + 1)-DOF system q = [x, y] (y the
    particle relative to the ground), built independently of the oracle: the pendulum is a spring
    m w1^2 and a dashpot between floor j and the particle, and the building's classical damping
    for one ratio zeta_s is the matrix function C = 2 zeta_s M^1/2 (M^-1/2 K M^-1/2)^1/2 M^1/2."""
    n = len(masses)
    M = np.diag(masses)
    K = np.diag(np.append(stiffnesses[1:], 0.0) + stiffnesses) - np.diag(stiffnesses[1:], 1) - np.diag(stiffnesses[1:], -1)
    root = np.diag(np.sqrt(masses))
    iroot = np.diag(1.0 / np.sqrt(masses))
    C = 2.0 * zeta_s * root @ np.real(scipy.linalg.sqrtm(iroot @ K @ iroot)) @ root
    w_1 = np.sqrt(np.min(np.linalg.eigvals(np.linalg.solve(M, K)).real))
    m = mu * sum(masses)
    w1 = FR * w_1
    kp, cp = m * w1 ** 2, 2.0 * zeta_p * m * w1
    j = floor - 1
    Mq, Kq, Cq = np.zeros((n + 1, n + 1)), np.zeros((n + 1, n + 1)), np.zeros((n + 1, n + 1))
    Mq[:n, :n], Kq[:n, :n], Cq[:n, :n], Mq[n, n] = M, K, C, m
    for mat, c in ((Kq, kp), (Cq, cp)):
        mat[j, j] += c
        mat[n, n] += c
        mat[j, n] -= c
        mat[n, j] -= c
    Minv = np.linalg.inv(Mq)
    A = np.block([[np.zeros((n + 1, n + 1)), np.eye(n + 1)], [-Minv @ Kq, -Minv @ Cq]])
    return A, Minv, Mq, m


def propagate(A, Minv, Mq, z0, t, a_g, F, floor):
    """z(t) of z' = A z + b under held a_g and F, by one exponential of the augmented matrix."""
    n1 = Mq.shape[0]
    load = -Mq @ np.ones(n1) * a_g
    load[floor - 1] += F
    b = np.concatenate((np.zeros(n1), Minv @ load))
    aug = np.zeros((2 * n1 + 1, 2 * n1 + 1))
    aug[:2 * n1, :2 * n1], aug[:2 * n1, -1] = A, b
    return (scipy.linalg.expm(aug * t) @ np.append(z0, 1.0))[:2 * n1]


def to_oracle(z, floor):
    """(x, v, r, rdot) from z = [x, y, x', y']."""
    n = (len(z) - 2) // 2
    x, y, v, u = z[:n], z[n], z[n + 1:2 * n + 1], z[2 * n + 1]
    return x, v, y - x[floor - 1], u - v[floor - 1]


@pytest.mark.parametrize("damped", [False, True])
def test_free_flight_matches_matrix_exponential(damped):
    """(1) No contact (d huge): the oracle is the linear (N+1)-DOF system, so it must match expm."""
    zeta_s, zeta_p = (0.03, 0.05) if damped else (0.0, 0.0)
    floor, a_g, F = 2, 0.7, 150.0
    x0, v0, r0, rd0 = np.array([0.003, -0.001, 0.002]), np.array([0.01, 0.0, -0.02]), 0.01, 0.05
    ts = np.linspace(0.0, 3.0, 31)
    res = simulate(MASSES, STIFF, zeta_s, 0.05, 0.9, 1e3, 0.5, zeta_p, 3.0, damper_floor=floor,
                   a_g=a_g, F=F, x0=x0, v0=v0, r0=r0, rdot0=rd0, sample_times=ts)
    assert res["impacts"] == [] and res["stick"] == []
    A, Minv, Mq, m = linear_model(MASSES, STIFF, zeta_s, 0.05, 0.9, zeta_p, floor)
    assert res["m"] == pytest.approx(m, rel=1e-15)
    z0 = np.concatenate((x0, [x0[floor - 1] + r0], v0, [v0[floor - 1] + rd0]))
    exact = np.array([np.concatenate(to_oracle(propagate(A, Minv, Mq, z0, t, a_g, F, floor), floor)[:2])
                      for t in ts])
    rel = np.array([to_oracle(propagate(A, Minv, Mq, z0, t, a_g, F, floor), floor)[2:] for t in ts])
    xs, vs = exact[:, :3], exact[:, 3:]
    assert np.max(np.abs(res["x"] - xs)) <= 1e-9 * np.max(np.abs(xs))
    assert np.max(np.abs(res["v"] - vs)) <= 1e-9 * np.max(np.abs(vs))
    assert np.max(np.abs(res["r"] - rel[:, 0])) <= 1e-9 * np.max(np.abs(rel[:, 0]))
    assert np.max(np.abs(res["rdot"] - rel[:, 1])) <= 1e-9 * np.max(np.abs(rel[:, 1]))
    if not damped:
        assert res["viscous"] == 0.0
    assert abs(res["balance"]) <= 1e-10 * (abs(res["work"]) + res["energy0"])


def test_single_impact_matches_the_law_applied_by_hand():
    """(2) Flight, one impact, flight: expm up to the contact time found by root finding, the
    impact law applied here (momentum between the particle and floor j only, r'+ = -e r'-), expm
    again; plus momentum / restitution / loss across the impact from the oracle's own samples."""
    floor, e, d, zeta_s, zeta_p, mu, FR = 2, 0.6, 0.01, 0.02, 0.03, 0.04, 1.1
    rd0 = 0.4
    A, Minv, Mq, m = linear_model(MASSES, STIFF, zeta_s, mu, FR, zeta_p, floor)
    j, n = floor - 1, 3
    z0 = np.zeros(2 * n + 2)
    z0[2 * n + 1] = rd0
    gap = lambda t: to_oracle(propagate(A, Minv, Mq, z0, t, 0.0, 0.0, floor), floor)[2] - d
    t_hit = brentq(gap, 1e-6, 2.0 * d / rd0, xtol=1e-15, rtol=1e-15)
    zi = propagate(A, Minv, Mq, z0, t_hit, 0.0, 0.0, floor)
    vj, u = zi[n + 1 + j], zi[2 * n + 1]
    w = u - vj
    mj = MASSES[j]
    P = mj * vj + m * u
    vj_new = (P + m * e * w) / (m + mj)  # momentum and Newton's law solved by hand
    u_new = vj_new - e * w
    zp = zi.copy()
    zp[n + 1 + j], zp[2 * n + 1] = vj_new, u_new
    t_end = t_hit + 0.03
    ts = np.linspace(t_hit + 0.001, t_end, 30)
    after = [to_oracle(propagate(A, Minv, Mq, zp, t - t_hit, 0.0, 0.0, floor), floor) for t in ts]
    assert all(abs(a[2]) < d for a in after)  # exactly one impact on this window
    res = simulate(MASSES, STIFF, zeta_s, mu, FR, d, e, zeta_p, t_end, damper_floor=floor,
                   rdot0=rd0, sample_times=ts)
    assert len(res["impacts"]) == 1 and res["stick"] == []
    t_imp, side, w_b, w_a, loss = res["impacts"][0]
    assert side == 1
    assert t_imp == pytest.approx(t_hit, abs=1e-12)
    assert w_b == pytest.approx(w, rel=1e-9) and w_a == -e * w_b
    assert loss == pytest.approx(0.5 * m * mj / (m + mj) * (1 - e * e) * w * w, rel=1e-9)
    vjb, ub, vja, ua = res["impact_states"][0]
    assert mj * vja + m * ua == pytest.approx(mj * vjb + m * ub, rel=1e-14, abs=1e-14 * m * abs(w))
    assert ua - vja == pytest.approx(-e * (ub - vjb), rel=1e-12)
    xs = np.array([a[0] for a in after])
    vs = np.array([a[1] for a in after])
    rs = np.array([a[2] for a in after])
    assert np.max(np.abs(res["x"] - xs)) <= 1e-8 * np.max(np.abs(xs))
    assert np.max(np.abs(res["v"] - vs)) <= 1e-8 * np.max(np.abs(vs))
    assert np.max(np.abs(res["r"] - rs)) <= 1e-8 * d

    # the jump seen in the oracle's dense samples just around the impact
    h = 1e-9
    near = simulate(MASSES, STIFF, zeta_s, mu, FR, d, e, zeta_p, t_hit + 1e-3, damper_floor=floor,
                    rdot0=rd0, sample_times=[t_imp - h, t_imp + h])
    momentum = near["v"] @ np.array(MASSES) + m * near["u"]
    assert abs(momentum[1] - momentum[0]) <= 1e-6 * m * abs(w)  # only O(h) from the storey forces
    others = [k for k in range(n) if k != j]
    assert np.max(np.abs(near["v"][1, others] - near["v"][0, others])) <= 1e-6 * abs(w)
    assert near["rdot"][1] == pytest.approx(-e * near["rdot"][0], rel=1e-6)
    assert near["energy_t"][0] - near["energy_t"][1] == pytest.approx(loss, rel=1e-5)


def test_energy_balance_through_many_impacts():
    """(3) E(0) + work - E(t) = viscous + impact losses, to ~1e-8 relative, at every sample."""
    ts = np.linspace(0.0, 6.0, 601)
    res = simulate(MASSES, STIFF, 0.02, 0.05, 1.0, 0.02, 0.5, 0.05, 6.0, damper_floor=2,
                   a_g=lambda t: 3.0 * np.sin(8.0 * t), F=lambda t: 200.0 * np.cos(5.0 * t),
                   x0=[0.001, 0.0, -0.002], r0=0.005, sample_times=ts)
    assert len(res["impacts"]) > 50
    assert np.max(np.abs(res["r"])) <= 0.02
    scale = max(abs(res["work"]), res["dissipated"], res["energy0"], np.max(res["energy_t"]))
    assert abs(res["balance"]) <= 1e-8 * scale
    gap = res["energy0"] + res["work_t"] - res["energy_t"] - res["viscous_t"] - res["impact_loss_t"]
    assert np.max(np.abs(gap)) <= 1e-8 * scale
    assert res["impact_loss"] == pytest.approx(sum(imp[4] for imp in res["impacts"]), rel=1e-14)
    assert res["impact_loss"] > 0.0 and res["viscous"] > 0.0


def test_particle_rides_the_stop_under_a_held_ground_acceleration():
    """(4) A held a_g larger than w1^2 d drives the particle onto the stop at -d: it chatters,
    sticks and rides it; the stop pushes it toward +r (N >= 0) throughout, and the building
    settles at the static deflection of the augmented mass, K x = -(M 1 + m e_j) a_g."""
    floor, d, a_g = 2, 0.02, 2.0
    M, K = np.diag(MASSES), np.diag([7.5e5, 6.5e5, 3.0e5]) - np.diag([3.5e5, 3.0e5], 1) - np.diag([3.5e5, 3.0e5], -1)
    x0 = np.linalg.solve(K, -M @ np.ones(3) * a_g)  # at rest under a_g, the particle free at r = 0
    ts = np.linspace(0.0, 20.0, 401)
    res = simulate(MASSES, STIFF, 0.1, 0.05, 1.0, d, 0.5, 0.05, 20.0, damper_floor=floor, a_g=a_g,
                   x0=x0, sample_times=ts)
    assert res["w1"] ** 2 * d < a_g
    assert len(res["stick"]) == 1
    t0, t1, side = res["stick"][0]
    assert side == -1 and t1 == 20.0
    assert len(res["impacts"]) > 3 and res["impacts"][-1][3] == 0.0 and res["impacts"][-1][0] == t0
    riding = res["side"] == -1
    assert np.array_equal(riding, ts >= t0)
    assert np.all(res["N"][riding] > 0.0)
    assert np.all(res["r"][riding] == -d) and np.all(res["rdot"][riding] == 0.0)
    assert np.max(np.abs(res["v"][riding, floor - 1] - res["u"][riding])) == 0.0
    m = res["m"]
    load = -M @ np.ones(3) * a_g
    load[floor - 1] -= m * a_g
    assert res["x"][-1] == pytest.approx(np.linalg.solve(K, load), rel=1e-4)
    assert res["N"][-1] == pytest.approx(m * a_g - m * res["w1"] ** 2 * d, rel=1e-4)
    assert abs(res["balance"]) <= 1e-8 * max(abs(res["work"]), res["dissipated"], res["energy0"])


def test_release_when_the_contact_force_vanishes():
    """(4b) The same ride, then a_g is eased to zero: N crosses zero, the particle leaves the stop
    (no impact at release) and flies freely again."""
    floor, d, A = 2, 0.02, 2.0

    def a_g(t):
        if t < 3.0:
            return A
        if t < 4.0:
            return A * 0.5 * (1.0 + np.cos(np.pi * (t - 3.0)))
        return 0.0

    M = np.diag(MASSES)
    K = np.diag([7.5e5, 6.5e5, 3.0e5]) - np.diag([3.5e5, 3.0e5], 1) - np.diag([3.5e5, 3.0e5], -1)
    ts = np.linspace(0.0, 6.0, 601)
    res = simulate(MASSES, STIFF, 0.1, 0.05, 1.0, d, 0.5, 0.05, 6.0, damper_floor=floor, a_g=a_g,
                   x0=np.linalg.solve(K, -M @ np.ones(3) * A), sample_times=ts)
    assert len(res["stick"]) == 1
    t0, t1, side = res["stick"][0]
    assert side == -1 and t0 < 3.0 < t1 < 4.0
    riding = (ts > t0) & (ts < t1)
    assert np.all(res["N"][riding] > 0.0)
    assert res["N"][riding][-1] < 0.02 * res["m"] * A  # fading out as the release nears
    after = (ts > t1) & (ts < t1 + 0.05)
    assert np.all(res["side"][after] == 0) and np.all(res["r"][after] > -d)
    assert not any(t1 < imp[0] < t1 + 0.05 for imp in res["impacts"])
    assert abs(res["balance"]) <= 1e-8 * max(abs(res["work"]), res["dissipated"], res["energy0"])
