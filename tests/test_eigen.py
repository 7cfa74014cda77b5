"""The general eigen-solver (eigen.py) and Modes for n >= 3 against numpy / scipy; n <= 2 unchanged."""
import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.optimize import linear_sum_assignment

from pidamper_physics import eigen, modal
from pidamper_physics.modal import Modes, ModesError, Motion

DAMPINGS = ("none", "classical", "nonclassical", "heavy")


def building(seed, n, damping):
    """Mass-normalised (K, C) of an (n - 1)-storey shear building with a light particle hung from one
    floor (n DOF): M^-1 K and M^-1 C, not symmetric; "heavy" overdamps the particle and a storey."""
    rng = np.random.default_rng(seed)
    nf = n - 1
    m = rng.uniform(0.6, 1.4, nf) * 1e5
    k = rng.uniform(0.6, 1.4, nf) * 2e8
    floor = int(rng.integers(nf)) if rng.uniform() < 0.5 else nf - 1
    mp = rng.uniform(0.01, 0.05) * m[floor]
    Kf = np.zeros((n, n))
    for i in range(nf):
        Kf[i, i] += k[i]
        if i > 0:
            Kf[i - 1, i - 1] += k[i]
            Kf[i - 1, i] -= k[i]
            Kf[i, i - 1] -= k[i]
    M = np.diag(np.append(m, mp))
    w1 = math.sqrt(min(abs(np.linalg.eigvals(np.linalg.solve(M[:nf, :nf], Kf[:nf, :nf])))))
    wp = w1 * rng.uniform(0.8, 1.25)
    kp = mp * wp * wp

    def join(mat, i, j, value):
        mat[i, i] += value
        mat[j, j] += value
        mat[i, j] -= value
        mat[j, i] -= value

    join(Kf, floor, nf, kp)
    Cf = np.zeros((n, n))
    if damping == "classical":  # Rayleigh: M^-1 C = a I + b M^-1 K
        Cf = 0.05 * w1 * M + 0.02 / w1 * Kf
    elif damping in ("nonclassical", "heavy"):
        zeta = 0.05 if damping == "nonclassical" else rng.uniform(2.0, 5.0)
        join(Cf, floor, nf, 2.0 * zeta * mp * wp)
        for i in rng.choice(nf, size=max(1, nf // 3), replace=False):
            zs = rng.uniform(0.01, 0.1) if damping == "nonclassical" else rng.uniform(0.5, 3.0)
            c = 2.0 * zs * math.sqrt(k[i] * m[i])
            if i == 0:
                Cf[0, 0] += c
            else:
                join(Cf, i - 1, i, c)
    return np.linalg.solve(M, Kf), np.linalg.solve(M, Cf)


def state_matrix(K, C):
    n = len(K)
    return np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])


def full(modes):
    """(lam, V, W) of all 2n modes, unfolding each weight-2 mode into its conjugate pair."""
    lam, cols, rows = [], [], []
    V, W = np.array(modes.V), np.array(modes.W)
    for k, (x, w) in enumerate(zip(modes.lam, modes.weight)):
        lam.append(x)
        cols.append(V[:, k])
        rows.append(W[k])
        if w == 2.0:
            lam.append(x.conjugate())
            cols.append(V[:, k].conj())
            rows.append(W[k].conj())
    return np.array(lam), np.array(cols).T, np.array(rows)


def eigenvalue_error(ours, ref):
    cost = np.abs(ours[:, None] - ref[None, :])
    r, c = linear_sum_assignment(cost)
    return cost[r, c].max() / np.abs(ref).max()


CASES = [(n, damping) for n in range(3, 12) for damping in DAMPINGS]


