"""One step of Hairer's DOP853 (explicit Runge-Kutta, order 8) and its dense output as a power-basis polynomial.

Uses the coefficients of Hairer's DOP853 as tabulated in scipy.integrate._ivp.dop853_coefficients (BSD),
copied here as plain floats; the step, the error norm and the dense output follow scipy's `DOP853`
(scipy/integrate/_ivp/rk.py), so they agree with it to rounding.  Plain Python + math, no numpy.

Conventions: a state `y` is a sequence of floats, `rhs(t, y)` returns a sequence of the same length
(it is called with lists), and vectors returned here are lists.  One step goes

    y_new, f_new, err, K = dop853_step(rhs, t, y, f, h, rtol, atol)   # 12 rhs calls (f = rhs(t, y) given)
    if err <= 1:                                                        # accepted
        coeffs = dop853_dense(rhs, t, y, h, K, y_new)                   # 3 more rhs calls

and `coeffs[i] = (c0, ..., c7)` is component i as a polynomial in theta = (t' - t) / h, 0 <= theta <= 1:
y_i(t + theta h) ~ sum_k c_k theta**k, with c0 = y[i] exactly, c1 = h f[i] and sum_k c_k = y_new[i] to rounding.
"""
import math

# Nodes c_s of stages 0..15 (12 step stages, stage 12 = the new point, 13..15 for the dense output).
_C = (0.0, 0.05260015195876773, 0.0789002279381516, 0.1183503419072274, 0.2816496580927726, 0.3333333333333333,
      0.25, 0.3076923076923077, 0.6512820512820513, 0.6, 0.8571428571428571, 1.0, 1.0, 0.1, 0.2, 0.7777777777777778)

# Nonzero a_sj of stage s, in the order of the stage derivatives K_j listed on the right.  Row 12 holds the
# weights b_j of y_new.
_A = (
    (),
    (0.05260015195876773,),  # 1: K0
    (0.0197250569845379, 0.0591751709536137),  # 2: K0, K1
    (0.02958758547680685, 0.08876275643042054),  # 3: K0, K2
    (0.2413651341592667, -0.8845494793282861, 0.924834003261792),  # 4: K0, K2, K3
    (0.037037037037037035, 0.17082860872947386, 0.12546768756682242),  # 5: K0, K3, K4
    (0.037109375, 0.17025221101954405, 0.06021653898045596, -0.017578125),  # 6: K0, K3, K4, K5
    (0.03709200011850479, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402,
     0.008273789163814023),  # 7: K0, K3, K4, K5, K6
    (0.6241109587160757, -3.3608926294469414, -0.868219346841726, 27.59209969944671, 20.154067550477894,
     -43.48988418106996),  # 8: K0, K3, K4, K5, K6, K7
    (0.47766253643826434, -2.4881146199716677, -0.590290826836843, 21.230051448181193, 15.279233632882423,
     -33.28821096898486, -0.020331201708508627),  # 9: K0, K3, K4, K5, K6, K7, K8
    (-0.9371424300859873, 5.186372428844064, 1.0914373489967295, -8.149787010746927, -18.52006565999696,
     22.739487099350505, 2.4936055526796523, -3.0467644718982196),  # 10: K0, K3, K4, K5, K6, K7, K8, K9
    (2.273310147516538, -10.53449546673725, -2.0008720582248625, -17.9589318631188, 27.94888452941996,
     -2.8589982771350235, -8.87285693353063, 12.360567175794303,
     0.6433927460157636),  # 11: K0, K3, K4, K5, K6, K7, K8, K9, K10
    (0.054293734116568765, 4.450312892752409, 1.8915178993145003, -5.801203960010585, 0.3111643669578199,
     -0.1521609496625161, 0.20136540080403034, 0.04471061572777259),  # 12: K0, K5, K6, K7, K8, K9, K10, K11
    (0.056167502283047954, 0.25350021021662483, -0.2462390374708025, -0.12419142326381637, 0.15329179827876568,
     0.00820105229563469, 0.007567897660545699, -0.008298),  # 13: K0, K6, K7, K8, K9, K10, K11, K12
    (0.03183464816350214, 0.028300909672366776, 0.053541988307438566, -0.05492374857139099,
     -0.00010834732869724932, 0.0003825710908356584, -0.00034046500868740456,
     0.1413124436746325),  # 14: K0, K5, K6, K7, K10, K11, K12, K13
    (-0.42889630158379194, -4.697621415361164, 7.683421196062599, 4.06898981839711, 0.3567271874552811,
     -0.0013990241651590145, 2.9475147891527724, -9.15095847217987),  # 15: K0, K5, K6, K7, K8, K12, K13, K14
)

