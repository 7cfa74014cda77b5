"""Closed-form motion of a damped linear system with n degrees of freedom, by modes.

    q'' + C q' + K q = b + f sin(Omega tau + psi),    tau = t - t0 >= 0

(mass-normalised: K, C in 1/s2, 1/s; b, f in m/s2 per DOF).  With z = (q, q') the system
is z' = A z + ..., A = [[0, I], [-K, -C]], whose eigenvalues lam_k (complex, Re <= 0) and
eigenvectors V[:, k] = (phi_k, lam_k phi_k) are found once per (K, C) by `Modes`.  Each
modal coordinate eta_k obeys eta' = lam eta + beta + gamma sin(Omega tau + psi), solved by

    eta(tau) = exp(lam tau) eta0 + (beta/lam) expm1(lam tau) + g+ E(i Omega) + g- E(-i Omega),
    E(s) = (exp(s tau) - exp(lam tau)) / (s - lam) = tau exp(lam tau) phi1((s - lam) tau),

with g+- = +-gamma exp(+-i psi) / 2i and phi1(w) = (exp(w) - 1)/w summed as a series for small
|w|: exact at and next to resonance.  The held load's part beta/lam expm1(lam tau) is evaluated
without forming exp(lam tau) - 1, so a load that dwarfs the restoring force (a small g, a large
force: beta/lam >> eta) does not cancel.  Complex-conjugate modes are folded (one of each pair,
weight 2), so a two-DOF underdamped system costs two complex modes per evaluation.  n = 1, 2
are solved in closed form (2-DOF: eigen.quartic_roots, V^-1 by eigen.gauss_solve), n >= 3 by the
general eigen-solver (eigen.pencil_modes, eigen.inverse_rows).
Plain Python (math, cmath): this runs inside the FMU.
"""
import cmath
import math
import struct
import math as _libm  # exp, expm1, sin, cos: in the compiled build libc's (modal.pxd), the very functions
# CPython's math and cmath call

from . import _ccomplex as _cx  # complex(re, im): a C complex in the compiled build
from . import _clist as _cl  # sums over lists: C bodies in the compiled build
from . import eigen

#: |lam| / the fastest |lam| below which a mode is secular (a storey of zero tangent): its held
#: load's part is beta tau phi1(lam tau), never beta / lam (an elastic building never has one)
SECULAR = 1e-6
_BOUND_ORDERS = 6  # Motion.bounds tabulates the modes to this order at least (the guards' highest)
_SERIES = 0.25  # |w| below which phi1 is summed as a series (14 terms: below 1e-17)
_INF = math.inf


def phi1(w):
    """(exp(w) - 1) / w for complex w, accurate for every w (series near 0)."""
    if abs(w) > _SERIES:
        return _quot(_exp(w) - 1.0, w)
    term = total = _cx.parts(1.0, 0.0)
    for k in range(2, 16):
        term = _quot(term * w, _cx.parts(k, 0.0))  # term * w / k, as CPython divides by k + 0j
        total += term
    return total


def _exp(z):
    """cmath.exp(z): for finite z with |Re z| <= 700 (no overflow) its formula, exp(Re z) (cos Im z,
    sin Im z), written out with libm's functions as cmath calls them (the same bits; in the compiled
    build a C computation); cmath itself elsewhere (its special values and its OverflowError)."""
    a, b = z.real, z.imag
    if -700.0 <= a <= 700.0 and -_INF < b < _INF:
        el = _libm.exp(a)
        return _cx.parts(el * _libm.cos(b), el * _libm.sin(b))
    return cmath.exp(z)


def exp_pair(z):
    """(exp(z), exp(z) - 1) for complex z, both to full relative precision (cmath has no expm1):
    near 0 the difference is summed from expm1 and the half-angle sine, elsewhere it does not cancel."""
    a, b = z.real, z.imag
    if a * a + b * b > 0.25:
        e = _exp(z)
        return e, e - 1.0
    em = _expm1_near_zero(a, b)
    return em + 1.0, em


def _exp_lead(z):
    """exp_pair(z)[0], without its pair."""
    a, b = z.real, z.imag
    if a * a + b * b > 0.25:
        return _exp(z)
    return _expm1_near_zero(a, b) + 1.0


