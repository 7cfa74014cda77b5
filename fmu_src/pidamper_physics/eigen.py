"""The eigen-solvers and linear solvers of the physics, plain Python (math, cmath): `jacobi_eigh` for
a symmetric matrix (the undamped modes of a shear building: cyclic Jacobi, accurate to rounding,
real orthonormal vectors), `pencil_modes` for the modes of q'' + C q' + K q (any n, complex modes)
with its LU (`lu_factor`, `lu_solve`, `inverse_rows`), and the 2-DOF closed forms modal.Modes keeps
for n <= 2 (`quartic_roots`, `gauss_solve`: measured more accurate there, see their docstrings).

Conventions: matrices are nested lists, `a[i][j]` = row i, column j; K and C are real n x n and
need not be symmetric (M^-1 K, M^-1 C of a lumped system, C non-proportional in general).  The
state matrix A = [[0, I], [-K, -C]] (2n x 2n, acting on z = (q, q')) has the eigenvalues of the
quadratic pencil P(lam) = lam^2 I + lam C + K, and the eigenvector (phi, lam phi) for
P(lam) phi = 0.  Steps (`pencil_modes`):

  1. eigenvalues of A: balancing by powers of 2 (exact), Householder reduction to Hessenberg
     form, then complex single-shift QR (Wilkinson shifts, deflation of negligible subdiagonal
     entries, an exceptional shift every 10 iterations without deflation, an iteration cap);
  2. classification: |Im lam| <= SNAP x (largest |lam|) is snapped to real (complex arithmetic
     leaves a real eigenvalue a rounding-sized imaginary part); the rest must split into as many
     Im > 0 as Im < 0 values, matched into conjugate pairs (each pair averaged);
  3. eigenvectors by inverse iteration on P(lam) (n x n LU with partial pivoting; a real lam
     gives a real phi), normalised to |phi|_2 = 1.

Failures raise EigenError.  Runs inside the FMU.
"""
import cmath
import math

EPS = 2.0 ** -52
#: relative |Im lam| below which an eigenvalue is real: a true pair this narrow would be closer
#: than the 1e-7 at which modes count as coinciding, so snapping it cannot hide a distinct pair
SNAP = 2.5e-8
#: relative distance within which a computed Im < 0 value must mirror an Im > 0 one
PAIR = 1e-6
MAX_ITERATIONS = 30  # QR iterations per eigenvalue, on average, before EigenError


class EigenError(ArithmeticError):
    """The eigen-solver failed (QR did not converge, or the spectrum is not that of a real matrix)."""


