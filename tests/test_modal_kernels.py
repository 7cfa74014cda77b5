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
