"""The deteriorating storey law (pidamper_physics.imk, OpenSees's IMKBilin exact in drift): its
backbone against the closed form, one cycle's deterioration computed by hand from the areas of the
hysteresis, OpenSees's IMKBilin material converging to it as its strain step falls, and its
refusals."""
import json
import math
import random

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from pidamper_physics.imk import (BACKBONE, ELASTIC, LOST, LOST_NEG, LOST_POS, PARAMETERS, RESIDUAL, IMKStorey,
                                  check_imk)
from pidamper_physics.refusals import ParameterError

#: normalised (Ke = Fy = 1: yield drift 1), capping at drift 4 and 1.2 Fy, zero force 10 beyond it,
#: residual 0.3 Fy, ultimate drift 15, reference energies 60 Fy (drift units), exponents 1
NORM = [1.0, 3.0, 10.0, 15.0, 1.0, 1.2, 0.3, 3.0, 10.0, 15.0, 1.0, 1.2, 0.3, 60.0, 60.0, 60.0, 1.0, 1.0, 1.0, 1.0, 1.0]
#: a storey [N/m, m, N] (8e7 N/m, 6e5 N, 3 m high), Lignos-Krawinkler (2011) ratios of a steel beam
#: hinge as a storey drift: capping at 2.4 % drift, residual 0.4 Fy from 0.34 m, ultimate 0.6 m
STOREY = [8e7, 0.0648, 0.4206, 0.60, 6e5, 1.1, 0.4, 0.0648, 0.4206, 0.60, 6e5, 1.1, 0.4,
          3.306, 3.306, 3.306, 1.0, 1.0, 1.0, 1.0, 1.0]
#: asymmetric sides, non-integer exponents, no residual on the positive side
ASYM = [1.0, 2.0, 8.0, 12.0, 1.2, 1.15, 0.0, 4.0, 12.0, 14.0, 0.9, 1.05, 0.25, 80.0, 60.0, 100.0, 1.3, 0.8, 1.1,
        1.15, 0.9]


def close(a, b, scale):
    return abs(a - b) <= 1e-12 * scale


def backbone_closed_form(p, s):
    """The initial backbone of side s (+1 / -1) at drift u = s x, x >= 0: elastic, pre-capping,
    post-capping, residual, and 0 past the ultimate drift; with its corners."""
    i = 1 if s > 0 else 7
    ke, (dp, dpc, du, fy, fmax, fres) = p[0], p[i:i + 6]
    uy, fcap = fy / ke, fmax * fy
    ucap = uy + dp
    kp, kpc = (fcap - fy) / dp, fcap / dpc
    ures = ucap + (fcap - fres * fy) / kpc

    def force(x):
        if x >= du:
            f = 0.0
        elif x <= uy:
            f = ke * x
        elif x <= ucap:
            f = fy + kp * (x - uy)
        elif x <= ures:
            f = fcap - kpc * (x - ucap)
        else:
            f = fres * fy
        return s * f

    corners = {"touch": uy, "kink": ucap, "ultimate": du}
    if ures < du:  # the residual plateau, if the post-capping line reaches it before the ultimate drift
        corners["residual"] = ures
    return force, corners


@pytest.mark.parametrize("params, side", [(STOREY, 1), (STOREY, -1), (ASYM, -1), (NORM, 1)])
def test_a_monotonic_push_follows_the_backbone_to_the_ultimate_drift(params, side):
    force, corners = backbone_closed_form(params, side)
    fy = params[4 if side > 0 else 10]
    du = corners["ultimate"]
    events = []
    storey = IMKStorey(params, events=events)
    for j in range(1, 401):
        x = 1.2 * du * j / 400
        f = storey.move(side * x)
        assert close(f, force(x), fy), (x, f, force(x))
    assert storey.failure == (LOST_POS if side > 0 else LOST_NEG)
    kinds = [kind for kind, _ in events]
    # no excursion, no reversal: a monotonic push deteriorates nothing
    assert "excursion" not in kinds and "reversal" not in kinds
    at = {kind: u for kind, u in events}
    names = {"touch": "touch", "residual": f"failure {RESIDUAL}", "ultimate": f"failure {storey.failure}"}
    assert (f"failure {RESIDUAL}" in at) == ("residual" in corners)
    for kind, name in names.items():
        if kind in corners:
            assert close(abs(at[name]), corners[kind], corners["ultimate"]), (kind, at[name], corners[kind])
    assert at[f"failure {BACKBONE}"] == at["touch"]


