"""Ground-motion records (readers, stochastic generators, suites) and intensity measures (PGA,
PGV, the Nigam-Jennings response spectrum) against closed forms and independent oracles."""
import math

import numpy as np
import pytest
from scipy import signal as sps
from scipy.integrate import quad

from pidamper.forcing import ground_motion as gm
from pidamper.forcing import spectra

G = 9.80665


# ------------------------------------------------------------------------------------------
# 1. PEER NGA .AT2
# ------------------------------------------------------------------------------------------

# values in the PEER style (Fortran E15.7 without the leading 0), 12 of them
PEER_TOKENS = [".1234567E-02", "-.2345678E-01", ".3456789E+00", "-.4567891E-03", ".0000000E+00",
               ".5678912E-02", "-.6789123E-01", ".7891234E-02", "-.8912345E-02", ".9123456E-04",
               "-.1000000E+01", ".2000000E-05"]


def _peer_text(header4, tokens=PEER_TOKENS, per_line=5):
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", "Imperial Valley-02, 5/19/1940, El Centro Array #9, 180",
             "ACCELERATION TIME SERIES IN UNITS OF G", header4]
    for start in range(0, len(tokens), per_line):
        lines.append("".join(f"{tok:>15}" for tok in tokens[start:start + per_line]))
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("header4", ["NPTS=    12, DT=   .0050 SEC", "   12    0.0050    NPTS, DT",
                                     "NPTS=     12  DT=  0.0050 SEC,"])
def test_at2_peer_text_both_header_forms(tmp_path, header4):
    path = tmp_path / "RSN6_IMPVALL.I_I-ELC180.AT2"
    path.write_text(_peer_text(header4))
    rec = gm.read_at2(path)
    assert rec.name == "RSN6_IMPVALL.I_I-ELC180"
    assert rec.dt == 0.005 and rec.npts == 12
    expected = np.array([float(t) for t in PEER_TOKENS]) * G
    assert np.array_equal(rec.accel, expected)  # same parse, same product: bit for bit
    assert "Imperial Valley-02" in rec.source and str(path) in rec.source


def test_at2_write_read_round_trip(tmp_path):
    accel = np.random.default_rng(7).standard_normal(23) * 3.0
    rec = gm.Record("synthetic", 0.0125, accel, "test")
    back = gm.read_at2(gm.write_at2(tmp_path / "full.AT2", rec, digits=16))
    assert back.dt == rec.dt and back.npts == 23
    assert np.max(np.abs(back.accel - accel)) <= 4e-16 * np.max(np.abs(accel))
    back7 = gm.read_at2(gm.write_at2(tmp_path / "peer.AT2", rec))  # PEER precision: 8 significant digits
    assert np.max(np.abs(back7.accel - accel) / np.abs(accel)) < 6e-8
    lines = (tmp_path / "peer.AT2").read_text().splitlines()
    assert lines[2] == "ACCELERATION TIME SERIES IN UNITS OF G" and lines[3].startswith("NPTS=")
    assert [len(line.split()) for line in lines[4:]] == [5, 5, 5, 5, 3]


def _base_lines(tmp_path):
    """A valid AT2 with 40 values: header lines 1-4, data on lines 5-12 (5 per line)."""
    rec = gm.Record("base", 0.01, np.linspace(-1, 1, 40), "test")
    text = gm.write_at2(tmp_path / "base.AT2", rec).read_text()
    return text.splitlines()


