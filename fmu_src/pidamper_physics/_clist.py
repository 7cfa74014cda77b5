"""Sums over lists of floats and complex numbers, each added left to right from zero (the modes'
projections and components, the systems' matrix rows).  The plain build runs these bodies;
`_clist.pxd` gives the compiled build C bodies of the same sums, which read the lists' items in
place (no index checks per item, no boxing) and do the same operations in the same order, so both
builds give the same bits.  Plain Python, never compiled itself: a module that cimports the .pxd gets
its inline bodies, the plain build these.

Complex products are CPython's (3.11-3.13): a real operand multiplies as the complex (x, 0.0)."""


def dot(a, b):
    """sum_k a_k b_k of floats, k < len(a)."""
    s = 0.0
    for k in range(len(a)):
        x = a[k]
        y = b[k]
        s += x * y
    return s


def weighted_real(weight, row, eta):
    """sum_k weight_k Re(row_k eta_k), k < len(eta): a component of z from its modes."""
    s = 0.0
    for k in range(len(eta)):
        w = weight[k]
        v = row[k]
        e = eta[k]
        s += w * (v * e).real
    return s


def real_dot(row, eta):
    """sum_k Re(row_k eta_k), k < len(row)."""
    s = 0.0
    for k in range(len(row)):
        v = row[k]
        e = eta[k]
        s += (v * e).real
    return s


def real_dots(row, levels, lo, hi):
    """[real_dot(row, levels[j]) for lo <= j < hi], the row read once for up to five of them."""
    count = hi - lo
    if count > 5 or count < 1:
        return [real_dot(row, levels[j]) for j in range(lo, hi)]
    l0 = levels[lo]
    l1 = levels[lo + 1] if count > 1 else l0
    l2 = levels[lo + 2] if count > 2 else l0
    l3 = levels[lo + 3] if count > 3 else l0
    l4 = levels[lo + 4] if count > 4 else l0
    s0 = s1 = s2 = s3 = s4 = 0.0
    for k in range(len(row)):
        v = row[k]
        s0 += (v * l0[k]).real
        if count > 1:
            s1 += (v * l1[k]).real
            if count > 2:
                s2 += (v * l2[k]).real
                if count > 3:
                    s3 += (v * l3[k]).real
                    if count > 4:
                        s4 += (v * l4[k]).real
    return [s0, s1, s2, s3, s4][:count]


def complex_dot(w, x, offset, n):
    """sum_i w[offset + i] x[i], i < n, of complex w and real x (from 0j)."""
    s = 0j
    for i in range(n):
        wi = w[offset + i]
        xi = x[i]
        s += wi * xi
    return s