def test_one_cycle_deteriorates_as_the_hysteresis_areas_say():
    """Push to drift 2 (past yield), then back to -3: the unloading stiffness deteriorates at the
    reversal by the energy of the loop so far less the elastic energy, the negative backbone at the
    zero-force crossing by the energy of the excursion, and the reloading line meets that
    deteriorated backbone; each value from the areas of the loop, by hand."""
    lam, ke, fy, fcap, dp, kpc0, fres = 60.0, 1.0, 1.0, 1.2, 3.0, 0.12, 0.3
    kp = (fcap - fy) / dp
    events = []
    storey = IMKStorey(NORM, events=events)
    storey.move(2.0)
    f1 = fy + kp * (2.0 - fy / ke)
    e1 = 0.5 * fy * (fy / ke) + 0.5 * (fy + f1) * (2.0 - fy / ke)  # the elastic triangle, the plastic trapezoid
    assert close(storey.f, f1, 1.0) and close(storey.e_acc, e1, 1.0)
    storey.move(-3.0)
    # the reversal at 2: E_i = E_j = e1 - f1^2 / (2 Ke) (the elastic energy given back), beta_K = E_i / (E_ref - E_j)
    elastic = f1 * f1 / (2.0 * ke)
    beta_k = (e1 - elastic) / (lam * fy - (e1 - elastic))
    k1 = ke * (1.0 - beta_k)
    assert close(storey.k, k1, 1.0)
    # the zero-force crossing: the unloading line gives back f1^2 / (2 k1); that excursion's energy
    u_c = 2.0 - f1 / k1
    e_c = e1 - f1 * f1 / (2.0 * k1)
    beta_s = beta_c = e_c / (lam * fy - e_c)
    # the negative backbone after it (signed values): strength and slopes by beta_S, capping line by beta_C
    fy2, kp2 = -fy * (1.0 - beta_s), kp * (1.0 - beta_s)
    fcap_line = (-fcap - kpc0 * (fy / ke + dp)) * (1.0 - beta_c)  # the post-capping line's value at u = 0
    kpc2 = -kpc0 * (fy2 + fres) / (-fy + fres)  # -kpc0 (Fy - Fres) / (Fy0 - Fres), signed
    fy_line = fy2 - kp2 * fy2 / ke  # the pre-capping line's value at u = 0
    ucap2 = (fcap_line - fy_line) / (kp2 - kpc2)
    fcap2 = fy_line + kp2 * ucap2
    rotated = (fcap2 + fres) / (ucap2 - u_c + fres / k1)  # the pre-capping slope through (u where -fres is reached)
    kp2 = min(kp2, rotated) if rotated > 0.0 else kp2
    neg = storey.neg
    assert close(neg.fy, fy2, 1.0) and close(neg.ucap, ucap2, 10.0) and close(neg.fcap, fcap2, 1.0)
    assert close(neg.kp, kp2, 1.0) and close(neg.kpc, kpc2, 1.0)
    # the reloading line k1 (u - u_c) meets the pre-capping line fcap2 + kp2 (u - ucap2)
    u_t = (fcap2 - kp2 * ucap2 + k1 * u_c) / (k1 - kp2)
    f_t = k1 * (u_t - u_c)
    assert ucap2 < -3.0 < u_t < u_c
    f_end = fcap2 + kp2 * (-3.0 - ucap2)
    assert close(storey.f, f_end, 1.0)
    assert close(storey.e_acc, e_c + 0.5 * f_t * (u_t - u_c) + 0.5 * (f_t + f_end) * (-3.0 - u_t), 1.0)
    assert [kind for kind, _ in events] == ["touch", f"failure {BACKBONE}", "reversal", "excursion", "touch"]
    at = [u for _, u in events]
    assert at[2] == 2.0 and close(at[3], u_c, 1.0) and close(at[4], u_t, 1.0)