MALFORMED = {
    "bad NPTS line": (lambda L: L[:3] + ["NPTS=  4O, DT=   .0100 SEC"] + L[4:], 4, "NPTS"),
    "NPTS zero": (lambda L: L[:3] + ["NPTS=   0, DT=   .0100 SEC"] + L[4:], 4, "NPTS"),
    "DT negative": (lambda L: L[:3] + ["NPTS=  40, DT=  -.0100 SEC"] + L[4:], 4, "DT"),
    "no NPTS/DT at all": (lambda L: L[:3] + ["5590 values at 200 Hz"] + L[4:], 4, "NPTS"),
    "garbled number on line 7": (lambda L: L[:6] + [L[6].replace("E-0", "E-O", 1)] + L[7:], 7,
                                 "expected a finite number"),
    "nan on line 9": (lambda L: L[:8] + ["NaN " + L[8]] + L[9:], 9, "expected a finite number"),
    "too few values": (lambda L: L[:11] + [" ".join(L[11].split()[:-1])], 12, "after 39 values"),
    "too few lines": (lambda L: L[:10], 10, "after 30 values"),
    "too many values": (lambda L: L[:12] + ["  .1000000E+00"], 13, "one too many"),
    "missing line 1": (lambda L: L[1:], 3, "ACCELERATION TIME SERIES IN UNITS OF G"),
    "missing line 2": (lambda L: L[:1] + L[2:], 3, "ACCELERATION TIME SERIES IN UNITS OF G"),
    "missing line 3": (lambda L: L[:2] + L[3:], 3, "ACCELERATION TIME SERIES IN UNITS OF G"),
    "missing line 4": (lambda L: L[:3] + L[4:], 4, "NPTS"),
    "velocity file": (lambda L: L[:2] + ["VELOCITY TIME SERIES IN UNITS OF CM/S"] + L[3:], 3, "UNITS OF G"),
    "units of gal": (lambda L: L[:2] + ["ACCELERATION TIME SERIES IN UNITS OF GAL"] + L[3:], 3, "UNITS OF G"),
    "header only": (lambda L: L[:2], 3, "header"),
    "empty": (lambda L: [], 1, "header"),
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_at2_malformed_refused_naming_file_and_line(tmp_path, case):
    edit, line, what = MALFORMED[case]
    good = _base_lines(tmp_path)
    assert gm.read_at2(tmp_path / "base.AT2").npts == 40 and len(good) == 12
    path = tmp_path / "bad.AT2"
    lines = edit(list(good))
    path.write_text("".join(line + "\n" for line in lines))
    with pytest.raises(gm.RecordError) as info:
        gm.read_at2(path)
    message = str(info.value)
    assert isinstance(info.value, ValueError)
    assert message.startswith(f"{path}, line {line}:"), message
    assert what in message, message


# ------------------------------------------------------------------------------------------
# 2. CSV time,a_g
# ------------------------------------------------------------------------------------------

def _csv(path, times, values, header="time,a_g"):
    path.write_text(header + "\n" + "".join(f"{float(t)!r},{float(a)!r}\n" for t, a in zip(times, values)))
    return path


def test_csv_good_file_shifted_to_zero(tmp_path):
    times = 12.5 + 0.02 * np.arange(50)
    values = np.sin(times)
    rec = gm.read_csv(_csv(tmp_path / "rec.csv", times, values))
    assert rec.name == "rec" and rec.npts == 50
    assert rec.dt == pytest.approx(0.02, rel=1e-12)
    assert rec.time[0] == 0.0 and rec.duration == pytest.approx(0.98, rel=1e-12)
    assert np.array_equal(rec.accel, values)
    assert rec.to_forcing().target == "a_g"


@pytest.mark.parametrize("edit, line, what", [
    (lambda t, a: (np.r_[t[:4], t[4] + 1e-3, t[5:]], a), 6, "uniform spacing"),  # sample 4 is on line 6
    (lambda t, a: (t[::-1], a), 3, "increasing"),
])
def test_csv_non_uniform_refused_naming_line(tmp_path, edit, line, what):
    times, values = edit(0.01 * np.arange(20), np.zeros(20))
    path = _csv(tmp_path / "bad.csv", times, values)
    with pytest.raises(gm.RecordError, match=what) as info:
        gm.read_csv(path)
    assert str(info.value).startswith(f"{path}, line {line}:"), str(info.value)


def test_csv_malformed_refused_naming_line(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("time,a_g\n0.0,1.0\n0.01,2.0\n0.02,abc\n0.03,1.0\n")
    with pytest.raises(gm.RecordError, match=rf"^{path}, line 4: .*two finite numbers"):
        gm.read_csv(path)
    path.write_text("time,a_g\n0.0,1.0\n")
    with pytest.raises(gm.RecordError, match=rf"^{path}, line 3 \(end of file\): 1 data rows"):
        gm.read_csv(path)
    path.write_text("t,acc\n0.0,1.0\n0.01,2.0\n")
    with pytest.raises(gm.RecordError, match=rf"^{path}, line 1: header"):
        gm.read_csv(path)


# ------------------------------------------------------------------------------------------
# 3-4. Response spectrum against closed forms
# ------------------------------------------------------------------------------------------

def _sine_response(t, A, W, w, zeta):
    """Closed-form u, u' of u'' + 2 zeta w u' + w^2 u = -A sin(W t), u(0) = u'(0) = 0."""
    r, s = w * w - W * W, 2 * zeta * w * W
    den = r * r + s * s
    c1, c2 = -A * r / den, A * s / den
    wd = w * math.sqrt(1 - zeta * zeta)
    d1 = -c2
    d2 = (zeta * w * d1 - c1 * W) / wd
    e = np.exp(-zeta * w * t)
    u = c1 * np.sin(W * t) + c2 * np.cos(W * t) + e * (d1 * np.cos(wd * t) + d2 * np.sin(wd * t))
    v = (c1 * W * np.cos(W * t) - c2 * W * np.sin(W * t)
         + e * ((-zeta * w * d1 + wd * d2) * np.cos(wd * t) + (-zeta * w * d2 - wd * d1) * np.sin(wd * t)))
    return u, v


def test_spectrum_of_sine_record_matches_closed_form():
    """a = A sin(W t) sampled every dt = 2.5e-4 s (W dt = 1.6e-3): the piecewise-linear record
    differs from the sine by <= A (W dt)^2 / 8, so Sd agrees with the closed form (evaluated at
    the same samples) to ~1e-7; near and at resonance (T = 1 s = 2 pi / W) included."""
    A, W, zeta, dt = 2.0, 2 * math.pi, 0.05, 2.5e-4
    t = np.arange(0.0, 8.0 + dt / 2, dt)
    periods = np.array([0.2, 0.5, 0.95, 1.0, 1.05, 2.0, 4.0])
    spec = spectra.response_spectrum(A * np.sin(W * t), dt, periods, zeta)
    for k, T in enumerate(periods):
        w = 2 * math.pi / T
        u, v = _sine_response(t, A, W, w, zeta)
        sd = np.max(np.abs(u))
        assert spec["Sd"][k] == pytest.approx(sd, rel=1e-6, abs=0)
        assert spec["Sv"][k] == pytest.approx(np.max(np.abs(v)), rel=1e-6, abs=0)
        assert spec["Sa"][k] == pytest.approx(w * w * sd, rel=1e-6, abs=0)
        assert spec["Sa_abs"][k] == pytest.approx(np.max(np.abs(w * w * u + 2 * zeta * w * v)), rel=1e-6)
    assert spec["Sd"][3] > 5 * spec["Sd"][0]  # resonance is where it should be


def test_sdof_history_matches_lsim_first_order_hold_and_closed_form_matrices():
    """The whole u, u' history of a coarse random record (dt = 0.02 s) against scipy.signal.lsim
    with linear interpolation of the input (an independent exact solution for piecewise-linear
    input), and the closed-form Nigam-Jennings matrices against the matrix-exponential ones."""
    rng = np.random.default_rng(3)
    dt = 0.02
    accel = rng.standard_normal(400)
    t = np.arange(accel.size) * dt
    periods = np.array([0.1, 0.3, 1.0, 3.0])
    zeta = 0.05
    u, v = spectra.sdof_response(accel, dt, periods, zeta)
    uc, vc = spectra.sdof_response(accel, dt, periods, zeta, method="closed-form")
    for k, T in enumerate(periods):
        w = 2 * math.pi / T
        system = ([[0.0, 1.0], [-w * w, -2 * zeta * w]], [[0.0], [-1.0]], np.eye(2), [[0.0], [0.0]])
        _, y, _ = sps.lsim(system, accel, t, interp=True)
        assert np.max(np.abs(u[:, k] - y[:, 0])) <= 1e-12 * np.max(np.abs(y[:, 0]))
        assert np.max(np.abs(v[:, k] - y[:, 1])) <= 1e-12 * np.max(np.abs(y[:, 1]))
    assert np.max(np.abs(uc - u)) <= 1e-12 * np.max(np.abs(u))
    spec = spectra.response_spectrum(accel, dt, periods, zeta)
    assert np.array_equal(spec["Sd"], np.max(np.abs(u), axis=0))
    assert np.array_equal(spec["Sv"], np.max(np.abs(v), axis=0))


def _ramp_response(t, slope, w, zeta):
    """u of u'' + 2 zeta w u' + w^2 u = -slope * t for t > 0, from rest; 0 for t <= 0."""
    wd = w * math.sqrt(1 - zeta * zeta)
    d1 = -2 * zeta * slope / w ** 3
    d2 = slope * (1 - 2 * zeta * zeta) / (w * w * wd)
    tp = np.maximum(t, 0.0)
    u = -slope / (w * w) * (tp - 2 * zeta / w) + np.exp(-zeta * w * tp) * (d1 * np.cos(wd * tp) + d2 * np.sin(wd * tp))
    return np.where(t > 0, u, 0.0)


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2])
def test_triangular_pulse_matches_superposed_ramps(zeta):
    """A symmetric triangular pulse (peak A at td/2, vertices on samples) is exactly piecewise
    linear; its response is the closed-form superposition g(t) - 2 g(t - td/2) + g(t - td) of
    ramp responses. Agreement at the samples to round-off."""
    A, td, dt = 3.0, 0.4, 0.01
    t = np.arange(0.0, 6.0 + dt / 2, dt)
    accel = np.interp(t, [0.0, td / 2, td], [0.0, A, 0.0], right=0.0)
    periods = np.array([0.05, 0.2, 0.4, 0.8, 1.6, 3.0])
    spec = spectra.response_spectrum(accel, dt, periods, zeta)
    for k, T in enumerate(periods):
        w = 2 * math.pi / T
        slope = 2 * A / td
        u = _ramp_response(t, slope, w, zeta) - 2 * _ramp_response(t - td / 2, slope, w, zeta) \
            + _ramp_response(t - td, slope, w, zeta)
        assert spec["Sd"][k] == pytest.approx(np.max(np.abs(u)), rel=1e-12, abs=0)