def _expm1_near_zero(a, b):
    """exp(a + i b) - 1 for |a + i b| <= 0.5, from expm1 and the half-angle sine (no cancellation)."""
    ea = _libm.expm1(a)
    h = _libm.sin(0.5 * b)
    omc = 2.0 * h * h  # 1 - cos(b)
    return _cx.parts(ea - ea * omc - omc, (1.0 + ea) * 2.0 * h * _libm.cos(0.5 * b))


class ModesError(ValueError):
    """The system has coinciding modes (not diagonalisable): closed form by modes fails."""


#: the systems solved in this process, by their matrices' bits: a yielding building meets the same
#: regimes again, in one run and in every run of a study (Modes is read-only once built)
_SOLVED = {}
SOLVED_KEPT = 1024  # systems kept (the oldest dropped first)


def solved_modes(K, C):
    """Modes(K, C), solved once per process for each (K, C) (equal to the last bit, signed zeros
    included: the same matrices give the same modes, so a kept one is what a new solve would give).
    ModesError is raised anew each time."""
    key = (len(K), struct.pack(f"<{len(K) * len(K)}d", *[k for row in K for k in row]),
           struct.pack(f"<{len(C) * len(C)}d", *[c for row in C for c in row]))
    modes = _SOLVED.get(key)
    if modes is None:
        modes = Modes(K, C)
        if len(_SOLVED) >= SOLVED_KEPT:
            del _SOLVED[next(iter(_SOLVED))]
        _SOLVED[key] = modes
    return modes