def _history(amplitudes, n):
    """A smooth cyclic drift history, half-cycle k: (-1)^k A_k sin(pi (t - k)) on [k, k + 1], sampled
    at n points per half-cycle (n odd: no sample on a turning point); (samples, the turning points
    (t, u) in order)."""
    samples, turns = [], []
    for k, a in enumerate(amplitudes):
        sign = -1.0 if k % 2 else 1.0
        turns.append((k + 0.5, sign * a))
        for j in range(1, n + 1):
            t = k + j / n
            samples.append((t, sign * a * math.sin(math.pi * (t - k))))
    return samples, turns


def _ours(params, samples, turns):
    """Our law along the history, through its exact turning points; the force at each sample."""
    storey, out, i = IMKStorey(params), [], 0
    for t, u in samples:
        while i < len(turns) and turns[i][0] <= t:
            if turns[i][0] < t:
                storey.move(turns[i][1])
            i += 1
        out.append(storey.move(u))
    return out, storey.failure


@pytest.mark.parametrize("params, amplitudes", [
    (NORM, (0.5, 0.5, 2, 2, 4, 4, 6, 6, 8, 8, 10, 10, 12, 12, 16, 16)),
    (STOREY, (0.004, 0.004, 0.015, 0.015, 0.04, 0.04, 0.08, 0.08, 0.15, 0.15, 0.3, 0.3, 0.45, 0.45, 0.65, 0.65)),
    (ASYM, (0.5, 0.5, 2, 2, 4, 4, 6, 6, 8, 8, 10, 10, 13, 13, 16, 16)),
])
def test_opensees_imkbilin_converges_to_the_exact_law(params, amplitudes, tmp_path):
    """OpenSees's IMKBilin (openseespy, in a child process) at 101, 401 and 1601 samples per
    half-cycle against our law on the same samples, through yield, capping, deterioration, the
    residual and the loss of both sides: the error falls at about second order in the step."""
    from pidamper.running import isolated

    assert isolated.call("pidamper.oracles.opensees:available", hard_exit=True) is None  # the test extra has it
    fy, errors = params[4], []
    for n in (101, 401, 1601):
        samples, turns = _history(amplitudes, n)
        ours, failure = _ours(params, samples, turns)
        path = tmp_path / f"strains-{n}.json"
        path.write_text(json.dumps([u for _, u in samples]))
        theirs = isolated.call("pidamper.oracles.opensees:imk_material", params, str(path), hard_exit=True)
        assert None not in theirs
        errors.append(max(abs(a - b) for a, b in zip(ours, theirs)) / fy)
        assert failure == LOST  # both sides lost by the end
        assert theirs[-1] == 0.0
    assert errors[0] / errors[1] >= 6.0 and errors[1] / errors[2] >= 6.0, errors
    assert errors[2] <= 3e-5, errors


