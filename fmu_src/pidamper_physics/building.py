"""A linear shear building: lumped floor masses, storey stiffnesses, classical modal damping.

Floors k = 1..N carry masses m_k [kg]; storey k (stiffness k_k [N/m]) joins floor k - 1 to
floor k, floor 0 being the ground.  With x the floor displacements relative to the ground [m]:

    M x'' + C x' + K x = -M 1 a_g + f,     M = diag(m_k),
    K = tridiagonal: K[k][k] = k_k + k_(k+1), K[k][k+1] = K[k+1][k] = -k_(k+1),

with k_k less the geometric stiffness P_k / h_k of P-Delta where it is on (P_k the gravity load
the storey carries, h_k its height; the strain energy then includes the P-Delta potential), and
the damping `damping` chooses (DAMPING_MODELS):

    MODAL (0):            C = M Phi diag(2 zeta w_r) Phi^T M   (every elastic mode at the ratio zeta,
                          the matrix kept while storeys yield),
    RAYLEIGH_INITIAL (1): C = a0 M + a1 K                      (Rayleigh, the elastic K, kept),
    RAYLEIGH_TANGENT (2): C = a0 M + a1 K_t                    (Rayleigh, the tangent K_t of the
                          storeys' current regime, P-Delta included, as OpenSees's betaK),

a0 = 2 zeta w_1 w_j / (w_1 + w_j), a1 = 2 zeta / (w_1 + w_j): the ratio zeta at the first mode and
the j-th, j = min(3, N) (mode r then has a0 / (2 w_r) + a1 w_r / 2); Phi the undamped mode shapes
normalised to Phi^T M Phi = I, w_r the natural frequencies (ascending).  Drift of storey k: x_k - x_(k-1); base shear: k_1 x_1 + the first storey's share of
the damping force, (C x')_ground = -(sum of the rows of C) x' (the dashpots' reaction on the ground).
Plain Python (math): this ships inside the FMU.
"""
import math

from .eigen import jacobi_eigh
from .modal import _dot3, _matrix_sum

MODAL, RAYLEIGH_INITIAL, RAYLEIGH_TANGENT = 0, 1, 2
#: the damping models' names (ShearBuilding's `damping`), by number
DAMPING_MODELS = ("modal", "Rayleigh, initial stiffness", "Rayleigh, tangent stiffness")


class ShearBuilding:
    """Matrices and modes of an N-storey shear building (see the module doc).

    masses [kg], stiffnesses [N/m], heights [m]: sequences of N positive numbers (floor / storey 1
    first; heights default to 3 m); zeta [1]: the damping ratio of every mode (MODAL) or of the
    first and the min(3, N)-th (Rayleigh), 0 <= zeta < 1; damping: MODAL, RAYLEIGH_INITIAL or
    RAYLEIGH_TANGENT (Params checks them all).  zetas: each elastic mode's damping ratio."""

    def __init__(self, masses, stiffnesses, zeta=0.0, heights=None, geometric=None, damping=MODAL):
        n = len(masses)
        if n < 1 or len(stiffnesses) != n:
            raise ValueError("a shear building needs a mass and a stiffness per storey")
        self.n = n
        self.masses = [float(m) for m in masses]
        self.stiffnesses = [float(k) for k in stiffnesses]
        self.zeta = float(zeta)
        self.heights = [3.0] * n if heights is None else [float(h) for h in heights]
        # P-Delta: the geometric stiffness P_k / h_k [N/m] of each storey, taken off its stiffness
        self.geometric = [0.0] * n if geometric is None else [float(g) for g in geometric]
        self.net = [k - g for k, g in zip(self.stiffnesses, self.geometric)]  # k_k - P_k / h_k [N/m]
        ks = self.net + [0.0]
        self.K = [[0.0] * n for _ in range(n)]
        for i in range(n):
            self.K[i][i] = ks[i] + ks[i + 1]
            if i + 1 < n:
                self.K[i][i + 1] = self.K[i + 1][i] = -ks[i + 1]
        # M^-1/2 K M^-1/2 is symmetric: its eigenvectors psi give Phi = M^-1/2 psi
        root = [math.sqrt(m) for m in self.masses]
        sym = [[self.K[i][j] / (root[i] * root[j]) for j in range(n)] for i in range(n)]
        lams, psi = jacobi_eigh(sym)
        self.omegas = [math.sqrt(max(lam, 0.0)) for lam in lams]
        self.shapes = [[psi[i][r] / root[i] for r in range(n)] for i in range(n)]  # Phi[i][r]
        phi = self.shapes
        self.damping = int(damping)
        self.rayleigh = None  # (a0 [1/s], a1 [s]) of a Rayleigh model
        if self.damping == MODAL:
            self.zetas = [self.zeta] * n
            # C = M Phi diag(2 zeta w) Phi^T M
            self.C = [[self.masses[i] * self.masses[j] * sum(phi[i][r] * 2.0 * self.zeta * self.omegas[r] * phi[j][r]
                                                              for r in range(n)) for j in range(n)] for i in range(n)]
        else:
            w1, wj = self.omegas[0], self.omegas[min(3, n) - 1]
            a0, a1 = 2.0 * self.zeta * w1 * wj / (w1 + wj), 2.0 * self.zeta / (w1 + wj)
            self.rayleigh = (a0, a1)
            self.zetas = [a0 / (2.0 * w) + a1 * w / 2.0 for w in self.omegas]
            self.C = self._rayleigh(self.K)

    def _rayleigh(self, K):
        """a0 M + a1 K [N s/m] of the stiffness matrix K [N/m] (nested lists)."""
        a0, a1 = self.rayleigh
        n = self.n
        return [[(a0 * self.masses[i] if i == j else 0.0) + a1 * K[i][j] for j in range(n)] for i in range(n)]

    def damping_matrix(self, K):
        """C [N s/m] in a regime of the storeys whose stiffness matrix is K [N/m]: a0 M + a1 K under
        RAYLEIGH_TANGENT, the model's fixed C otherwise."""
        return self._rayleigh(K) if self.damping == RAYLEIGH_TANGENT else self.C

    def tangent_damping(self):
        """True when C follows the storeys' tangent stiffness (RAYLEIGH_TANGENT)."""
        return self.damping == RAYLEIGH_TANGENT

    @property
    def w_1(self):
        """First natural frequency [rad/s]."""
        return self.omegas[0]

    @property
    def spread(self):
        """w_n / w_1: the fastest natural frequency over the first."""
        return max(self.omegas) / min(self.omegas)

    @property
    def total_mass(self):
        return sum(self.masses)

    def drifts(self, x):
        """Storey drifts x_k - x_(k-1) [m] of floor displacements x (relative to the ground)."""
        return [x[k] - (x[k - 1] if k else 0.0) for k in range(self.n)]

    def drift_ratios(self, x):
        """Storey drift ratios (x_k - x_(k-1)) / h_k [1] of floor displacements x."""
        return [(x[k] - (x[k - 1] if k else 0.0)) / self.heights[k] for k in range(self.n)]

    def base_shear(self, x, v):
        """Force of the building on the ground [N] (storey 1's spring and the dashpots' ground
        reaction): the sum of K x + C x' over all floors."""
        return _matrix_sum(self.K, x, self.C, v, self.n)

    def energy(self, x, v):
        """Kinetic plus strain energy [J] of the floors (relative motion)."""
        d = self.drifts(x)
        return 0.5 * _dot3(self.masses, v, v) + 0.5 * _dot3(self.net, d, d)
