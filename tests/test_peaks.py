"""The building FMUs' running maxima (storey[k].drift_ratio_max, floor[k].v_abs_max,
floor[k].a_abs_max) are exact: against an independent integration of every smooth piece."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import eigh
from scipy.optimize import minimize_scalar

from pidamper import CoreStepper, FmuStepper, find_fmu, forcing
from pidamper_physics.building_level import BuildingFlight

MASSES, STIFF, HEIGHTS = [1.0e5, 1.0e5, 1.0e5], [2.0e8, 2.0e8, 2.0e8], [3.5, 3.0, 3.0]
CASE = {"storeys": 3, "fidelity": 1, "zeta_s": 0.02, "zeta_p": 0.01, "mu": 0.05, "FR": 0.95, "d": 0.005, "e": 0.5,
        **{f"floor[{k + 1}].m": m for k, m in enumerate(MASSES)},
        **{f"storey[{k + 1}].k": s for k, s in enumerate(STIFF)},
        **{f"storey[{k + 1}].h": h for k, h in enumerate(HEIGHTS)}}
H = 0.01


def matrices():
    """M, K and the classical modal damping C of the building (numpy / scipy, not the core's)."""
    M = np.diag(MASSES)
    k = STIFF + [0.0]
    K = np.diag([k[i] + k[i + 1] for i in range(3)]) - np.diag(k[1:3], 1) - np.diag(k[1:3], -1)
    w2, phi = eigh(K, M)  # mass-normalised shapes
    C = M @ phi @ np.diag(2 * CASE["zeta_s"] * np.sqrt(w2)) @ phi.T @ M
    return M, K, C, math.sqrt(w2[0])


def sampled_and_refined(quantities, s0, s1, intervals):
    """Largest values of quantities(s) (an array) over [s0, s1]: sampled on a grid, each sampled
    local maximum refined by a bounded scalar maximiser over its two grid intervals."""
    grid = np.linspace(s0, s1, intervals + 1)
    values = np.array([quantities(s) for s in grid])
    tops = values.max(axis=0)
    for index in np.ndindex(tops.shape):
        series = values[(slice(None),) + index]
        for i in range(1, intervals):
            if series[i] >= series[i - 1] and series[i] >= series[i + 1]:
                best = minimize_scalar(lambda s: -quantities(s)[index], bounds=(grid[i - 1], grid[i + 1]),
                                       method="bounded", options={"xatol": 1e-14 * max(s1 - s0, 1e-300)})
                tops[index] = max(tops[index], -best.fun)
    return tops


def pieces(signal, n_steps):
    """The core's smooth pieces (t0, t1, free?, start state) with the ground acceleration over each."""
    out = []
    with CoreStepper(CASE, forcing=signal) as stepper:
        core = stepper.core

        def take(seg, t0, t1):
            out.append((t0, t1, isinstance(seg, BuildingFlight), list(seg.state(0.0)), ground[0]))

        ground = [0.0]
        for k in range(n_steps):
            ground[0] = float(signal.value(k * H))
            core.advance((k + 1) * H, 0.0, ground[0], observe=take)
        return out, core.impacts


def oracle_peaks(piece_list):
    """Running maxima over every piece, each integrated by solve_ivp (rtol 1e-12) from its start
    state, sampled on 40 points and refined by a bounded scalar maximiser around each sampled peak."""
    M, K, C, w_1 = matrices()
    m = CASE["mu"] * sum(MASSES)
    w1 = CASE["FR"] * w_1
    cp = 2 * CASE["zeta_p"] * m * w1
    Minv = np.linalg.inv(M)
    ride = M.copy()
    ride[2, 2] += m
    Rinv = np.linalg.inv(ride)
    tops = np.zeros((3, 3))  # drift ratio, |v_abs|, |a_abs| per storey / floor
    v_ground = 0.0

    for t0, t1, free, z0, ag in piece_list:
        tau = t1 - t0

        def accel(z):
            if free:
                x, y, v, u = z[:3], z[3], z[4:7], z[7]
                wire = m * w1 ** 2 * (y - x[2]) + cp * (u - v[2])
                f = -MASSES[0] * ag * np.ones(3)
                f = -np.asarray(MASSES) * ag
                f[2] += wire
                return Minv @ (f - C @ v - K @ x), -ag - wire / m
            x, v = z[:3], z[3:]
            load = -np.asarray(MASSES) * ag
            load[2] -= m * ag
            return Rinv @ (load - C @ v - K @ x), None

        def rhs(_, z):
            a, b = accel(z)
            if free:
                return np.concatenate([z[4:7], [z[7]], a, [b]])
            return np.concatenate([z[3:], a])

        if tau > 0.0:
            sol = solve_ivp(rhs, (0.0, tau), z0, method="DOP853", rtol=1e-12, atol=1e-16, dense_output=True)
            at = sol.sol
        else:
            at = lambda s: np.asarray(z0)  # noqa: E731

        def quantities(s, vg=v_ground):
            z = at(s)
            x, v = (z[:3], z[4:7]) if free else (z[:3], z[3:])
            drift = np.diff(np.concatenate([[0.0], x])) / HEIGHTS
            return np.abs(np.stack([drift, v + vg + ag * s, accel(z)[0] + ag]))

        tops = np.maximum(tops, sampled_and_refined(quantities, 0.0, tau, 40))
        v_ground += ag * tau
    return tops


def test_running_maxima_match_an_independent_integration_within_1e_9():
    """DampedShearBuilding3.fmu under a Kanai-Tajimi record with hundreds of impacts: each running
    maximum equals the oracle's to 1e-9 of the peak, and the sampled values under-read it."""
    signal = forcing.kanai_tajimi(8.0, pga=4.0, seed=3, dt=0.01)
    n_steps = 800
    piece_list, impacts = pieces(signal, n_steps)
    assert impacts >= 200
    expected = oracle_peaks(piece_list)
    names = [[f"storey[{k}].drift_ratio_max" for k in (1, 2, 3)], [f"floor[{k}].v_abs_max" for k in (1, 2, 3)],
             [f"floor[{k}].a_abs_max" for k in (1, 2, 3)]]
    sampled = np.zeros((3, 3))
    with FmuStepper(find_fmu(storeys=3), CASE, forcing=signal) as fmu:
        for k in range(1, n_steps + 1):
            fmu.advance(k * H)
            sampled[0] = np.maximum(sampled[0], [abs(fmu.get(f"storey[{i}].drift_ratio")) for i in (1, 2, 3)])
            sampled[2] = np.maximum(sampled[2], [abs(fmu.get(f"floor[{i}].a")) for i in (1, 2, 3)])
        assert fmu.get("impacts") == impacts
        got = np.array([[fmu.get(n) for n in row] for row in names])
    assert got == pytest.approx(expected, rel=1e-9, abs=0.0)
    assert np.all(got[0] >= sampled[0]) and np.all(got[2] >= sampled[2])
    assert np.any(got[2] > sampled[2] * (1 + 1e-3))  # sampling at the communication points under-reads


def test_the_maxima_are_part_of_the_fmu_state():
    """get/set FMU state keeps the maxima: a run restored to an earlier state and run again ends with
    the same maxima, bit for bit."""
    signal = forcing.kanai_tajimi(2.0, pga=4.0, seed=5, dt=0.01)
    with FmuStepper(find_fmu(storeys=3), CASE, forcing=signal) as fmu:
        for k in range(1, 101):
            fmu.advance(k * H)
        saved = fmu.save()
        before = [fmu.get(f"floor[{i}].a_abs_max") for i in (1, 2, 3)]
        for k in range(101, 201):
            fmu.advance(k * H)
        first = [fmu.get(f"floor[{i}].a_abs_max") for i in (1, 2, 3)] + [fmu.get("storey[1].drift_ratio_max")]
        fmu.restore(saved)
        assert [fmu.get(f"floor[{i}].a_abs_max") for i in (1, 2, 3)] == before
        for k in range(101, 201):
            fmu.advance(k * H)
        assert [fmu.get(f"floor[{i}].a_abs_max") for i in (1, 2, 3)] + [fmu.get("storey[1].drift_ratio_max")] == first


def test_the_bare_building_s_maxima_match_the_matrix_exponential():
    """ShearBuilding<N>'s core (ShearMotion) under held forces, ground acceleration and floor
    impulses: its running maxima against the matrix exponential of the augmented state (scipy),
    sampled and refined on every piece between impulses, to 1e-9; both sides of an impulse count."""
    from scipy.linalg import expm

    from pidamper_physics.params import check_building
    from pidamper_physics.shear_motion import ShearMotion

    masses, stiff, heights, zeta = [1.2e5, 1.0e5, 0.8e5], [9e7, 8e7, 6e7], [4.0, 3.0, 3.0], 0.03
    building = check_building(masses, stiff, zeta, heights)
    motion = ShearMotion(building)
    M = np.diag(masses)
    Minv = np.linalg.inv(M)
    K, C = np.array(building.K), np.array(building.C)
    rng = np.random.default_rng(7)
    h, tops, v_ground = 0.01, np.zeros((3, 3)), 0.0
    for step in range(300):
        F = rng.normal(0.0, 2e5, 3)
        ag = float(rng.normal(0.0, 3.0))
        kicks = [(float(rng.uniform(0.0, h)), int(rng.integers(3)), float(rng.normal(0.0, 2e3)))] if step % 7 == 0 else []
        t0 = motion.t
        x, v = (np.array(z) for z in motion.floors())
        A = np.zeros((7, 7))
        A[:3, 3:6] = np.eye(3)
        A[3:6, :3], A[3:6, 3:6], A[3:6, 6] = -Minv @ K, -Minv @ C, Minv @ F - ag
        cuts = [0.0] + [tk for tk, _, _ in sorted(kicks)] + [h]
        y = np.concatenate([x, v, [1.0]])
        for (s0, s1), kick in zip(zip(cuts, cuts[1:]), sorted(kicks) + [None]):
            def at(s, y=y, s0=s0):
                z = expm(A * (s - s0)) @ y
                xs, vs = z[:3], z[3:6]
                drift = np.diff(np.concatenate([[0.0], xs])) / heights
                return np.abs(np.stack([drift, vs + v_ground + ag * s, Minv @ (F - C @ vs - K @ xs)]))
            tops = np.maximum(tops, sampled_and_refined(at, s0, s1, 30))
            y = expm(A * (s1 - s0)) @ y
            if kick is not None:
                y[3 + kick[1]] += kick[2] / masses[kick[1]]
        v_ground += ag * h
        motion.advance(t0 + h, list(F), ag, [(t0 + tk, k, J) for tk, k, J in kicks])
    got = np.array([motion.peaks.drift, motion.peaks.velocity, motion.peaks.acceleration])
    assert got == pytest.approx(tops, rel=1e-9, abs=0.0)


class _PolynomialPiece:
    """One floor under a storey of 1 m moving as a polynomial x(s) relative to the ground (held a_g =
    0): every derivative in closed form and its bound over [0, tau] by the sum of the Taylor terms'
    magnitudes, in peaks.Piece's protocol."""

    def __init__(self, poly, tau):
        self.p, self.tau = poly, tau

    def _d(self, s, j):
        return float(self.p.deriv(j)(s)) if j else float(self.p(s))

    def start(self):
        return tuple([self._d(0.0, j)] for j in range(5))

    def first(self):
        return tuple([self._d(0.0, j)] for j in range(3))

    def _bound(self, j):
        c = self.p.deriv(j).coef if j else self.p.coef
        return float(sum(abs(a) * self.tau ** i for i, a in enumerate(c)))

    def bounds(self, floor_order, drift_order):
        return [[self._bound(floor_order), self._bound(floor_order + 1)]], [self._bound(drift_order)]

    def derivatives(self, s, floors):
        return {k: [self._d(s, j) for j in range(lo, hi)] for k, (lo, hi) in floors.items()}


def _polynomial_top(poly, tau):
    """max |poly| over [0, tau]: at the ends and the real roots of its derivative inside."""
    points = [0.0, tau] + [r.real for r in poly.deriv().roots() if abs(r.imag) < 1e-12 and 0.0 < r.real < tau]
    return max(abs(float(poly(s))) for s in points)


def test_a_piece_is_cleared_only_where_no_value_exceeds_its_maximum():
    """Peaks.take on closed-form pieces (random polynomials of degree 3 to 6, convex and concave): a
    maximum set just below the piece's true peak (1e-8 of it) is raised to that peak (to 1e-12),
    whatever bound (first or second order, or the search) settles the piece: any bound that cleared
    a piece holding a larger value would leave it below.  The other two maxima are set far above
    any value (1e6 times), so that the one under test decides whether the piece is searched."""
    from numpy.polynomial import Polynomial

    from pidamper_physics.peaks import Peaks, Piece

    piece_type = type("PolynomialPiece", (_PolynomialPiece, Piece), {})
    rng = np.random.default_rng(11)
    names = ("drift", "velocity", "acceleration")
    decided = 0
    for case in range(600):
        tau = 10 ** rng.uniform(-3, -1)
        degree = int(rng.integers(3, 7))
        poly = Polynomial([rng.normal() / tau ** j * 10 ** rng.uniform(-1, 0) for j in range(degree + 1)])
        tops = [_polynomial_top(poly.deriv(q) if q else poly, tau) for q in range(3)]
        under = int(rng.integers(3))
        start = abs(float(poly.deriv(under)(0.0) if under else poly(0.0)))
        if start > 0.999 * tops[under]:
            continue  # the peak is (nearly) the start's: nothing for a bound to decide
        peaks = Peaks([1.0])
        for q, top in enumerate(tops):
            getattr(peaks, names[q])[0] = top * (1 - 1e-8) if q == under else 1e6 * (top + 1.0)
        peaks.take(piece_type(poly, tau), tau, 0.0)
        got = [peaks.drift[0], peaks.velocity[0], peaks.acceleration[0]]
        for q, top in enumerate(tops):
            if q == under:
                assert got[q] == pytest.approx(top, rel=1e-12), (case, names[q])
            else:
                assert got[q] == 1e6 * (top + 1.0), (case, names[q])
        decided += 1
    assert decided > 300
