"""The closed form's per-mode kernels (modal.py) are CPython's complex arithmetic operation by
operation, so that the compiled build (Cython, C complex doubles) and the plain one agree to the
bit: division written out as CPython divides (Smith's method), sums left to right."""
import math
import random

import pytest

from pidamper_physics import modal


def _bits(z):
    return z.real.hex(), z.imag.hex()


def _number(rng):
    if rng.random() < 0.05:
        return rng.choice([0.0, -0.0, 1.0, -2.0, 0.5])
    return rng.choice([-1.0, 1.0]) * rng.random() * 10.0 ** rng.uniform(-40.0, 40.0)


def test_quot_divides_as_cpython_does():
    rng = random.Random(7)
    checked = 0
    for _ in range(100_000):
        a, b = complex(_number(rng), _number(rng)), complex(_number(rng), _number(rng))
        if b == 0:
            continue
        assert _bits(modal._quot(a, b)) == _bits(a / b), (a, b)
        checked += 1
    assert checked > 90_000


def test_quot_by_zero_raises_as_division_does():
    with pytest.raises(ZeroDivisionError):
        modal._quot(1.0 + 1j, 0j)


def test_sums_run_left_to_right_from_zero():
    """0.1 + 0.2 + 0.3 in that order is 0.6000000000000001; compensated (math.fsum) it is 0.6."""
    assert modal._dot_real([1.0, 1.0, 1.0], [0.1, 0.2, 0.3]) == (0.1 + 0.2) + 0.3 != math.fsum([0.1, 0.2, 0.3])
    assert modal._real_dot([1 + 0j] * 3, [0.1 + 0j, 0.2 + 0j, 0.3 + 0j]) == (0.1 + 0.2) + 0.3
    assert modal._weighted_real([2.0] * 3, [1 + 1j] * 3, [0.1 + 0j, 0.2 + 0j, 0.3 + 0j]) == (0.2 + 0.4) + 0.6
    assert modal._dot([1j, 1j, 1j], [0.1, 0.2, 0.3], 0, 3) == complex(0.0, (0.1 + 0.2) + 0.3)
    assert modal._total([0.1, 0.2, 0.3]) == (0.1 + 0.2) + 0.3
    assert modal._dot3([1.0] * 3, [1.0] * 3, [0.1, 0.2, 0.3]) == (0.1 + 0.2) + 0.3
    assert modal._dot_change([1.0] * 3, [0.2, 0.4, 0.6], [0.1, 0.2, 0.3]) == ((0.2 - 0.1) + (0.4 - 0.2)) + (0.6 - 0.3)
    assert modal._matrix_sum([[1.0, 1.0], [1.0, 0.0]], [0.1, 0.2], None, None, 2) == (0.1 + 0.2) + 0.1
    assert modal._matrix_sum([[1.0]], [0.1], [[1.0]], [0.2], 1) == 0.1 + 0.2


def test_exp_is_cmath_exp_to_the_bit():
    """_exp writes cmath's formula out (libm's exp, cos, sin: in C in the compiled build); it must
    give cmath.exp's bits for every z, signed zeros included, and raise where cmath raises."""
    import cmath

    rng = random.Random(11)
    for _ in range(200_000):
        re = rng.choice([rng.uniform(-60.0, 5.0), rng.uniform(-1.0, 1.0) * 10.0 ** rng.uniform(-300.0, 2.8),
                         rng.choice([0.0, -0.0, 700.0, -700.0, 709.0, -745.0])])
        im = rng.choice([rng.uniform(-100.0, 100.0), rng.uniform(-1.0, 1.0) * 10.0 ** rng.uniform(-300.0, 3.0),
                         0.0, -0.0])
        z = complex(re, im)
        assert _bits(modal._exp(z)) == _bits(cmath.exp(z)), z
    for z in (complex(math.inf, 0.0), complex(-math.inf, 1.0), complex(0.0, math.inf), complex(math.nan, 1.0)):
        try:
            expected = cmath.exp(z)
        except ValueError:
            with pytest.raises(ValueError):
                modal._exp(z)
            continue
        assert _bits(modal._exp(z)) == _bits(expected), z
    with pytest.raises(OverflowError):
        modal._exp(complex(800.0, 1.0))


def test_exp_pair_near_zero_builds_its_parts_as_complex_does():
    """The small-z branch builds exp(z) - 1 from its parts (_ccomplex.parts: a C complex in the
    compiled build); it must be complex(re, im) of the same parts, signed zeros included."""
    rng = random.Random(5)
    for z in [complex(-0.0, -0.0), complex(0.0, -0.0), complex(-0.0, 0.0)] + [
            complex(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)) for _ in range(20_000)]:
        if abs(z) > 0.5:
            continue
        a, b = z.real, z.imag
        ea, h = math.expm1(a), math.sin(0.5 * b)
        omc = 2.0 * h * h
        expected = complex(ea - ea * omc - omc, (1.0 + ea) * 2.0 * h * math.cos(0.5 * b))
        e, em = modal.exp_pair(z)
        assert _bits(em) == _bits(expected) and _bits(e) == _bits(expected + 1.0), z
    assert math.copysign(1.0, modal.exp_pair(complex(0.0, -0.0))[1].imag) == -1.0