# Error estimators (5th and 3rd order), on K0, K5, K6, K7, K8, K9, K10, K11.
_E5 = (0.01312004499419488, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864, -0.35032884874997366,
       0.3341791187130175, 0.08192320648511571, -0.022355307863886294)
_E3 = (-0.18980075407240762, 4.450312892752409, 1.8915178993145003, -5.801203960010585, -0.4226823213237919,
       -0.1521609496625161, 0.20136540080403034, 0.02265179219836082)

# Dense output: F3..F6 = h * D.K, on K0, K5, K6, ..., K15.
_D = (
    (-8.428938276109013, 0.5667149535193777, -3.0689499459498917, 2.38466765651207, 2.117034582445028,
     -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331, 18.148505520854727,
     -9.194632392478356, -4.436036387594894),
    (10.427508642579134, 242.28349177525817, 165.20045171727028, -374.5467547226902, -22.113666853125306,
     7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845, -31.139403219565178,
     -9.35292435884448, 35.81684148639408),
    (19.985053242002433, -387.0373087493518, -189.17813819516758, 527.8081592054236, -11.57390253995963,
     6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508, -60.19669523126412,
     84.32040550667716, 11.99229113618279),
    (-25.69393346270375, -154.18974869023643, -231.5293791760455, 357.6391179106141, 93.40532418362432,
     -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114, 96.32455395918828,
     -39.17726167561544, -149.72683625798564),
)