def jacobi_eigh(a, sweeps=100):
    """Eigenvalues (ascending) and orthonormal eigenvectors (as columns) of the symmetric matrix
    a (nested lists), by cyclic Jacobi rotations: accurate to rounding for small n."""
    n = len(a)
    a = [list(map(float, row)) for row in a]
    vec = [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]
    for _ in range(sweeps):
        off = sum(a[i][j] * a[i][j] for i in range(n) for j in range(i + 1, n))
        if off <= 1e-36 * sum(a[i][i] * a[i][i] for i in range(n)):
            break
        for p in range(n - 1):
            for q in range(p + 1, n):
                apq = a[p][q]
                if apq == 0.0:
                    continue
                theta = (a[q][q] - a[p][p]) / (2.0 * apq)
                t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(n):  # columns p, q
                    akp, akq = a[k][p], a[k][q]
                    a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
                for k in range(n):  # rows p, q
                    apk, aqk = a[p][k], a[q][k]
                    a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
                for k in range(n):
                    vkp, vkq = vec[k][p], vec[k][q]
                    vec[k][p], vec[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    order = sorted(range(n), key=lambda i: a[i][i])
    return [a[i][i] for i in order], [[vec[k][i] for i in order] for k in range(n)]


def balance(a):
    """Copy of the square matrix a scaled by D^-1 a D (D diagonal, powers of 2: exact, same
    eigenvalues) so that each row and its column have like 1-norms (Parlett and Reinsch)."""
    n = len(a)
    a = [[float(x) for x in row] for row in a]
    done = False
    while not done:
        done = True
        for i in range(n):
            c = sum(abs(a[j][i]) for j in range(n) if j != i)
            r = sum(abs(a[i][j]) for j in range(n) if j != i)
            if c == 0.0 or r == 0.0:
                continue
            total = c + r
            f = 1.0
            while c < 0.5 * r:
                c, r, f = 2.0 * c, 0.5 * r, 2.0 * f
            while c >= 2.0 * r:
                c, r, f = 0.5 * c, 2.0 * r, 0.5 * f
            if c + r < 0.95 * total:
                done = False
                for j in range(n):  # row i by 1/f, column i by f
                    a[i][j] /= f
                    a[j][i] *= f
    return a


def hessenberg(a):
    """Upper Hessenberg matrix similar to the real square matrix a (Householder reflections)."""
    n = len(a)
    a = [list(row) for row in a]
    for k in range(n - 2):
        x = [a[i][k] for i in range(k + 1, n)]
        tail = math.fsum(t * t for t in x[1:])
        if tail == 0.0:
            continue
        alpha = math.sqrt(x[0] * x[0] + tail)
        if x[0] > 0.0:
            alpha = -alpha  # v0 = x0 - alpha without cancellation
        v = x
        v[0] -= alpha
        beta = 2.0 / (v[0] * v[0] + tail)  # H = I - beta v v^T
        rows = a[k + 1:]
        acc = [0.0] * (n - k)  # v^T a[k+1:, k:]
        for vi, row in zip(v, rows):
            seg = row[k:]
            acc = [p + vi * t for p, t in zip(acc, seg)]
        for vi, row in zip(v, rows):
            f = beta * vi
            row[k:] = [t - f * p for t, p in zip(row[k:], acc)]
        for row in a:  # a[:, k+1:] (I - beta v v^T)
            seg = row[k + 1:]
            f = beta * sum(t * vi for t, vi in zip(seg, v))
            if f != 0.0:
                row[k + 1:] = [t - f * vi for t, vi in zip(seg, v)]
        a[k + 1][k] = alpha
        for i in range(k + 2, n):
            a[i][k] = 0.0
    return a


def _wilkinson(a, b, c, d):
    """The eigenvalue of [[a, b], [c, d]] nearer d."""
    t = 0.5 * (a - d)
    disc = cmath.sqrt(t * t + b * c)
    if (t.conjugate() * disc).real < 0.0:
        disc = -disc
    den = t + disc
    return d if den == 0 else d - b * c / den


def hessenberg_eigenvalues(h):
    """Eigenvalues (complex, in order of deflation) of the upper Hessenberg matrix h."""
    n = len(h)
    h = [[complex(x) for x in row] for row in h]
    norm = max((sum(abs(x) for x in row) for row in h), default=0.0)
    out = []
    hi, its, total = n - 1, 0, 0
    while hi >= 0:
        lo = hi
        while lo > 0:  # the active block is lo..hi
            ref = abs(h[lo - 1][lo - 1]) + abs(h[lo][lo]) or norm
            if abs(h[lo][lo - 1]) <= EPS * ref:
                h[lo][lo - 1] = 0j
                break
            lo -= 1
        if lo == hi:
            out.append(h[hi][hi])
            hi, its = hi - 1, 0
            continue
        its += 1
        total += 1
        if total > MAX_ITERATIONS * n:
            raise EigenError(f"QR iteration did not converge ({total} iterations, {hi + 1} eigenvalues left)")
        if its % 10 == 0:  # exceptional shift: break a cycle the Wilkinson shift may fall into
            sub = abs(h[hi][hi - 1]) + (abs(h[hi - 1][hi - 2]) if hi - 2 >= lo else 0.0)
            sigma = h[hi][hi] + 0.75 * sub * cmath.exp(1j * its)
        else:
            sigma = _wilkinson(h[hi - 1][hi - 1], h[hi - 1][hi], h[hi][hi - 1], h[hi][hi])
        # one QR step on the active block: h - sigma I = Q R, h <- R Q + sigma I
        for i in range(lo, hi + 1):
            h[i][i] -= sigma
        rots = []
        for k in range(lo, hi):
            x, y = h[k][k], h[k + 1][k]
            r = math.hypot(abs(x), abs(y))
            c, s = (x / r, y / r) if r > 0.0 else (1.0, 0.0)
            cc, sc = c.conjugate(), s.conjugate()
            rk, rk1 = h[k], h[k + 1]  # rows k, k+1 by [[c*, s*], [-s, c]]
            for j in range(k, hi + 1):
                u, w = rk[j], rk1[j]
                rk[j], rk1[j] = cc * u + sc * w, c * w - s * u
            rots.append((c, s, cc, sc))
        for k, (c, s, cc, sc) in zip(range(lo, hi), rots):  # columns k, k+1 by the adjoint
            for i in range(lo, min(k + 2, hi) + 1):
                row = h[i]
                u, w = row[k], row[k + 1]
                row[k], row[k + 1] = c * u + s * w, cc * w - sc * u
        for i in range(lo, hi + 1):
            h[i][i] += sigma
    return out


def eigenvalues(a):
    """Eigenvalues (complex) of the real square matrix a."""
    return hessenberg_eigenvalues(hessenberg(balance(a)))


def lu_factor(a):
    """LU with partial pivoting of the square matrix a: (rows of L\\U, pivot order). An exactly
    zero pivot is replaced by EPS x the largest entry (a singular a: inverse iteration)."""
    n = len(a)
    m = [list(row) for row in a]
    tiny = EPS * max(abs(x) for row in a for x in row) or EPS
    perm = list(range(n))
    for col in range(n):
        piv = max(range(col, n), key=lambda r: abs(m[r][col]))
        m[col], m[piv] = m[piv], m[col]
        perm[col], perm[piv] = perm[piv], perm[col]
        top = m[col]
        if top[col] == 0:
            top[col] = tiny
        inv = 1.0 / top[col]
        for r in range(col + 1, n):
            row = m[r]
            f = row[col] * inv
            row[col] = f
            if f != 0:
                for c in range(col + 1, n):
                    row[c] -= f * top[c]
    return m, perm


def lu_solve(factors, b):
    """x with a x = b, given factors = lu_factor(a)."""
    m, perm = factors
    n = len(m)
    y = [b[p] for p in perm]
    for r in range(1, n):
        row = m[r]
        y[r] -= sum(row[c] * y[c] for c in range(r))
    for r in range(n - 1, -1, -1):
        row = m[r]
        y[r] = (y[r] - sum(row[c] * y[c] for c in range(r + 1, n))) / row[r]
    return y


def quartic_roots(c3, c2, c1, c0, guesses):
    """Roots of l^4 + c3 l^3 + c2 l^2 + c1 l + c0 (Durand-Kerner, then Newton polish): the 2-DOF
    modes in closed form.  Kept beside pencil_modes (QR, then inverse iteration), which through
    the ill-conditioned case of gauss_solve (coupled level, g = 1e-15) gives x(1 s) to 2e-8 (its
    eigenvalues with the explicit 2-DOF shapes) or 1e-7 (its vectors too) instead of 2e-10."""
    def p(x):
        return (((x + c3) * x + c2) * x + c1) * x + c0

    def dp(x):
        return ((4.0 * x + 3.0 * c3) * x + 2.0 * c2) * x + c1

    roots = list(guesses)
    for _ in range(500):
        moved = 0.0
        for i, r in enumerate(roots):
            den = 1.0 + 0j
            for j, s in enumerate(roots):
                if j != i:
                    den *= r - s
            step = p(r) / den
            roots[i] = r - step
            moved = max(moved, abs(step) / max(abs(r), 1e-300))
        if moved < 1e-15:
            break
    for i, r in enumerate(roots):  # Newton: quadratic convergence to full precision
        for _ in range(3):
            d = dp(r)
            if d == 0:
                break
            r = r - p(r) / d
        roots[i] = r
    return roots


def gauss_solve(a, b):
    """x with a x = b (complex Gauss elimination with partial pivoting, the right-hand side eliminated
    with a; a is n x n).  Kept beside lu_factor/lu_solve for the 2-DOF modes (modal.Modes, n <= 2):
    on the coupled level at g = 1e-15 it holds x(1 s) to 2e-10, where lu_factor/lu_solve of V by
    columns give 4e-8 and of V^T (inverse_rows) 4e-9 (tests/test_edges.py::
    test_small_g_under_a_force_is_exact; V is ill-conditioned there)."""
    n = len(a)
    m = [list(row) + [b[i]] for i, row in enumerate(a)]
    for col in range(n):
        piv = max(range(col, n), key=lambda r: abs(m[r][col]))
        m[col], m[piv] = m[piv], m[col]
        for r in range(col + 1, n):
            f = m[r][col] / m[col][col]
            for c in range(col, n + 1):
                m[r][c] -= f * m[col][c]
    x = [0j] * n
    for r in range(n - 1, -1, -1):
        x[r] = (m[r][n] - sum(m[r][c] * x[c] for c in range(r + 1, n))) / m[r][r]
    return x


def pencil_vector(K, C, lam, steps=3):
    """Unit phi with (lam^2 I + lam C + K) phi ~ 0, by inverse iteration (real if lam is real)."""
    n = len(K)
    l2 = lam * lam
    P = [[lam * C[i][j] + K[i][j] + (l2 if i == j else 0.0) for j in range(n)] for i in range(n)]
    factors = lu_factor(P)
    x = [1.0 + 0.5 * math.sin(1.7 * i + 0.3) for i in range(n)]  # no structure the modes share
    for _ in range(steps):
        x = lu_solve(factors, x)
        big = max(abs(t) for t in x)
        x = [t / big for t in x]
    norm = math.sqrt(sum(abs(t) ** 2 for t in x))
    return [t / norm for t in x]


def pencil_modes(K, C):
    """Eigenvalues and unit phi of q'' + C q' + K q: ([lam] * 2n, [phi] * 2n), each conjugate
    pair adjacent (Im > 0 first, exact conjugates), real eigenvalues with imaginary part 0 and real
    phi; ordered by |lam|.  Raises EigenError."""
    n = len(K)
    A = [[0.0] * n + [1.0 if j == i else 0.0 for j in range(n)] for i in range(n)] + \
        [[-x for x in K[i]] + [-x for x in C[i]] for i in range(n)]
    lams = eigenvalues(A)
    scale = max(abs(x) for x in lams)
    if not math.isfinite(scale):
        raise EigenError("the eigenvalues are not finite")
    real = [x.real for x in lams if abs(x.imag) <= SNAP * scale]
    upper = [x for x in lams if x.imag > SNAP * scale]
    lower = [x.conjugate() for x in lams if x.imag < -SNAP * scale]
    if len(upper) != len(lower):
        raise EigenError(f"{len(upper)} eigenvalues with Im > 0 but {len(lower)} with Im < 0")
    pairs = []
    for x in upper:
        k = min(range(len(lower)), key=lambda j: abs(lower[j] - x))
        y = lower.pop(k)
        if abs(y - x) > PAIR * scale:
            raise EigenError(f"eigenvalue {x:.6g} has no conjugate (nearest {y.conjugate():.6g})")
        pairs.append(0.5 * (x + y))
    out_lam, out_vec = [], []
    for x in sorted(real + pairs, key=abs):
        phi = pencil_vector(K, C, x)
        if isinstance(x, complex):
            out_lam += [x, x.conjugate()]
            out_vec += [phi, [t.conjugate() for t in phi]]
        else:
            out_lam.append(complex(x))
            out_vec.append([complex(t) for t in phi])
    return out_lam, out_vec


def inverse_rows(V, rows):
    """The given rows of V^-1 (square V): row k solves V^T y = e_k (one LU of V^T)."""
    n = len(V)
    factors = lu_factor([[V[i][j] for i in range(n)] for j in range(n)])
    return [lu_solve(factors, [1.0 if r == k else 0.0 for r in range(n)]) for k in rows]


#: eigenvalue of a^T a, relative to its largest, at or below which a direction is null: the
#: rounding floor of the product a^T a (a few ulps of its largest entry), where an exactly
#: singular a leaves its zero eigenvalues (seen: 1.2e-16 for a 4-storey mechanism of rank 2)
NULL_LEVEL = 1e-13


def null_space(a, r):
    """r orthonormal real vectors spanning the null space of the square matrix a (those of the r
    smallest eigenvalues of a^T a, by jacobi_eigh), or None if a has no null space of dimension r."""
    n = len(a)
    ata = [[sum(a[k][i] * a[k][j] for k in range(n)) for j in range(n)] for i in range(n)]
    lams, vec = jacobi_eigh(ata)
    top = max(abs(x) for x in lams) or 1.0
    if r > n or any(lams[k] > NULL_LEVEL * top for k in range(r)):
        return None
    return [[vec[i][k] for i in range(n)] for k in range(r)]