def test_rectangular_pulse_undamped_shock_spectrum():
    """Undamped response to a rectangular pulse A of duration td (u_st = A / w^2): max |u| =
    2 u_st if td / T >= 1/2, else 2 u_st sin(pi td / T) (the residual vibration). The record is
    the pulse with ramps of one sample (dt = 2e-4 s): the exact response to that trapezoid is the
    pulse response averaged over dt, so the maxima agree to O((w dt)^2) ~ 3e-6."""
    A, td, dt = 1.5, 0.5, 2e-4
    n_pulse = round(td / dt)
    periods = np.array([0.25, 0.5, 0.8, 1.0, 2.0, 4.0])
    accel = np.zeros(round((td + periods.max()) / dt) + 2)
    accel[1:n_pulse + 1] = A
    spec = spectra.response_spectrum(accel, dt, periods, zeta=0.0)
    w = 2 * math.pi / periods
    ratio = td / periods
    expected = 2 * A / w ** 2 * np.where(ratio >= 0.5, 1.0, np.abs(np.sin(math.pi * ratio)))
    assert np.max(np.abs(spec["Sd"] / expected - 1)) < 5e-6


def test_spectrum_edges_and_sa():
    rec = gm.Record("r", 0.01, np.sin(np.arange(300) * 0.1), "test")
    spec = spectra.response_spectrum(rec.accel, rec.dt, [0.0, 0.5, 1.0])
    assert spec["Sd"][0] == 0.0 and spec["Sa"][0] == spectra.pga(rec)
    assert spectra.sa(rec, 0.5) == spec["Sa"][1]
    assert isinstance(spectra.sa(rec, 1.0), float)
    assert spectra.sa(rec.scaled(2.0), 1.0) == pytest.approx(2 * spectra.sa(rec, 1.0), rel=1e-14)
    with pytest.raises(ValueError, match="zeta"):
        spectra.response_spectrum(rec.accel, rec.dt, [1.0], zeta=1.0)


