"""FEMA P-695's pushover of a building of deteriorating storeys (assessment.deteriorating_pushover):
one storey against the closed form of its backbone with P-Delta, three storeys against OpenSees's
displacement-controlled pushover of `IMKBilin` zeroLength storeys."""
import math

import numpy as np
import pytest

from pidamper.assessment.deteriorating_pushover import pushover
from pidamper.assessment.p695 import first_mode
from pidamper_physics.refusals import ParameterError

G = 9.81


def law(fy, dp=0.02, dpc=0.3, du=0.5, fmax=1.3, fres=0.3, lam=1.0, ke=8e7):
    """An IMKBilin law of a storey [N/m, m, N], the same both ways."""
    side = [dp, dpc, du, fy, fmax, fres]
    return [ke] + side + side + [lam, lam, lam, 1.0, 1.0, 1.0, 1.0, 1.0]


def test_one_storey_follows_its_backbone_less_p_delta():
    """Capping at Fcap - (P/h) ucap, then down the post-capping line less P-Delta to 80 % of it;
    delta_y,eff = V_max / (Ke - P/h) (one storey: C0 = 1, T from Ke - P/h)."""
    m, h, fy, ke, dp, dpc, fmax = 2e5, 3.0, 6e5, 8e7, 0.02, 0.3, 1.3
    po = pushover([m], [law(fy)], [h], p_delta=True, g=G)
    geo = G * m / h
    ucap, fcap = fy / ke + dp, fmax * fy
    v_max = fcap - geo * ucap
    kpc = fcap / dpc
    delta_u = (fcap + kpc * ucap - 0.8 * v_max) / (kpc + geo)
    assert po.critical == 1 and "20 % of the peak" in po.limit
    assert po.v_max == pytest.approx(v_max, rel=1e-13)
    assert po.delta_u == pytest.approx(delta_u, rel=1e-13)
    assert po.delta_y_eff == pytest.approx(v_max / (ke - geo), rel=1e-12)
    assert po.mu_t == pytest.approx(delta_u * (ke - geo) / v_max, rel=1e-12)
    corners = [(0.0, 0.0), (fy / ke, fy - geo * fy / ke), (ucap, v_max), (delta_u, 0.8 * v_max)]
    assert np.allclose(np.c_[po.roof, po.base_shear], corners, rtol=1e-13, atol=0.0)


def opensees(masses, laws, heights, po, steps):
    from pidamper.running import isolated

    m = np.asarray(masses)
    geo = G * np.cumsum(m[::-1])[::-1] / np.asarray(heights)
    phi, _ = first_mode(m, np.array([law_[0] for law_ in laws]) - geo)
    roof, shear = isolated.call("pidamper.oracles.opensees:imk_pushover_curve", list(masses), laws, list(heights),
                                True, (m * phi).tolist(), 1.2 * po.delta_u, steps, G, hard_exit=True)
    return np.array(roof), np.array(shear)


@pytest.mark.parametrize("laws, peak", [
    # storey 1 softens at once: P-Delta outweighs its pre-capping stiffness (the peak at its yield)
    ([law(6e5, dp=0.0648, dpc=0.4206, du=0.6, fmax=1.1, fres=0.4, lam=3.306), law(5.5e5, dp=0.0648, dpc=0.4206, du=0.6,
      fmax=1.1, fres=0.4, lam=3.306), law(4e5, dp=0.0648, dpc=0.4206, du=0.6, fmax=1.1, fres=0.4, lam=3.306)], "yield"),
    # storeys 2 and 3 yield first, storey 1 caps: the others unload along stiffnesses their reversal deteriorated
    ([law(6e5), law(5.2e5), law(3.2e5)], "capping"),
])
def test_three_storeys_are_opensees_pushover(laws, peak):
    """Base shear along OpenSees's displacement-controlled curve (Newton, roof control) against
    ours at its roof displacements, to 80 % of the peak: within 1e-4 of the peak at 4000 steps
    and 1e-5 at 16000 (the other storeys' reversals are taken at OpenSees's samples), and
    OpenSees's largest sample within 1e-4 below our peak."""
    masses, heights = [1e5] * 3, [3.0] * 3
    po = pushover(masses, laws, heights, p_delta=True, g=G)
    assert po.critical == 1 and "20 % of the peak" in po.limit
    geo1 = G * 3e5 / 3.0
    side = laws[0][1:7]
    top = (side[3] / laws[0][0] + side[0]) if peak == "capping" else side[3] / laws[0][0]
    force = side[3] * side[4] if peak == "capping" else side[3]
    assert po.v_max == pytest.approx(force - geo1 * top, rel=1e-13)  # storey 1 carries all of V
    for steps, limit in ((4000, 1e-4), (16000, 1e-5)):
        roof, shear = opensees(masses, laws, heights, po, steps)
        assert roof[-1] >= po.delta_u, f"OpenSees stopped at roof {roof[-1]} (steps {steps})"
        keep = roof <= po.delta_u
        error = np.abs(shear[keep] - np.interp(roof[keep], po.roof, po.base_shear)).max() / po.v_max
        assert error <= limit, (steps, error)
        assert -1e-4 <= shear.max() / po.v_max - 1.0 <= 1e-12


def test_a_storey_that_cannot_stand_is_refused():
    with pytest.raises(ParameterError, match=r"storey\[1\]\.Ke .*P/h"):
        pushover([1e7], [law(6e5, ke=1e7)], [3.0], p_delta=True, g=G)
    assert math.isfinite(pushover([1e7], [law(6e5, ke=1e8)], [3.0], p_delta=True, g=G).mu_t)


def test_the_assessment_s_pushover_of_a_deteriorating_building_is_this_one():
    """`pidamper assess` takes FEMA P-695's pushover of a building with storey_law = 1 from
    of_params(Params): the deteriorating one, to 20 % strength loss (one storey: the closed form)."""
    from pidamper.assessment.deteriorating_pushover import of_params
    from pidamper_physics import Params

    m, h, fy, ke, dp, dpc, fmax = 2e5, 3.0, 6e5, 8e7, 0.02, 0.3, 1.3
    params = Params(storeys=1, floor_m=[m], storey_k=[ke], storey_h=[h], storey_Fy=[fy], p_delta=1, g=G, mu=0.0,
                    storey_law=1, storey_imk=[{"dp_pos": dp, "dp_neg": dp, "dpc_pos": dpc, "dpc_neg": dpc,
                                               "FmaxFy_pos": fmax, "FmaxFy_neg": fmax}])
    push = of_params(params)
    geo = G * m / h
    ucap = fy / ke + dp
    assert push.v_max == pytest.approx(fmax * fy - geo * ucap, rel=1e-13)
    assert "20 % of the peak" in push.limit and push.weight == pytest.approx(G * m)
    kpc = fmax * fy / dpc
    assert push.delta_u == pytest.approx((fmax * fy + kpc * ucap - 0.8 * push.v_max) / (kpc + geo), rel=1e-13)