class Modes:
    """Eigen-decomposition of q'' + C q' + K q (n DOF, K and C as nested lists, not necessarily
    symmetric).  lam: the kept eigenvalues (Im > 0 of each conjugate pair, weight 2; real ones,
    weight 1), V: 2n rows of z = (q, q') by kept mode, W: kept rows of V^-1 (modal projections of
    z), fastest: the largest |lam|.  Raises ModesError if two modes coincide (or, n >= 3, if the
    eigen-solver fails)."""

    __slots__ = ("n", "lam", "weight", "V", "W", "fastest", "secular", "growth_rate", "_weighted", "_complex",
                 "_difference", "_drifts", "_floors", "_powers")

    def __init__(self, K, C):
        n = len(K)
        self.n = n
        self._weighted, self._complex, self._difference, self._drifts = {}, {}, {}, {}  # rows kept (below)
        self._floors, self._powers = {}, {}
        # solved in the time unit 1/s of the stiffest term, so that the state matrix's rows (q and
        # q') have like scales whatever the units (a small g made V ill-scaled: 2e-4 of x lost at
        # g = 1e-15 m/s2); lam, V and W are scaled back at the end
        s = math.sqrt(max(abs(k) for row in K for k in row))
        damping = max(abs(c) for row in C for c in row)
        if s <= 1e-8 * damping or s == 0.0:  # stiffness negligible beside the damping (yielding storeys
            s = damping or 1.0               # of zero tangent): the damping's scale
        K = [[k / (s * s) for k in row] for row in K]
        C = [[c / s for c in row] for row in C]
        uncoupled = n == 2 and K[0][1] == K[1][0] == C[0][1] == C[1][0] == 0.0
        if n >= 3:  # general solver; lams come as exact conjugate pairs and snapped real values
            try:
                lams, vecs = eigen.pencil_modes(K, C)
            except eigen.EigenError as err:
                raise ModesError(f"eigen-solver: {err}") from None
        elif uncoupled:  # two independent oscillators: modes may share a frequency (FR = 1)
            lams = [-0.5 * C[i][i] + sign * cmath.sqrt(0.25 * C[i][i] ** 2 - K[i][i]) for i in (0, 1) for sign in (1, -1)]
        elif n == 1:
            k, c = K[0][0], C[0][0]
            disc = cmath.sqrt(0.25 * c * c - k)
            lams = [-0.5 * c + disc, -0.5 * c - disc]
        else:
            (k11, k12), (k21, k22) = K
            (c11, c12), (c21, c22) = C
            guesses = [-0.5 * c11 + cmath.sqrt(0.25 * c11 * c11 - k11) * (1 + 1e-3j),
                       -0.5 * c11 - cmath.sqrt(0.25 * c11 * c11 - k11) * (1 - 2e-3j),
                       -0.5 * c22 + cmath.sqrt(0.25 * c22 * c22 - k22) * (1.01 + 3e-3j),
                       -0.5 * c22 - cmath.sqrt(0.25 * c22 * c22 - k22) * (0.99 - 4e-3j)]
            lams = eigen.quartic_roots(c11 + c22, k11 + k22 + c11 * c22 - c12 * c21,
                                  c11 * k22 + c22 * k11 - c12 * k21 - c21 * k12, k11 * k22 - k12 * k21, guesses)
        scale = max(abs(x) for x in lams)
        # a zero eigenvalue of multiplicity r >= 2 (r storeys of zero tangent: a mechanism of r
        # degrees of freedom) is semi-simple: its modes are a basis of null(K), lam = 0 exactly
        zeros = [k for k, lam in enumerate(lams) if abs(lam) <= SECULAR * scale] if not uncoupled else []
        if len(zeros) < 2:
            zeros = []
        for k in zeros:
            lams[k] = 0j
        for i in range(len(lams) if not uncoupled else 0):
            for j in range(i):
                if abs(lams[i] - lams[j]) <= 1e-7 * scale and not (i in zeros and j in zeros):
                    raise ModesError(f"two modes coincide (eigenvalue {lams[i]:.6g})")
        if uncoupled:
            vecs = [[1.0 + 0j, 0j]] * 2 + [[0j, 1.0 + 0j]] * 2
        elif n <= 2:
            vecs = [None if k in zeros else self._shape(K, C, lam) for k, lam in enumerate(lams)]
        if zeros:
            basis = eigen.null_space(K, len(zeros))
            if basis is None:
                raise ModesError(f"{len(zeros)} eigenvalues at 0 but K has no null space of that dimension")
            for k, phi in zip(zeros, basis):
                vecs[k] = [complex(t) for t in phi]
        # columns (phi, lam phi)
        V = [[vecs[k][i] for k in range(2 * n)] for i in range(n)] + \
            [[lams[k] * vecs[k][i] for k in range(2 * n)] for i in range(n)]
        # fold conjugate pairs: keep Im > 0 with weight 2, real modes with weight 1
        keep = [k for k, lam in enumerate(lams) if lam.imag > 1e-12 * scale or abs(lam.imag) <= 1e-12 * scale]
        # the kept rows of V^-1: n <= 2 from its columns (solving V x = e_j), else from one LU
        if n <= 2:
            inv_cols = [eigen.gauss_solve(V, [1.0 if r == j else 0.0 for r in range(2 * n)]) for j in range(2 * n)]
            inv_rows = {k: [inv_cols[j][k] for j in range(2 * n)] for k in keep}
        else:
            inv_rows = dict(zip(keep, eigen.inverse_rows(V, keep)))
        self.lam = [s * lams[k] for k in keep]
        self.weight = [2.0 if lams[k].imag > 1e-12 * scale else 1.0 for k in keep]
        # rows: components of z (the velocities' rows back in 1/s); W: modal projections of z
        self.V = [[V[i][k] * (s if i >= n else 1.0) for k in keep] for i in range(2 * n)]
        self.W = [[inv_rows[k][j] / (s if j >= n else 1.0) for j in range(2 * n)] for k in keep]
        self.fastest = s * scale
        # modes of lam ~ 0 (a zero tangent stiffness), and the growth rate of the fastest growing
        # one (Re lam > 0: a negative tangent) [1/s], beyond rounding of the spectrum
        self.secular = [k for k, lam in enumerate(self.lam) if abs(lam) <= SECULAR * self.fastest]
        self.growth_rate = max([lam.real for lam in self.lam if lam.real > 1e-9 * self.fastest], default=0.0)

    def weighted_complex(self, i):
        """weight_k V_ik over the kept modes (component i = sum of the real parts of these times
        the modal coordinates), kept."""
        cache = self._complex
        if i not in cache:
            cache[i] = [w * v for w, v in zip(self.weight, self.V[i])]
        return cache[i]

    def weighted_difference(self, i, j):
        """weight_k |V_ik - V_jk| over the kept modes (the bounds of z_i - z_j), kept."""
        cache = self._difference
        if (i, j) not in cache:
            cache[i, j] = [w * abs(a - b) for w, a, b in zip(self.weight, self.V[i], self.V[j])]
        return cache[i, j]

    def weighted_drifts(self, n):
        """The rows (weighted, weighted_difference) of the drifts z_0, z_1 - z_0, ..., z_(n-1) - z_(n-2)
        (a building's storeys, its floors first in z), kept."""
        cache = self._drifts
        if n not in cache:
            cache[n] = [self.weighted(0)] + [self.weighted_difference(k, k - 1) for k in range(1, n)]
        return cache[n]

    def weighted_floors(self, n):
        """The rows (weighted) of the components 0..n-1 (a building's floors, first in z), kept."""
        cache = self._floors
        if n not in cache:
            cache[n] = [self.weighted(i) for i in range(n)]
        return cache[n]

    def powers(self, orders):
        """Per kept mode [|lam|^j for j < orders] (how a bound grows per derivative), kept."""
        cache = self._powers
        if orders not in cache:
            cache[orders] = [[abs(lam) ** j for j in range(orders)] for lam in self.lam]
        return cache[orders]

    def weighted(self, i):
        """weight_k |V_ik| over the kept modes (the bounds of component i's modal parts), kept."""
        cache = self._weighted
        if i not in cache:
            cache[i] = [w * abs(v) for w, v in zip(self.weight, self.V[i])]
        return cache[i]

    @staticmethod
    def _shape(K, C, lam):
        if len(K) == 1:
            return [1.0 + 0j]
        l2 = lam * lam
        r0 = (l2 + C[0][0] * lam + K[0][0], C[0][1] * lam + K[0][1])
        r1 = (C[1][0] * lam + K[1][0], l2 + C[1][1] * lam + K[1][1])
        a, b = r0 if abs(r0[0]) + abs(r0[1]) >= abs(r1[0]) + abs(r1[1]) else r1
        phi = [-b, a]
        norm = math.sqrt(abs(phi[0]) ** 2 + abs(phi[1]) ** 2)
        return [phi[0] / norm, phi[1] / norm]