# ------------------------------------------------------------------------------------------
# 5. PGA, PGV
# ------------------------------------------------------------------------------------------

def test_pgv_exact_for_piecewise_linear_records():
    dt = 0.01
    # a triangle pulse: v rises monotonically to its area A td / 2
    t = np.arange(0.0, 1.0 + dt / 2, dt)
    tri = gm.Record("tri", dt, np.interp(t, [0.0, 0.2, 0.4], [0.0, 5.0, 0.0], right=0.0), "test")
    assert spectra.pgv(tri) == pytest.approx(5.0 * 0.4 / 2, rel=1e-13)
    assert spectra.pga(tri) == 5.0
    # a sign change inside an interval: the peak lies between the samples, at the zero crossing
    # v(dt) = A dt / 2, then + A dt / 4 up to the crossing at 1.5 dt: 3 A dt / 4
    jump = gm.Record("jump", dt, [0.0, 4.0, -4.0, 0.0], "test")
    assert spectra.pgv(jump) == pytest.approx(0.75 * 4.0 * dt, rel=1e-14)
    assert np.max(np.abs(spectra.ground_velocity(jump))) == pytest.approx(0.5 * 4.0 * dt, rel=1e-14)
    # a negative record: the peak of |v|
    assert spectra.pgv(jump.scaled(-1.0)) == pytest.approx(0.03, rel=1e-14)