def dop853_step(rhs, t, y, f, h, rtol, atol):
    """One DOP853 step of y' = rhs(t, y) from (t, y), with f = rhs(t, y), to t + h (h > 0).

    Returns (y_new, f_new, err, K): y_new the 8th-order solution at t + h, f_new = rhs(t + h, y_new),
    err the scaled error norm exactly as scipy's DOP853 computes it (RMS over components of the combined
    5th/3rd-order estimate, scale = atol + rtol * max(|y|, |y_new|); rtol, atol scalars), err <= 1 meaning
    the step is accepted, and K = (K0, ..., K12) the stage derivatives (K0 = f, K12 = f_new) that
    `dop853_dense` needs.  Calls rhs 12 times.
    """
    C = _C
    k0 = f
    a0, = _A[1]
    k1 = rhs(t + C[1] * h, [yi + h * (a0 * x0) for yi, x0 in zip(y, k0)])
    a0, a1 = _A[2]
    k2 = rhs(t + C[2] * h, [yi + h * (a0 * x0 + a1 * x1) for yi, x0, x1 in zip(y, k0, k1)])
    a0, a2 = _A[3]
    k3 = rhs(t + C[3] * h, [yi + h * (a0 * x0 + a2 * x2) for yi, x0, x2 in zip(y, k0, k2)])
    a0, a2, a3 = _A[4]
    k4 = rhs(t + C[4] * h, [yi + h * (a0 * x0 + a2 * x2 + a3 * x3) for yi, x0, x2, x3 in zip(y, k0, k2, k3)])
    a0, a3, a4 = _A[5]
    k5 = rhs(t + C[5] * h, [yi + h * (a0 * x0 + a3 * x3 + a4 * x4) for yi, x0, x3, x4 in zip(y, k0, k3, k4)])
    a0, a3, a4, a5 = _A[6]
    k6 = rhs(t + C[6] * h, [yi + h * (a0 * x0 + a3 * x3 + a4 * x4 + a5 * x5)
                            for yi, x0, x3, x4, x5 in zip(y, k0, k3, k4, k5)])
    a0, a3, a4, a5, a6 = _A[7]
    k7 = rhs(t + C[7] * h, [yi + h * (a0 * x0 + a3 * x3 + a4 * x4 + a5 * x5 + a6 * x6)
                            for yi, x0, x3, x4, x5, x6 in zip(y, k0, k3, k4, k5, k6)])
    a0, a3, a4, a5, a6, a7 = _A[8]
    k8 = rhs(t + C[8] * h, [yi + h * (a0 * x0 + a3 * x3 + a4 * x4 + a5 * x5 + a6 * x6 + a7 * x7)
                            for yi, x0, x3, x4, x5, x6, x7 in zip(y, k0, k3, k4, k5, k6, k7)])
    a0, a3, a4, a5, a6, a7, a8 = _A[9]
    k9 = rhs(t + C[9] * h, [yi + h * (a0 * x0 + a3 * x3 + a4 * x4 + a5 * x5 + a6 * x6 + a7 * x7 + a8 * x8)
                            for yi, x0, x3, x4, x5, x6, x7, x8 in zip(y, k0, k3, k4, k5, k6, k7, k8)])
    a0, a3, a4, a5, a6, a7, a8, a9 = _A[10]
    k10 = rhs(t + C[10] * h, [yi + h * (a0 * x0 + a3 * x3 + a4 * x4 + a5 * x5 + a6 * x6 + a7 * x7 + a8 * x8
                                        + a9 * x9)
                              for yi, x0, x3, x4, x5, x6, x7, x8, x9 in zip(y, k0, k3, k4, k5, k6, k7, k8, k9)])
    a0, a3, a4, a5, a6, a7, a8, a9, a10 = _A[11]
    k11 = rhs(t + C[11] * h, [yi + h * (a0 * x0 + a3 * x3 + a4 * x4 + a5 * x5 + a6 * x6 + a7 * x7 + a8 * x8
                                        + a9 * x9 + a10 * x10)
                              for yi, x0, x3, x4, x5, x6, x7, x8, x9, x10
                              in zip(y, k0, k3, k4, k5, k6, k7, k8, k9, k10)])
    a0, a5, a6, a7, a8, a9, a10, a11 = _A[12]
    y_new = [yi + h * (a0 * x0 + a5 * x5 + a6 * x6 + a7 * x7 + a8 * x8 + a9 * x9 + a10 * x10 + a11 * x11)
             for yi, x0, x5, x6, x7, x8, x9, x10, x11 in zip(y, k0, k5, k6, k7, k8, k9, k10, k11)]
    f_new = rhs(t + h, y_new)

    e0, e5, e6, e7, e8, e9, e10, e11 = _E5
    d0, d5, d6, d7, d8, d9, d10, d11 = _E3
    n5 = n3 = 0.0
    for yi, zi, x0, x5, x6, x7, x8, x9, x10, x11 in zip(y, y_new, k0, k5, k6, k7, k8, k9, k10, k11):
        scale = atol + rtol * max(abs(yi), abs(zi))
        r5 = (e0 * x0 + e5 * x5 + e6 * x6 + e7 * x7 + e8 * x8 + e9 * x9 + e10 * x10 + e11 * x11) / scale
        r3 = (d0 * x0 + d5 * x5 + d6 * x6 + d7 * x7 + d8 * x8 + d9 * x9 + d10 * x10 + d11 * x11) / scale
        n5 += r5 * r5
        n3 += r3 * r3
    err = 0.0 if n5 == 0.0 and n3 == 0.0 else abs(h) * n5 / math.sqrt((n5 + 0.01 * n3) * len(y))
    return y_new, f_new, err, (k0, k1, k2, k3, k4, k5, k6, k7, k8, k9, k10, k11, f_new)


