"""Newton impact law between the primary (mass M, velocity v) and the particle (m = mu M, u).

Momentum M v + m u is conserved and u+ - v+ = -e (u - v):

    v+ = ((1 - mu e) v + mu (1 + e) u) / (1 + mu)
    u+ = ((1 + e) v + (mu - e) u) / (1 + mu)

The paper names the particle with index 1; with mu = m/M the law conserves
momentum only when v is the primary, as here.  Energy lost:
dE = 0.5 M mu / (1 + mu) (1 - e^2) (u - v)^2.
"""


def collide(v, u, mu, e):
    """Velocities (v+, u+) of primary and particle after an impact."""
    q = 1.0 + mu
    w = u - v  # relative velocity before
    # centre-of-mass form: exact momentum to rounding, restitution to rounding
    vc = (v + mu * u) / q
    return vc + mu * e * w / q, vc - e * w / q


def impact_loss(M, mu, e, v, u):
    """Energy [J] lost in an impact with pre-impact velocities v (primary), u (particle)."""
    w = u - v
    return 0.5 * M * mu / (1.0 + mu) * (1.0 - e * e) * w * w