def test_pgv_of_fine_sine():
    """a = A sin(W t): v = A (1 - cos W t) / W, peak 2 A / W (to the interpolation error)."""
    A, W, dt = 2.0, 3.0, 1e-3
    t = np.arange(0.0, 5.0 + dt / 2, dt)
    rec = gm.Record("sine", dt, A * np.sin(W * t), "test")
    assert spectra.pgv(rec) == pytest.approx(2 * A / W, rel=1e-6)


# ------------------------------------------------------------------------------------------
# 6. Stochastic records
# ------------------------------------------------------------------------------------------

KT = dict(omega_g=15.6, zeta_g=0.6)
CP = dict(omega_g=15.6, zeta_g=0.6, omega_f=1.5, zeta_f=0.6)


def test_closed_form_variances_and_model():
    """Kanai-Tajimi closed form = quad of the density = Lyapunov variance of the simulated
    state-space model; Clough-Penzien quad oracle = Lyapunov variance."""
    S0 = 0.02
    closed = gm.kanai_tajimi_variance(S0=S0, **KT)
    integral = 2 * quad(lambda w: float(gm.kanai_tajimi_psd(w, S0=S0, **KT)), 0, np.inf, limit=400,
                        epsabs=0, epsrel=1e-12)[0]
    assert integral == pytest.approx(closed, rel=1e-9)
    assert gm.stationary_variance(S0=S0, **KT) == pytest.approx(closed, rel=1e-12)
    assert gm.stationary_variance(S0=S0, **CP) == pytest.approx(gm.clough_penzien_variance(S0=S0, **CP), rel=1e-9)
    assert gm.clough_penzien_variance(S0=S0, **CP) < closed  # the high-pass removes power


@pytest.mark.parametrize("model, params", [("kanai-tajimi", KT), ("clough-penzien", CP)])
def test_stochastic_records_reproduce_target_variance(model, params):
    """40 independent stationary records of 20 s: the mean of their mean squares is an unbiased
    estimate of the stationary variance; it lies within 4 standard errors of the target."""
    S0 = 0.02
    target = gm.kanai_tajimi_variance(S0=S0, **KT) if model == "kanai-tajimi" else \
        gm.clough_penzien_variance(S0=S0, **CP)
    make = gm.GENERATORS[model]
    ms = np.array([np.mean(make(20.0, 0.01, S0=S0, seed=s, **params).accel ** 2) for s in range(40)])
    se = ms.std(ddof=1) / math.sqrt(ms.size)
    assert abs(ms.mean() - target) < 4 * se, (ms.mean(), target, se)
    assert se < 0.05 * target


def test_seed_pga_envelope_and_start():
    a = gm.kanai_tajimi(5.0, 0.01, S0=0.02, seed=11, **KT)
    b = gm.kanai_tajimi(5.0, 0.01, S0=0.02, seed=11, **KT)
    c = gm.kanai_tajimi(5.0, 0.01, S0=0.02, seed=12, **KT)
    assert np.array_equal(a.accel, b.accel) and not np.allclose(a.accel, c.accel)
    assert a.npts == 501 and a.duration == pytest.approx(5.0) and a.name == "kanai-tajimi-seed11"
    assert "seed=11" in a.source and "S0=0.02" in a.source
    p = gm.clough_penzien(5.0, 0.01, pga=3.0, seed=11, **CP)
    assert np.max(np.abs(p.accel)) == pytest.approx(3.0, rel=1e-14)
    # a uniformly modulated process: the stationary record times the envelope, sample by sample
    env = {"kind": "jennings", "t1": 1.0, "t2": 3.0, "c": 0.8}
    m = gm.kanai_tajimi(5.0, 0.01, S0=0.02, seed=11, envelope=env, **KT)
    assert np.allclose(m.accel, a.accel * gm.envelope(a.time, **env), rtol=1e-14, atol=0)
    assert gm.kanai_tajimi(5.0, 0.01, S0=0.02, seed=11, start="rest", **KT).accel[0] == 0.0
    with pytest.raises(ValueError, match="exactly one of S0"):
        gm.kanai_tajimi(5.0, 0.01, S0=0.02, pga=3.0, **KT)
    with pytest.raises(ValueError, match=r"unknown parameter\(s\) \['t3'\]"):
        gm.kanai_tajimi(5.0, 0.01, S0=0.02, envelope={"kind": "jennings", "t1": 1, "t2": 2, "t3": 1}, **KT)