class Motion:
    """One segment of q'' + C q' + K q = b + f sin(Omega tau + psi) from z0 = (q0, q0').

    Modes may grow (Re lam > 0: a negative tangent stiffness) or be secular (lam ~ 0: a zero
    tangent; Modes.secular): their parts stay exact and the bounds account for the growth."""

    __slots__ = ("modes", "eta0", "coef", "steady", "gp", "gm", "om", "forced", "psi", "gamma", "beta", "secular",
                 "_columns", "_start", "_at", "_eta", "_levels_tau", "_levels_last")

    def __init__(self, modes, z0, b, f=None, om=0.0, psi=0.0):
        self.modes = modes
        self._columns = self._start = None  # caches: bounds' per-mode table over [0, T], derivatives at 0
        self._at = self._levels_tau = math.nan  # ... and the last modal coordinates and derivatives' levels
        self._eta = self._levels_last = None
        self.om, self.psi = om, psi
        self.forced = f is not None and any(fi != 0.0 for fi in f)
        self.eta0, self.coef, self.steady, self.gp, self.gm, self.gamma = [], [], [], [], [], []
        self.secular = modes.secular
        self._project(modes, z0, b, f, psi)

    def _project(self, modes, z0, b, f, psi):
        """The start z0, the held load b and the harmonic's amplitudes f in modal coordinates: eta0,
        coef, steady (and gamma, gp, gm if forced) per kept mode, beta per secular one."""
        n = modes.n
        eip = cmath.exp(1j * psi) if self.forced else 0j
        lams = modes.lam
        for k in range(len(lams)):
            w = modes.W[k]
            lam = lams[k]
            eta0 = _dot(w, z0, 0, 2 * n)
            c = _quot(_dot(w, b, n, n), lam) if lam != 0 else 0j  # beta / lam
            self.eta0.append(eta0)
            self.coef.append(eta0 + c)
            self.steady.append(-c)
            if self.forced:
                gamma = _dot(w, f, n, n)
                self.gamma.append(gamma)
                self.gp.append(_quot(gamma * eip, 2j))
                self.gm.append(_quot(_quot(-gamma, eip), 2j))
        # secular modes (lam ~ 0): no constant part, their held load's part is beta tau phi1(lam tau)
        self.beta = [_dot(modes.W[k], b, n, n) for k in self.secular]
        for k in self.secular:
            self.coef[k], self.steady[k] = self.eta0[k], 0j

    def modal(self, tau):
        """Modal coordinates eta_k(tau) of the kept modes (the list is shared: do not change it)."""
        if tau == self._at:  # the guards of several segments ask at one tau
            return self._eta
        if tau == 0.0:  # the closed form gives eta0 there (at most a zero's sign apart, which no sum of
            return self.eta0  # the components sees: they add from +0.0)
        lams, eta0 = self.modes.lam, self.eta0
        forced = self.forced
        if forced:
            sp = 1j * self.om
            e_plus, e_minus = _exp(sp * tau), _exp(-sp * tau)
        out = _free(lams, eta0, self.steady, tau)
        if forced:
            gp, gm = self.gp, self.gm
            for k in range(len(lams)):
                lam = lams[k]
                el = _exp_lead(lam * tau)
                o = out[k]
                g, h = gp[k], gm[k]
                out[k] = o + (g * _spread(sp, lam, tau, e_plus, el) + h * _spread(-sp, lam, tau, e_minus, el))
        if self.secular:  # their steady part is 0: the held load's part is beta tau phi1(lam tau)
            for i, k in enumerate(self.secular):
                out[k] += self.beta[i] * tau * phi1(lams[k] * tau)
        self._at, self._eta = tau, out
        return out

    def state(self, tau, rows=None):
        """z(tau) = (q, q') as a list of floats (only the components `rows`, if given, in their order)."""
        eta = self.modal(tau)
        m = self.modes
        weight = m.weight
        out = []
        for row in (m.V if rows is None else [m.V[i] for i in rows]):
            out.append(_weighted_real(weight, row, eta))
        return out

    def derivatives(self, tau, rows, orders=5):
        """{row: [d^j z_row / dtau^j at tau for j = lo..hi-1]} of the components `rows` ({row: (lo,
        hi)} with hi <= orders), from the modal coordinates and their equation
        eta' = lam eta + beta + gamma sin(Omega tau + psi): a few complex products per mode and
        order, cheaper than z(tau) and the system's matrices when a few rows are asked for."""
        m = self.modes
        levels = self._levels_at(tau, orders)
        out = {}
        for i, (lo, hi) in rows.items():
            row = m.weighted_complex(i)
            out[i] = _real_dots(row, levels, lo, hi)
        return out

    def component_derivatives(self, tau, first, last, orders):
        """[[d^j z_i / dtau^j at tau for j < orders] for first <= i < last] (a building's floors i), as
        derivatives() gives them."""
        m = self.modes
        levels = self._levels_at(tau, orders)
        out = []
        for i in range(first, last):
            out.append(_real_dots(m.weighted_complex(i), levels, 0, orders))
        return out

    def _levels_at(self, tau, orders):
        """_levels(tau, orders), those at 0 and the last kept (shared: do not change them)."""
        if tau == 0.0 and self._start is not None and len(self._start) >= orders:
            return self._start
        if tau == self._levels_tau and len(self._levels_last) >= orders:
            return self._levels_last
        levels = self._levels(tau, orders)
        if tau == 0.0:
            self._start = levels
        self._levels_tau, self._levels_last = tau, levels
        return levels

    def _levels(self, tau, orders):
        """[eta, eta', ..., eta^(orders - 1)] of the kept modes at tau (see derivatives)."""
        m = self.modes
        lams = m.lam
        eta = self.eta0 if tau == 0.0 else self.modal(tau)
        levels = [eta]
        d = _rates(lams, eta, self.steady)  # lam eta + beta, beta = -lam steady
        if self.secular:
            for i, k in enumerate(self.secular):
                d[k] += self.beta[i]
        s = c = 0.0  # the harmonic's sin and cos (forced only)
        if self.forced:
            s, c = self.load(tau)
            d = _plus_scaled(d, self.gamma, s)
        levels.append(d)
        for j in range(2, orders):  # d/dtau of gamma sin: gamma Omega cos, -gamma Omega^2 sin, ...
            d = _rates(lams, d, None)
            if self.forced:
                term = self.om ** (j - 1) * (c, -s, -c, s)[(j - 2) % 4]
                d = _plus_scaled(d, self.gamma, term)
            levels.append(d)
        return levels

    def load(self, tau):
        """(sin, cos) of Omega tau + psi (0, 0 unforced)."""
        if not self.forced:
            return 0.0, 0.0
        a = self.om * tau + self.psi
        return math.sin(a), math.cos(a)

    def bounds(self, T, orders=5, rows=None, vectors=None, weighted=None, first=0):
        """Per component of z: bounds of |z_c - rest_c| and of |d^j z_c / dtau^j|, j = 1..orders-1,
        over 0 <= tau <= T (Re lam <= 0 makes |exp(lam tau)| <= 1); only those of the orders
        first..orders-1 if `first` is given.  Only the components `rows`
        (indices), if given; or of the linear functions c . z whose modal rows (c V) are `vectors`,
        or whose rows weight_k |(c V)_k| are `weighted` (Modes.weighted, weighted_difference).  (The
        compiled build calls it in C when the motion is typed: pass these by position.)"""
        m = self.modes
        cached = self._columns  # the per-mode table of the last T, to the highest order asked
        if cached is not None and cached[0] == T and len(cached[1]) >= orders:
            columns = cached[1]
        else:
            columns = self._columns_over(T, max(orders, _BOUND_ORDERS))
            self._columns = (T, columns)
        if weighted is None and vectors is None:  # the components' rows (weight |V|, kept with the modes)
            weighted = [m.weighted(i) for i in (range(2 * m.n) if rows is None else rows)]
        elif weighted is None:  # (weight |V|) first, as the sum always did
            weighted = [[w * abs(v) for w, v in zip(m.weight, vrow)] for vrow in vectors]
        return [[_dot_real(scaled, columns[j]) for j in range(first, orders)] for scaled in weighted]

    def _columns_over(self, T, orders):
        """Per order j < orders, per kept mode: the bound of |eta_k^(j)| (j = 0: of its swing about
        the constant part) over [0, T]."""
        m = self.modes
        lams = m.lam
        count = len(lams)
        powers = m.powers(orders)  # per mode |lam|^j
        columns = [[0.0] * count for j in range(orders)]  # per order, by mode
        for k in range(count):
            pk = powers[k]
            size = abs(self.coef[k])
            for j in range(orders):
                p = pk[j]
                columns[j][k] = size * p
            if self.forced:
                _forced_bounds(columns, k, lams[k], self.gp[k], self.gm[k], self.om, pk, T, orders)
        for i, k in enumerate(self.secular):  # eta^(j) = lam^(j-1) exp(lam tau) (lam eta0 + beta), j >= 1
            lam, a = lams[k], abs(lams[k])
            slope = abs(lam * self.eta0[k] + self.beta[i])
            free = [abs(self.eta0[k]) + T * slope] + [slope * a ** (j - 1) for j in range(1, orders)]
            for j in range(orders):
                columns[j][k] = free[j] + columns[j][k] - abs(self.coef[k]) * a ** j
        if m.growth_rate:  # growing modes: |exp(lam tau)| <= exp(Re lam T) on [0, T]
            for k in range(count):
                lam = lams[k]
                if lam.real > 1e-9 * m.fastest:
                    grow = math.exp(lam.real * T)
                    for j in range(orders):
                        columns[j][k] = columns[j][k] * grow
        return columns

    def rest(self, rows=None, vectors=None):
        """Per component of z: the constant part (the equilibrium under the held load b); only
        the components `rows`, or the functions whose modal rows are `vectors`, if given."""
        m = self.modes
        if vectors is None:
            vectors = m.V if rows is None else [m.V[i] for i in rows]
        return [_weighted_real(m.weight, vrow, self.steady) for vrow in vectors]


