"""The impact law of every particle model (Damper's levels, DamperUnit): Newton's, restitution e.

Between the primary (mass M, velocity v) and the particle (m = mu M, u):

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



def relative(w, m, M_s, reduced, e, impulse_aware):
    """The same law in the unit's form (unit.py: particle m on a structure of mass M_s, reduced mass
    m M_s / (m + M_s), at approach velocity w = r' in the attachment's frame): (impulse J on the
    structure [N s], r' after [m/s], energy lost [J]).  Impulse-aware: the two-body law, r' -> -e w.
    Mean force: the attachment's velocity jump reaches the unit only through its next input, so
    r' -> w (m - e M_s) / (m + M_s); where that still approaches the stop (m > e M_s) the caller
    makes the impact plastic in the unit's frame (plastic_in_unit_frame)."""
    J = reduced * (1.0 + e) * w
    loss = 0.5 * reduced * (1.0 - e * e) * w * w
    if impulse_aware:
        return J, -e * w, loss
    return J, w * (m - e * M_s) / (m + M_s), loss


def plastic_in_unit_frame(w, m, M_s):
    """(J, r' after, loss) of the mean-force unit's plastic impact: J = m w, r' -> 0 (see relative)."""
    return m * w, 0.0, 0.5 * m * w * w * (M_s - m) / M_s