@pytest.mark.parametrize("key, value, rule", [
    ("Ke", 0.0, "elastic stiffness"),
    ("FmaxFy_pos", 0.9, "capping force must not be below the yield force"),
    ("du_neg", 2.0, "ultimate drift must not come before the capping drift"),
    ("FresFy_neg", 1.5, "0 <= FresFy <= 1"),
    ("dp_neg", -3.0, "positive magnitudes"),
    ("LamdaK", 0.0, "large Lamda"),
    ("D_pos", -0.1, ">= 0"),
    ("Cs", math.nan, "finite"),
])
def test_bad_parameters_are_refused_naming_the_storey_value_and_rule(key, value, rule):
    params = list(NORM)
    params[PARAMETERS.index(key)] = value
    with pytest.raises(ParameterError) as err:
        IMKStorey(params, name="storey[2]")
    assert f"storey[2].{key}" in str(err.value) and rule in str(err.value)
    assert repr(value) in str(err.value)
    with pytest.raises(ParameterError, match="21 numbers"):
        check_imk(NORM[:20])


def _random_path(seed, legs=150, reach=20.0):
    """Leg ends of a random piecewise-linear drift path in yield drifts: long legs and short ones
    (partial unloading and reloading, reversals anywhere), within +-reach."""
    rng, x, ends = random.Random(seed), 0.0, []
    for _ in range(legs):
        x = max(-reach, min(reach, x + (rng.uniform(-6, 6) if rng.random() < 0.7 else rng.uniform(-1, 1))))
        ends.append(x)
    return ends


@pytest.mark.parametrize("params, seed", [(NORM, 100), (NORM, 101), (ASYM, 102)])
def test_opensees_converges_on_random_paths_with_partial_cycles(params, seed, tmp_path):
    """Random piecewise-linear paths (reversals off the backbone, reloading inside a cycle), each
    leg cut into m equal strain steps for OpenSees: at the legs' ends its force approaches ours as
    m grows, by more than 30 times per 10 times more steps."""
    from pidamper.running import isolated

    uy = params[4] / params[0]
    ends = [uy * e for e in _random_path(seed)]
    storey = IMKStorey(params)
    ours = [storey.move(u) for u in ends]
    errors = []
    for m in (10, 100, 1000):
        strains, start = [], 0.0
        for u in ends:
            strains += [start + (u - start) * i / m for i in range(1, m + 1)]
            start = u
        path = tmp_path / f"strains-{m}.json"
        path.write_text(json.dumps(strains))
        theirs = isolated.call("pidamper.oracles.opensees:imk_material", params, str(path), hard_exit=True)[m - 1::m]
        errors.append(max(abs(a - b) for a, b in zip(ours, theirs)) / params[4])
    assert errors[0] / errors[1] >= 30.0 and errors[1] / errors[2] >= 30.0 and errors[2] <= 1e-4, errors


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10 ** 6), params=st.sampled_from([NORM, STOREY, ASYM]))
def test_invariants_on_random_paths(seed, params):
    """Along any path: the force never passes the backbone of the direction of motion, the failure
    state never goes back, a lost storey carries nothing, a leg taken in 100 moves ends where the
    leg taken at once does (a rate-independent law: splitting a move changes nothing), and the
    work done on the storey is the integral of its force (the trapezoid over the fine moves)."""
    uy, fy = params[4] / params[0], params[4]
    storey, fine = IMKStorey(params), IMKStorey(params)
    state, trapezoid = ELASTIC, 0.0
    for end in _random_path(seed, legs=30):
        target = uy * end
        d = 1 if target > storey.u else -1
        f = storey.move(target)
        assert d * (f - storey.backbone(d, target)) <= 1e-12 * fy
        assert storey.failure >= state
        state = storey.failure
        if state == LOST:
            assert f == 0.0
        u0 = fine.u
        for i in range(1, 101):
            u, f_before = fine.u, fine.f
            fine.move(u0 + (target - u0) * i / 100)
            trapezoid += 0.5 * (f_before + fine.f) * (fine.u - u)
        assert fine.failure == storey.failure
        assert abs(fine.f - f) <= 1e-9 * fy
    assert abs(fine.e_acc - storey.e_acc) <= 1e-9 * (abs(storey.e_acc) + fy * uy)
    assert abs(trapezoid - storey.e_acc) <= 2e-2 * (abs(storey.e_acc) + fy * uy)