def dop853_dense(rhs, t, y, h, K, y_new):
    """Dense output of the step (t, y) -> (t + h, y_new) whose stage derivatives K `dop853_step` returned.

    Returns coeffs, coeffs[i] = (c0, ..., c7): component i at t + theta h is sum_k c_k theta**k for
    0 <= theta <= 1, the 7th-order interpolant of scipy's DOP853 (its nested form expanded once, by hand,
    into the power basis).  c0 = y[i] exactly, c1 = h K0[i], sum_k c_k = y_new[i] to rounding.
    Calls rhs 3 times.
    """
    C = _C
    k0, _, _, _, _, k5, k6, k7, k8, k9, k10, k11, k12 = K
    a0, a6, a7, a8, a9, a10, a11, a12 = _A[13]
    k13 = rhs(t + C[13] * h, [yi + h * (a0 * x0 + a6 * x6 + a7 * x7 + a8 * x8 + a9 * x9 + a10 * x10 + a11 * x11
                                        + a12 * x12)
                              for yi, x0, x6, x7, x8, x9, x10, x11, x12 in zip(y, k0, k6, k7, k8, k9, k10, k11, k12)])
    a0, a5, a6, a7, a10, a11, a12, a13 = _A[14]
    k14 = rhs(t + C[14] * h, [yi + h * (a0 * x0 + a5 * x5 + a6 * x6 + a7 * x7 + a10 * x10 + a11 * x11 + a12 * x12
                                        + a13 * x13)
                              for yi, x0, x5, x6, x7, x10, x11, x12, x13
                              in zip(y, k0, k5, k6, k7, k10, k11, k12, k13)])
    a0, a5, a6, a7, a8, a12, a13, a14 = _A[15]
    k15 = rhs(t + C[15] * h, [yi + h * (a0 * x0 + a5 * x5 + a6 * x6 + a7 * x7 + a8 * x8 + a12 * x12 + a13 * x13
                                        + a14 * x14)
                              for yi, x0, x5, x6, x7, x8, x12, x13, x14
                              in zip(y, k0, k5, k6, k7, k8, k12, k13, k14)])

    # scipy: y(theta) = y + theta (F0 + (1-theta) (F1 + theta (F2 + (1-theta) (F3 + theta (F4 + (1-theta)
    # (F5 + theta F6)))))) with F0 = dy, F1 = h f - dy, F2 = 2 dy - h (f + f_new), F3..F6 = h D.K;
    # expanded: c1 = h f, c2 = 3 dy - 2 h f - h f_new + F3, c3 = -2 dy + h f + h f_new - 2 F3 + F4 + F5,
    # c4 = F3 - 2 F4 - 3 F5 + F6, c5 = F4 + 3 F5 - 3 F6, c6 = 3 F6 - F5, c7 = -F6.
    p, q, r, s = _D
    coeffs = []
    for yi, zi, x0, x5, x6, x7, x8, x9, x10, x11, x12, x13, x14, x15 in zip(
            y, y_new, k0, k5, k6, k7, k8, k9, k10, k11, k12, k13, k14, k15):
        F3 = h * (p[0] * x0 + p[1] * x5 + p[2] * x6 + p[3] * x7 + p[4] * x8 + p[5] * x9 + p[6] * x10
                  + p[7] * x11 + p[8] * x12 + p[9] * x13 + p[10] * x14 + p[11] * x15)
        F4 = h * (q[0] * x0 + q[1] * x5 + q[2] * x6 + q[3] * x7 + q[4] * x8 + q[5] * x9 + q[6] * x10
                  + q[7] * x11 + q[8] * x12 + q[9] * x13 + q[10] * x14 + q[11] * x15)
        F5 = h * (r[0] * x0 + r[1] * x5 + r[2] * x6 + r[3] * x7 + r[4] * x8 + r[5] * x9 + r[6] * x10
                  + r[7] * x11 + r[8] * x12 + r[9] * x13 + r[10] * x14 + r[11] * x15)
        F6 = h * (s[0] * x0 + s[1] * x5 + s[2] * x6 + s[3] * x7 + s[4] * x8 + s[5] * x9 + s[6] * x10
                  + s[7] * x11 + s[8] * x12 + s[9] * x13 + s[10] * x14 + s[11] * x15)
        dy = zi - yi
        hf0 = h * x0
        hf1 = h * x12
        coeffs.append((yi, hf0, 3.0 * dy - 2.0 * hf0 - hf1 + F3, hf0 + hf1 - 2.0 * dy - 2.0 * F3 + F4 + F5,
                       F3 - 2.0 * F4 - 3.0 * F5 + F6, F4 + 3.0 * F5 - 3.0 * F6, 3.0 * F6 - F5, -F6))
    return coeffs


def poly_eval(c, theta):
    """sum_k c[k] theta**k (Horner)."""
    p = 0.0
    for ck in reversed(c):
        p = p * theta + ck
    return p


def poly_derivs(c, theta, h):
    """(p, dp/dt, d2p/dt2, d3p/dt3) at theta, for p = sum_k c[k] theta**k and t = t0 + theta h."""
    p = d1 = d2 = d3 = 0.0
    for ck in reversed(c):
        d3 = d3 * theta + d2
        d2 = d2 * theta + d1
        d1 = d1 * theta + p
        p = p * theta + ck
    return p, d1 / h, 2.0 * d2 / (h * h), 6.0 * d3 / (h * h * h)


def poly_deriv_bound(c, j, h):
    """A bound of |d^j p / dt^j| over theta in [0, 1], for p = sum_k c[k] theta**k and t = t0 + theta h:
    sum_{k >= j} |c[k]| k! / (k - j)! / h**j."""
    return sum(abs(c[k]) * math.perm(k, j) for k in range(j, len(c))) / h ** j