def _spread(s, lam, tau, es, el):
    """(exp(s tau) - exp(lam tau)) / (s - lam), given es = exp(s tau), el = exp(lam tau)."""
    w = (s - lam) * tau
    if abs(w) > _SERIES:
        return _quot(es - el, s - lam)
    return tau * el * phi1(w)


def _forced_bounds(columns, k, lam, gp, gm, om, pk, T, orders):
    """Add to mode k's entries of `columns` (per order j < orders) the bounds of its forced parts
    g+- E(+-i Omega) and their derivatives over [0, T]: the lesser of the secular bound and the
    steady one (pk: |lam|^j)."""
    a = abs(lam)
    gap_p = abs(1j * om - lam)
    gap_m = abs(-1j * om - lam)
    ga_p = abs(gp)
    ga_m = abs(gm)
    p_p = ga_p * T  # the secular bounds of the forced parts, then of their derivatives
    p_m = ga_m * T
    w = 1.0  # om^j
    for j in range(orders):
        if j:
            w = om ** j
        q = pk[j]
        steady = ga_p * (w + q) / gap_p if gap_p > 0.0 else _INF
        add_p = steady if steady < p_p else p_p  # min(p_p, steady)
        steady = ga_m * (w + q) / gap_m if gap_m > 0.0 else _INF
        add_m = steady if steady < p_m else p_m
        column = columns[j]
        column[k] = (column[k] + add_p) + add_m
        p_p = a * p_p + ga_p * w
        p_m = a * p_m + ga_m * w


