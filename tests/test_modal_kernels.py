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
