"""A shear building calibrated to a frame's pushover (assessment.shear_calibration): on storey paths
drawn from known backbones (elastic, hardening to a capping point, a straight post-capping line),
with P-Delta taken off the shear as a frame's pushover reports it, the calibration gives back each
storey's stiffness, yield force, capping and post-capping exactly (to rounding)."""
import numpy as np
import pytest

from pidamper.assessment import shear_calibration as sc

H = np.array([5.0, 4.0, 4.0])
P = np.array([3.0e7, 2.0e7, 1.0e7])  # N: weight above each storey
#: per storey: Ke [N/m], Fy [N], hardening ratio, Fmax/Fy, dpc [m]
TRUE = [(2.0e8, 8.0e6, 0.03, 1.1, 0.5), (1.5e8, 6.5e6, 0.03, 1.1, 0.4), (1.0e8, 5.0e6, 0.03, 1.1, 0.4)]


def backbone(u, ke, fy, a, fmax_fy, dpc):
    uy = fy / ke
    uc = uy + (fmax_fy - 1.0) * fy / (a * ke)
    return np.where(u <= uy, ke * u, np.where(u <= uc, fy + a * ke * (u - uy), fmax_fy * fy * (1.0 - (u - uc) / dpc)))


def paths(steps=4000):
    """Storey 1 softens to half its peak; storey 2 yields and unloads; storey 3 stays elastic; every
    corner of the paths is a step (so that the trapezoids are exact)."""
    ke, fy, a, fr, dpc = TRUE[0]
    uc = fy / ke + (fr - 1.0) * fy / (a * ke)
    k2, f2, a2, r2, _ = TRUE[1]
    reach2 = f2 / k2 + (r2 - 1.0) * f2 / (a2 * k2) * 0.5
    corners = [fy / ke / (uc + 0.5 * dpc), uc / (uc + 0.5 * dpc), 0.6 * (f2 / k2) / reach2, 0.6, 0.7]
    t = np.unique(np.concatenate([np.linspace(0.0, 1.0, steps + 1)[1:], corners]))
    steps = t.size
    drift, shear = np.zeros((steps, 3)), np.zeros((steps, 3))
    drift[:, 0] = t * (uc + 0.5 * dpc)
    for k, top in ((1, 0.6), (2, 0.7)):
        ke, fy, a, fr, dpc = TRUE[k]
        reach = (fy / ke + (fr - 1.0) * fy / (a * ke) * 0.5) if k == 1 else 0.7 * fy / ke
        up = np.minimum(t / top, 1.0) * reach
        force = backbone(up, *TRUE[k])
        back = np.where(t > top, -(t - top) / (1 - top) * 0.3 * force[-1] / ke, 0.0)
        drift[:, k] = up + back
        shear[:, k] = force + ke * back
    shear[:, 0] = backbone(drift[:, 0], *TRUE[0])
    return shear - drift * (P / H)[None, :], drift


def test_each_storey_comes_back_from_its_path():
    shear, drift = paths()
    got = sc.calibrate([(shear, drift)], P, H)
    assert [s.basis for s in got] == ["softened", "yielded", "elastic"]
    for s, (ke, fy, a, fr, dpc) in zip(got, TRUE):
        assert s.ke == pytest.approx(ke, rel=1e-9)
    soft = got[0]
    ke, fy, a, fr, dpc = TRUE[0]
    assert soft.fy == pytest.approx(fy, rel=1e-9) and soft.fmax_fy == pytest.approx(fr, rel=1e-9)
    assert soft.dp == pytest.approx((fr - 1.0) * fy / (a * ke), rel=1e-9)
    assert soft.dpc == pytest.approx(dpc, rel=1e-9)
    ke, fy, a, fr, dpc = TRUE[1]  # the yielded storey: its own Fy; capping and post-capping as storey 1's drift ratios
    assert got[1].fy == pytest.approx(fy, rel=1e-9) and got[1].fmax_fy == pytest.approx(1.1, rel=1e-9)
    assert got[1].dpc == pytest.approx(TRUE[0][4] / H[0] * H[1], rel=1e-9)
    assert got[2].fy == pytest.approx(0.7 * TRUE[2][1], rel=1e-9)  # elastic: the largest force it showed


def test_a_pushover_with_no_softening_storey_is_refused():
    shear, drift = paths()
    with pytest.raises(ValueError, match="no storey softened"):
        sc.calibrate([(shear[:1000], drift[:1000])], P, H)


def test_a_storey_that_reaches_its_residual_plateau_gives_it_back():
    """A storey whose resistance falls along its post-capping line onto a plateau (0.8 Fy here, as a
    frame storey whose columns keep their strength while its beams' hinges deteriorate): the fitted
    falling branch gives back the line's slope and the plateau; without a plateau there is none."""
    ke, fy, a, fr, dpc = 1.0e8, 4.0e6, 0.03, 1.15, 0.2
    uc = fy / ke + (fr - 1.0) * fy / (a * ke)
    u = np.linspace(0.0, 3.0 * uc, 3001)[1:]
    r = np.maximum(backbone(u, ke, fy, a, fr, dpc), np.where(u > uc, 0.8 * fy, 0.0))
    u = np.unique(np.concatenate([u, [fy / ke, uc, uc + dpc * (1 - 0.8 / fr)]]))
    r = np.maximum(backbone(u, ke, fy, a, fr, dpc), np.where(u > uc, 0.8 * fy, 0.0))
    s = sc.storey(u, r)
    assert s.basis == "softened" and s.fy == pytest.approx(fy, rel=1e-9)
    assert s.dpc == pytest.approx(dpc, rel=1e-6) and s.fres_fy == pytest.approx(0.8, rel=1e-6)
    shear, drift = paths()
    assert np.isnan(sc.calibrate([(shear, drift)], P, H)[0].fres_fy)


def test_the_shipped_la9_study_is_its_frames_calibration_and_matches_the_frame():
    """studies/la9.toml's storeys are tools/la9_storeys.py's calibration of the OpenSees frame's
    pushovers (studies/la9/frame-pushover.json, to the 6 digits the tool writes), and that shear
    building has the frame's first period (after gravity, P-Delta) within 0.5 % and its peak base
    shear within 3 %."""
    import importlib.util
    import json
    import math
    import tomllib
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    spec = importlib.util.spec_from_file_location("la9_storeys", root / "tools" / "la9_storeys.py")
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    frame = json.loads((root / "studies" / "la9" / "frame-pushover.json").read_text())
    _, fields = tool.calibrated(frame)
    building = tomllib.loads((root / "studies" / "la9.toml").read_text())["building"]
    for name, values in fields.items():
        assert building[name] == pytest.approx(values, rel=5e-6), name
    p = tool.params(frame, fields)
    assert 2 * math.pi / p.building.w_1 == pytest.approx(frame["periods_after_gravity"][0], rel=5e-3)
    from pidamper.assessment import deteriorating_pushover
    push = deteriorating_pushover.pushover(list(frame["masses"]), p.imk, frame["storey_heights"], True, tool.G)
    assert push.v_max == pytest.approx(max(frame["steps"]["base_shear"]), rel=0.03)
