"""Impact law: momentum and restitution exact, loss formula, the index trap."""
import random

import pytest

from pidamper_physics import collide, impact_loss


@pytest.mark.parametrize("seed", range(5))
def test_momentum_restitution_and_loss(seed):
    rng = random.Random(seed)
    for _ in range(2000):
        v, u = rng.uniform(-3, 3), rng.uniform(-3, 3)
        mu, e, M = rng.uniform(0, 2), rng.uniform(0, 1), rng.uniform(0.1, 10)
        vp, up = collide(v, u, mu, e)
        scale = abs(v) + abs(u)
        assert abs((vp + mu * up) - (v + mu * u)) <= 4e-16 * (1 + mu) * scale  # momentum / M
        assert abs((up - vp) + e * (u - v)) <= 8e-16 * scale  # Newton restitution
        kinetic = lambda a, b: 0.5 * M * (a * a + mu * b * b)
        assert kinetic(v, u) - kinetic(vp, up) == pytest.approx(impact_loss(M, mu, e, v, u),
                                                                abs=1e-14 * M * scale * scale)


def test_paper_printed_law_with_primary_as_v():
    v, u, mu, e = 0.7, -0.2, 0.1, 0.2
    vp, up = collide(v, u, mu, e)
    assert vp == pytest.approx(((1 - mu * e) * v + mu * (1 + e) * u) / (1 + mu), rel=1e-15)
    assert up == pytest.approx(((1 + e) * v + (mu - e) * u) / (1 + mu), rel=1e-15)
    # the swapped mapping (particle as v) breaks momentum by M (1 + e)(1 - mu)(v - u)
    sp, su = ((1 - mu * e) * u + mu * (1 + e) * v) / (1 + mu), ((1 + e) * u + (mu - e) * v) / (1 + mu)
    swapped_change = (sp + mu * su) - (v + mu * u)
    assert abs(swapped_change) > 0.5 * abs(v - u)