def _flipped_eigh(eigh):
    """numpy's eigh with every eigenvector's sign flipped: an equally valid answer another LAPACK may give."""
    def flipped(C, *args, **kwargs):
        w, V = eigh(C, *args, **kwargs)
        return w, -V
    return flipped


@pytest.mark.parametrize("model, params, dt", [("kanai-tajimi", KT, 0.005), ("clough-penzien", CP, 0.01)])
def test_a_seed_gives_the_same_record_whatever_signs_lapack_picks(monkeypatch, model, params, dt):
    """The noise factor is the unique Cholesky factor, so a seed reproduces its record on any machine.
    An eigen-decomposition's eigenvector signs are the library's choice: with them flipped, a record
    drawn through V sqrt(w) changes (the shipped assessment page moved by 0.7 % in Sa between two
    machines); this one must not, from a stationary start or from rest."""
    make = gm.GENERATORS[model]
    for start in ("stationary", "rest"):
        before = make(10.0, dt, pga=1.0, seed=3, start=start, **params).accel
        with monkeypatch.context() as m:
            m.setattr(np.linalg, "eigh", _flipped_eigh(np.linalg.eigh))
            after = make(10.0, dt, pga=1.0, seed=3, start=start, **params).accel
        assert np.array_equal(before, after), model


def test_semi_definite_noise_factor_is_sign_free(monkeypatch):
    """A singular covariance (no Cholesky factor) is factored through eigh with each eigenvector's
    largest entry made positive: L L^T = C, and the same L with eigh's signs flipped."""
    v = np.array([1.0, -2.0, 0.5])
    C = np.outer(v, v) + np.outer([0.0, 1.0, 1.0], [0.0, 1.0, 1.0])  # rank 2 of 3
    L = gm._psd_sqrt(C)
    assert np.allclose(L @ L.T, C, rtol=0, atol=1e-14 * np.abs(C).max())
    monkeypatch.setattr(np.linalg, "eigh", _flipped_eigh(np.linalg.eigh))
    assert np.array_equal(gm._psd_sqrt(C), L)
    P = np.diag([4.0, 1.0])  # positive definite: Cholesky's factor, lower triangular with a positive diagonal
    assert np.array_equal(gm._psd_sqrt(P), np.diag([2.0, 1.0]))


def test_envelopes():
    t = np.array([-1.0, 0.0, 0.5, 1.0, 2.0, 3.0, 3.0 + 1 / 0.8])
    e = gm.envelope(t, "jennings", t1=1.0, t2=3.0, c=0.8)
    assert np.allclose(e, [0.0, 0.0, 0.25, 1.0, 1.0, 1.0, math.exp(-1.0)], rtol=1e-15, atol=0)
    b, c = 2.0, 0.5
    ts = np.linspace(0.1, 30, 300)
    sh = gm.envelope(ts, "saragoni-hart", b=b, c=c)
    assert gm.envelope(b / c, "saragoni-hart", b=b, c=c) == pytest.approx(1.0, rel=1e-15)
    ratio = sh / (ts ** b * np.exp(-c * ts))  # Saragoni-Hart's a t^b exp(-c t) with a fixed
    assert np.allclose(ratio, ratio[0], rtol=1e-12)
    assert sh.max() <= 1.0


# ------------------------------------------------------------------------------------------
# 7. Suites
# ------------------------------------------------------------------------------------------