def _free(lams, eta0, shift, tau):
    """The unforced modal coordinates exp(lam tau) eta0 - shift (exp(lam tau) - 1) at tau, per mode
    (shift: Motion.steady)
    (exp(lam tau) and its expm1 as exp_pair has them, written out: the hot loop)."""
    out = [0j] * len(lams)
    for k in range(len(lams)):
        z = lams[k] * tau
        a = z.real
        b = z.imag
        if a * a + b * b > 0.25:
            el = _exp(z)
            em = el - 1.0
        else:
            ea = _libm.expm1(a)
            h = _libm.sin(0.5 * b)
            omc = 2.0 * h * h  # 1 - cos(b)
            em = _cx.parts(ea - ea * omc - omc, (1.0 + ea) * 2.0 * h * _libm.cos(0.5 * b))
            el = em + 1.0
        e0 = eta0[k]
        c = shift[k]
        out[k] = el * e0 - c * em
    return out


def _plus_scaled(d, gamma, s):
    """[d_k + gamma_k s] (complex d, gamma; real s, multiplied as the complex (s, 0.0))."""
    out = [0j] * len(d)
    for k in range(len(d)):
        x = d[k]
        g = gamma[k]
        out[k] = x + g * s
    return out


def _rates(lams, eta, shift):
    """lam_k eta_k - shift_k lam_k per mode (lam_k eta_k if shift is None; shift: Motion.steady): the
    next derivative's modal coordinates of the free motion."""
    out = [0j] * len(lams)
    for k in range(len(lams)):
        lam = lams[k]
        e = eta[k]
        if shift is None:
            out[k] = lam * e
        else:
            c = shift[k]
            out[k] = lam * e - c * lam
    return out