@pytest.mark.parametrize("n, damping", CASES)
def test_modes_match_numpy(n, damping):
    worst = {"lam": 0.0, "recon": 0.0, "motion": 0.0}
    for seed in range(3):
        K, C = building(1000 * n + seed, n, damping)
        modes = Modes(K.tolist(), C.tolist())
        assert modes.n == n and sum(modes.weight) == 2 * n
        A = state_matrix(K, C)
        lam, V, W = full(modes)
        ref = np.linalg.eigvals(A)
        worst["lam"] = max(worst["lam"], eigenvalue_error(lam, ref))
        assert modes.fastest == pytest.approx(np.abs(ref).max(), rel=1e-12)
        # real modes: imaginary part exactly 0, real shapes; the rest folded with Im > 0
        for k, (x, w) in enumerate(zip(modes.lam, modes.weight)):
            if w == 1.0:
                assert x.imag == 0.0 and all(row[k].imag == 0.0 for row in modes.V)
            else:
                assert x.imag > 0.0
        if damping == "heavy":
            assert 1.0 in modes.weight  # the overdamped particle gives real modes
        if damping == "none":
            assert np.abs(lam.real).max() <= 1e-12 * np.abs(lam).max()
        # reconstruction in the time unit 1/s (rows and columns of q' scaled by 1/s)
        s = math.sqrt(np.abs(K).max())
        T = np.diag([1.0] * n + [1.0 / s] * n)
        scaled = T @ A @ np.linalg.inv(T) / s
        recon = T @ (V * lam) @ W @ np.linalg.inv(T) / s
        assert np.abs(recon.imag).max() <= 1e-11
        worst["recon"] = max(worst["recon"], np.abs(recon - scaled).max() / np.abs(scaled).max())
        worst["motion"] = max(worst["motion"], motion_error(modes, K, C, np.random.default_rng(seed)))
    print(f"n={n} {damping}: " + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))
    assert worst["lam"] <= 1e-12
    assert worst["recon"] <= 1e-11
    assert worst["motion"] <= 1e-11


def motion_error(modes, K, C, rng):
    """Largest error of Motion.state against expm of the system augmented with the load's
    (sin, cos) and a constant, relative to the largest |z| (q' in the time unit 1/s)."""
    n = len(K)
    s = math.sqrt(np.abs(K).max())
    slow = min(abs(x) for x in modes.lam)
    z0 = np.append(rng.uniform(-1, 1, n) * 1e-2, rng.uniform(-1, 1, n) * 1e-2 * s)
    b = rng.uniform(-1, 1, n) * 1e-2 * s * s
    f = rng.uniform(-1, 1, n) * 1e-2 * s * s
    om, psi = slow * rng.uniform(0.5, 2.0), rng.uniform(0, 2 * math.pi)
    aug = np.zeros((2 * n + 3, 2 * n + 3))
    aug[:2 * n, :2 * n] = state_matrix(K, C)
    aug[n:2 * n, 2 * n] = f
    aug[n:2 * n, 2 * n + 2] = b
    aug[2 * n, 2 * n + 1], aug[2 * n + 1, 2 * n] = om, -om
    x0 = np.concatenate([z0, [math.sin(psi), math.cos(psi), 1.0]])
    unit = np.array([1.0] * n + [1.0 / s] * n)
    worst = 0.0
    for forced in (False, True):
        motion = Motion(modes, z0.tolist(), b.tolist(), f.tolist() if forced else None, om, psi)
        refs, gots = [], []
        for period in (0.0, 0.01, 0.3, 1.0, 3.0):
            tau = period * 2 * math.pi / slow
            x = expm(aug * tau) @ (x0 if forced else np.append(x0[:2 * n], [0.0, 0.0, 1.0]))
            refs.append(x[:2 * n] * unit)
            gots.append(np.array(motion.state(tau)) * unit)
        refs, gots = np.array(refs), np.array(gots)
        worst = max(worst, np.abs(gots - refs).max() / np.abs(refs).max())
    return worst