def test_a_system_is_solved_once_per_process():
    """solved_modes keeps the Modes of each (K, C) by its matrices' bits: the same matrices give the
    same (read-only) object, a signed zero is another system, the oldest go first past the cap, and
    a system without modes raises every time."""
    K, C = [[2.0, -1.0], [-1.0, 1.0]], [[0.1, 0.0], [0.0, 0.1]]
    first = modal.solved_modes(K, C)
    assert modal.solved_modes([row[:] for row in K], [row[:] for row in C]) is first
    other = modal.solved_modes(K, [[0.1, -0.0], [0.0, 0.1]])
    assert other is not first and [z for z in other.lam] == [z for z in first.lam]
    fresh = modal.Modes(K, C)
    assert [_bits(z) for z in first.lam] == [_bits(z) for z in fresh.lam] and first.W == fresh.W
    kept = modal.SOLVED_KEPT
    try:
        modal.SOLVED_KEPT = len(modal._SOLVED)  # full: the next new system drops the oldest
        oldest = next(iter(modal._SOLVED))
        modal.solved_modes([[3.0]], [[0.25]])
        assert oldest not in modal._SOLVED and len(modal._SOLVED) == modal.SOLVED_KEPT
    finally:
        modal.SOLVED_KEPT = kept
    for _ in range(2):
        with pytest.raises(modal.ModesError):
            modal.solved_modes([[1.0, 0.0], [0.0, 1.0]], [[0.0, 1e-30], [1e-30, 0.0]])


def _special(rng):
    return rng.choice([_number(rng), _number(rng), 0.0, -0.0, math.inf, -math.inf, math.nan, 3, -7])


def _reference_sums(rng, n):
    """Random lists (floats with signed zeros, infinities, NaN and a few ints; complex) and the sums
    as a plain loop of Python's own operators forms them."""
    a = [_special(rng) for _ in range(n)]
    b = [_special(rng) for _ in range(n)]
    row = [complex(_special(rng), _special(rng)) for _ in range(n)]
    eta = [complex(_special(rng), _special(rng)) for _ in range(n)]
    dot = weighted = real = 0.0
    cdot = 0j
    for k in range(n):
        dot += a[k] * b[k]
        weighted += a[k] * (row[k] * eta[k]).real
        real += (row[k] * eta[k]).real
        cdot += row[k] * b[k]
    return a, b, row, eta, (dot, weighted, real, cdot)


def _same(x, y):
    x, y = complex(x), complex(y)
    return all((math.isnan(p) and math.isnan(q)) or p.hex() == q.hex()
               for p, q in ((x.real, y.real), (x.imag, y.imag)))


def test_list_sums_are_pythons_loops_to_the_bit():
    """modal's list sums (in the compiled build _clist.pxd's C bodies, which read the items in place)
    give what a loop of Python's operators gives, item types, signed zeros, infinities and NaN
    included; and the plain bodies (_clist.py) the same."""
    from pidamper_physics import _clist

    rng = random.Random(23)
    for _ in range(20_000):
        n = rng.randint(0, 7)
        a, b, row, eta, (dot, weighted, real, cdot) = _reference_sums(rng, n)
        for impl_dot, impl_weighted, impl_real, impl_cdot in (
                (modal._dot_real, modal._weighted_real, modal._real_dot, modal._dot),
                (_clist.dot, _clist.weighted_real, _clist.real_dot, _clist.complex_dot)):
            assert _same(impl_dot(a, b), dot), (a, b)
            assert _same(impl_weighted(a, row, eta), weighted), (a, row, eta)
            assert _same(impl_real(row, eta), real), (row, eta)
            assert _same(impl_cdot(row, b, 0, n), cdot), (row, b)
        levels = [eta, row, [complex(x) for x in b], eta, row, eta]
        for lo in range(0, 3):
            for hi in range(lo + 1, lo + 7):
                expected = [modal._real_dot(row, levels[j]) for j in range(lo, min(hi, len(levels)))]
                if hi > len(levels):
                    continue
                assert all(map(_same, modal._real_dots(row, levels, lo, hi), expected))
                assert all(map(_same, _clist.real_dots(row, levels, lo, hi), expected))


@pytest.mark.parametrize("call", [
    lambda: modal._dot_real([1.0, 2.0], [1.0]),
    lambda: modal._weighted_real([1.0], [1j, 1j], [1j, 1j]),
    lambda: modal._real_dot([1j, 1j], [1j]),
    lambda: modal._dot([1j], [1.0, 2.0], 0, 2),
    lambda: modal._dot([1j, 1j], [1.0, 2.0], 1, 2),
])
def test_list_sums_refuse_a_short_list_as_indexing_does(call):
    with pytest.raises(IndexError):
        call()


def test_list_sums_refuse_what_is_no_number():
    with pytest.raises(TypeError):
        modal._dot_real([1.0, "2"], [1.0, 1.0])
    with pytest.raises(TypeError):
        modal._real_dot([1j, None], [1j, 1j])