def _weighted_real(weight, row, eta):
    """sum_k weight_k Re(row_k eta_k), added left to right from 0 (a component of z from its modes)."""
    return _cl.weighted_real(weight, row, eta)


def _real_dot(row, eta):
    """sum_k Re(row_k eta_k), added left to right from 0."""
    return _cl.real_dot(row, eta)


def _real_dots(row, levels, lo, hi):
    """[_real_dot(row, levels[j]) for lo <= j < hi]: the same sums, each left to right from 0."""
    return _cl.real_dots(row, levels, lo, hi)


def _dot_real(a, b):
    """sum_k a_k b_k of floats, added left to right from 0."""
    return _cl.dot(a, b)


def _total(a):
    """sum_k a_k of floats, added left to right from 0 (sum() before CPython 3.12 compensated it)."""
    s = 0.0
    for k in range(len(a)):
        x = a[k]
        s += x
    return s


def _dot3(a, b, c):
    """sum_k (a_k b_k) c_k of floats, added left to right from 0."""
    s = 0.0
    for k in range(len(a)):
        x, y, z = a[k], b[k], c[k]
        s += x * y * z
    return s


def _dot_change(a, x1, x0):
    """sum_k a_k (x1_k - x0_k) of floats, added left to right from 0."""
    s = 0.0
    for k in range(len(a)):
        x, y, z = a[k], x1[k], x0[k]
        s += x * (y - z)
    return s


def _matrix_sum(A, x, B, v, n):
    """sum over i, then j < n of A_ij x_j (+ B_ij v_j when B is given), added left to right from 0."""
    s = 0.0
    for i in range(n):
        a = A[i]
        if B is None:
            for j in range(n):
                p, q = a[j], x[j]
                s += p * q
        else:
            b = B[i]
            for j in range(n):
                p, q, r, w = a[j], x[j], b[j], v[j]
                s += p * q + r * w
    return s


def _dot(w, x, offset, n):
    """sum_i w[offset + i] x[i], i < n (complex w, real x), added left to right from 0."""
    return _cl.complex_dot(w, x, offset, n)


def _quot(a, b):
    """a / b for complex a and b (b != 0), as CPython divides them (Smith's method: the larger part of
    b divides first), written out so that the compiled build divides alike, operation by operation."""
    ar, ai, br, bi = a.real, a.imag, b.real, b.imag
    if abs(br) >= abs(bi):
        ratio = bi / br
        denom = br + bi * ratio
        return _cx.parts((ar + ai * ratio) / denom, (ai - ar * ratio) / denom)
    ratio = br / bi
    denom = br * ratio + bi
    return _cx.parts((ar * ratio + ai) / denom, (ai * ratio - ar) / denom)