@pytest.mark.parametrize("size", [4, 9, 16, 22, 30])
def test_eigenvalues_general_matrices(size):
    rng = np.random.default_rng(size)
    for A in (rng.standard_normal((size, size)),
              rng.standard_normal((size, size)) * np.logspace(-4, 4, size)[:, None],  # badly scaled rows
              np.roll(np.eye(size), 1, axis=0)):  # cyclic shift: the Wilkinson shift stalls on it
        ours = np.array(eigen.eigenvalues(A.tolist()))
        assert eigenvalue_error(ours, np.linalg.eigvals(A)) <= 1e-12


def test_coinciding_modes_raise():
    K = [[4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    C = [[0.1, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]]
    with pytest.raises(ModesError, match="coincide"):
        Modes(K, C)
    # critically damped mode: a double real eigenvalue
    with pytest.raises(ModesError):
        Modes([[4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 9.0]], [[0.1, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 0.1]])


def test_solver_failure_is_modes_error(monkeypatch):
    K, C = building(3, 5, "nonclassical")
    monkeypatch.setattr(eigen, "MAX_ITERATIONS", 0)
    with pytest.raises(ModesError, match="eigen-solver"):
        Modes(K.tolist(), C.tolist())


# n <= 2: the closed-form path (quadratic and quartic roots, explicit shapes), not the general solver
SMALL = [
    ([[4.0]], [[0.1]]),
    ([[2.5e3]], [[150.0]]),  # overdamped: two real modes
    ([[1.05 * 39.4784176 + 0.05 * 35.0, -0.05 * 35.0], [-35.0, 35.0]], [[0.3 + 0.05 * 0.2, -0.05 * 0.2], [-0.2, 0.2]]),
    ([[1.02 * 1.0 + 0.02 * 0.9, -0.02 * 0.9], [-0.9, 0.9]], [[0.02 + 0.02 * 3.0, -0.02 * 3.0], [-3.0, 3.0]]),
    ([[39.4784176, 0.0], [0.0, 39.4784176]], [[0.1, 0.0], [0.0, 0.3]]),  # uncoupled, equal frequencies (FR = 1)
    ([[3.0e-12, -1.0e-12], [-2.0e-12, 2.0e-12]], [[1e-7, 0.0], [0.0, 2e-6]]),  # tiny scales
]


@pytest.mark.parametrize("K, C", SMALL)
def test_small_n_closed_form_against_numpy(K, C, monkeypatch):
    """n <= 2 takes the closed form, and it agrees with numpy's eigenvalues of the state matrix
    to 1e-13 of the largest |lam| (a few ulps of the roots), with V diag(lam) W reproducing the
    state matrix to 1e-12 in the time unit of the stiffest term (the conditioning of V enters)."""
    def refuse(K, C):
        raise AssertionError("n <= 2 must not use the general solver")

    monkeypatch.setattr(eigen, "pencil_modes", refuse)
    modes = Modes(K, C)
    n = len(K)
    assert modes.n == n and sum(modes.weight) == 2 * n
    A = state_matrix(np.array(K), np.array(C))
    lam, V, W = full(modes)
    ref = np.linalg.eigvals(A)
    assert eigenvalue_error(lam, ref) <= 1e-13
    assert modes.fastest == pytest.approx(np.abs(ref).max(), rel=1e-13)
    s = math.sqrt(np.abs(np.array(K)).max())
    T = np.diag([1.0] * n + [1.0 / s] * n)
    scaled = T @ A @ np.linalg.inv(T) / s
    recon = T @ (V * lam) @ W @ np.linalg.inv(T) / s
    assert np.abs(recon - scaled).max() <= 1e-12 * np.abs(scaled).max()


def test_general_path_taken_for_n3(monkeypatch):
    calls = []
    real = eigen.pencil_modes
    monkeypatch.setattr(eigen, "pencil_modes", lambda K, C: calls.append(len(K)) or real(K, C))
    K, C = building(1, 3, "classical")
    Modes(K.tolist(), C.tolist())
    assert calls == [3] and modal.eigen is eigen