def test_suite_folder(tmp_path):
    folder = tmp_path / "motions"
    folder.mkdir()
    base = gm.Record("x", 0.01, np.linspace(0, 1, 7), "test")
    gm.write_at2(folder / "b.AT2", base)
    gm.write_at2(folder / "c.at2", base.scaled(2.0))
    _csv(folder / "a.csv", 0.01 * np.arange(5), np.ones(5))
    (folder / "notes.txt").write_text("not a record")
    records = gm.suite({"folder": "motions"}, folder=tmp_path)
    assert [r.name for r in records] == ["a", "b", "c"]
    assert records[2].accel[-1] == pytest.approx(2.0, rel=1e-7)
    assert [r.name for r in gm.suite({"folder": str(folder)})] == ["a", "b", "c"]
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['scale'\]"):
        gm.suite({"folder": "motions", "scale": 2}, folder=tmp_path)
    with pytest.raises(ValueError, match="not a directory"):
        gm.suite({"folder": "nowhere"}, folder=tmp_path)


def test_suite_generator():
    spec = {"generator": "clough-penzien", "count": 3, "seed": 5, "duration": 4.0, "dt": 0.01, "pga": 2.5,
            "envelope": {"kind": "jennings", "t1": 0.5, "t2": 2.0, "c": 1.0}, **CP}
    records = gm.suite(spec)
    assert [r.name for r in records] == ["clough-penzien-seed5", "clough-penzien-seed6", "clough-penzien-seed7"]
    direct = gm.clough_penzien(4.0, 0.01, pga=2.5, seed=6, envelope=spec["envelope"], **CP)
    assert np.array_equal(records[1].accel, direct.accel)
    kt = gm.suite({"generator": "kanai-tajimi", "count": 2, "duration": 2.0, "dt": 0.01, "S0": 0.01, **KT})
    assert [r.name for r in kt] == ["kanai-tajimi-seed1", "kanai-tajimi-seed2"]
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['omega_gg'\]"):
        gm.suite({"generator": "kanai-tajimi", "count": 2, "duration": 2.0, "dt": 0.01, "S0": 0.01,
                  "omega_gg": 3.0, **KT})
    with pytest.raises(ValueError, match=r"unknown key\(s\) \['omega_f', 'zeta_f'\]"):
        gm.suite({**spec, "generator": "kanai-tajimi"})
    with pytest.raises(ValueError, match=r"missing key\(s\) \['count'\]"):
        gm.suite({k: v for k, v in spec.items() if k != "count"})
    with pytest.raises(ValueError, match="exactly one of 'set'"):
        gm.suite({"folder": "x", "generator": "kanai-tajimi"})


def test_record_basics():
    r = gm.Record("r", 0.5, [1.0, -2.0, 3.0], "src")
    assert r.npts == 3 and r.duration == 1.0 and np.array_equal(r.time, [0.0, 0.5, 1.0])
    s = r.scaled(2.0)
    assert s.name == "r" and np.array_equal(s.accel, [2.0, -4.0, 6.0]) and "scaled by 2.0" in s.source
    with pytest.raises(ValueError):
        r.accel[0] = 5.0  # read-only
    with pytest.raises(ValueError, match="dt"):
        gm.Record("r", 0.0, [1.0], "src")


def test_sa_avg_is_the_geometric_mean_of_sa_from_0_2_to_3_t1():
    """Sa_avg (Eads et al. 2015) of a FEMA P-695 record: its definition with the project's Sa at
    each of the ten periods 0.2 T1 .. 3 T1, and with an independent spectrum (scipy.signal.lsim,
    linear interpolation of the input: exact for the piecewise-linear record, peaks at the
    samples), to 1e-9; and it scales with the record (an intensity measure)."""
    record = gm.fema_p695("fema-p695-far-field", components="a", records=[2])[0]
    t1, zeta = 1.3, 0.05
    periods = np.linspace(0.2 * t1, 3.0 * t1, 10)
    mine = spectra.sa_avg(record, t1, zeta)
    by_sa = math.exp(sum(math.log(spectra.sa(record, float(T), zeta)) for T in periods) / 10)
    t = np.arange(record.npts) * record.dt
    logs = []
    for T in periods:
        w = 2 * math.pi / T
        system = ([[0.0, 1.0], [-w * w, -2 * zeta * w]], [[0.0], [-1.0]], [[1.0, 0.0]], [[0.0]])
        _, u, _ = sps.lsim(system, record.accel, t, interp=True)
        logs.append(math.log(w * w * np.max(np.abs(u))))
    independent = math.exp(sum(logs) / len(logs))
    assert mine == pytest.approx(by_sa, rel=1e-12)
    assert mine == pytest.approx(independent, rel=1e-9)
    assert spectra.sa_avg(record.scaled(2.5), t1, zeta) == pytest.approx(2.5 * mine, rel=1e-12)
