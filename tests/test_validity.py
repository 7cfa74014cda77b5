"""Validity of the linear model: the small-angle error estimate against the exact pendulum,
and the FMU's once-per-run warning through the FMI logger."""
import math

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import ellipk

from pidamper import FmuStepper, run
from pidamper.running import isolated
from pidamper_physics import Damper, Params, SmallAngleMonitor, frequency_error

W2 = math.sqrt(9.81)


@pytest.mark.parametrize("amplitude", [1e-3, 0.1, 0.4, 1.0, 2.0, 3.0, 3.14])
def test_frequency_error_is_the_exact_pendulum_s(amplitude):
    """w(A)/w0 = pi / (2 K(sin^2(A/2))), K the complete elliptic integral (mpmath, 40 digits)."""
    with mpmath.workdps(40):
        exact = float(1 - mpmath.pi / (2 * mpmath.ellipk(mpmath.sin(mpmath.mpf(amplitude) / 2) ** 2)))
    assert frequency_error(amplitude) == pytest.approx(exact, rel=4e-15)
    assert frequency_error(amplitude) == pytest.approx(1.0 - math.pi / (2.0 * ellipk(math.sin(0.5 * amplitude) ** 2)),
                                                       rel=1e-7)  # scipy's K, which loses digits to cancellation
    assert frequency_error(-amplitude) == frequency_error(amplitude)


def test_frequency_error_against_an_integrated_pendulum_and_its_small_angle_limit():
    amplitude = 0.8
    sol = solve_ivp(lambda t, s: (s[1], -W2 ** 2 * math.sin(s[0])), (0, 3.0), (amplitude, 0.0), method="DOP853",
                    rtol=1e-12, atol=1e-14, events=lambda t, s: s[0])
    period = 4.0 * sol.t_events[0][0]  # a quarter period from the extreme to the bottom
    assert frequency_error(amplitude) == pytest.approx(1.0 - (2 * math.pi / W2) / period, rel=1e-8)
    assert frequency_error(0.01) == pytest.approx(0.01 ** 2 / 16, rel=1e-4)
    assert frequency_error(math.pi) == frequency_error(10.0) == 1.0


def test_monitor_warns_once_at_the_first_swing_beyond_the_limit():
    p = Params(mu=0.0)  # primary alone: its swing is sqrt(theta^2 + (theta_dot/w2)^2) = 0.5 rad throughout
    dm = Damper(p, theta_dot0=0.5 * W2)
    monitor = SmallAngleMonitor(p, 0.45)
    assert monitor.summary() is None
    dm.advance(0.3)
    text = monitor.check(dm)
    assert "primary (theta) swings 0.5 rad" in text and "limit 0.45 rad" in text
    assert f"{100 * frequency_error(0.5):.2g} % slower" in text
    assert monitor.check(dm) is None and monitor.warned
    assert "largest swings of the run: primary 0.5 rad, particle within the limit (limit 0.45 rad)" in monitor.summary()
    assert SmallAngleMonitor(p, 0.55).check(dm) is None


def test_monitor_names_the_particle_and_keeps_its_largest_swing():
    p = Params(mu=0.1, d=10.0)  # no contact: the particle swings freely at 0.6 rad
    dm = Damper(p, alpha_dot0=0.6 * p.w1)
    monitor = SmallAngleMonitor(p)
    assert "particle (alpha) swings 0.6 rad" in monitor.check(dm)
    assert monitor.largest()[1] == pytest.approx(0.6, rel=1e-14)
    assert "would go over the top" in SmallAngleMonitor(Params(mu=0.1, d=10.0), 0.1).check(
        Damper(p, alpha_dot0=3.5 * p.w1))


def test_fmu_warns_once_and_sums_up_at_the_end_through_the_fmi_logger(fmu_path):
    """A swing of 0.5 rad (primary alone, no impacts) against the default limit 0.4 rad: one
    warning at the first step carrying the exact error, one summary at fmi2Terminate (the texts
    hold a '%', which the FMU must escape for the host's printf-style logger)."""
    result = run({"mu": 0.0, "theta_dot_0": 0.5 * W2}, stop_time=10.0, output_interval=0.01, fmu=fmu_path)
    warnings = result.meta["warnings"]
    assert len(warnings) == 2
    assert "t = 0.01 s: the primary (theta) swings 0.5 rad" in warnings[0]
    assert f"{100 * frequency_error(0.5):.2g} % slower" in warnings[0]
    assert "largest swings of the run: primary 0.5 rad" in warnings[1]
    assert np.abs(result.data["theta"]).max() == pytest.approx(0.5, rel=1e-3)  # sampled every 0.01 s


def test_fmu_summary_reports_the_largest_envelope_over_the_outputs(fmu_path):
    """The paper's free decay: the particle swings far beyond the small-angle range.  The
    summary's figure is the largest free-swing envelope at the communication points, computed
    here from the recorded outputs."""
    p = Params()
    result = run({"theta_dot_0": 0.7 * W2}, stop_time=20.0, output_interval=0.01, fmu=fmu_path)
    d = result.data
    envelope = np.sqrt(d["alpha"] ** 2 + (d["alpha_dot"] / p.w1) ** 2)[1:].max()
    primary = np.sqrt(d["theta"] ** 2 + (d["theta_dot"] / p.w2) ** 2)[1:].max()
    assert envelope >= np.abs(d["alpha"]).max() > 3.0
    summary = result.meta["warnings"][-1]
    assert f"primary {primary:.3g} rad, particle {envelope:.3g} rad" in summary and "over the top" in summary


def test_fmu_stays_quiet_within_the_limit_or_when_turned_off(fmu_path):
    small = run({"mu": 0.0, "theta_dot_0": 0.3 * W2}, stop_time=5.0, output_interval=0.01, fmu=fmu_path)
    off = run({"mu": 0.0, "theta_dot_0": 0.5 * W2, "angle_limit": 0.0}, stop_time=5.0, output_interval=0.01,
              fmu=fmu_path)
    assert small.meta["warnings"] == [] and off.meta["warnings"] == []


def test_a_restored_state_keeps_the_once_per_run_promise(fmu_path):
    heard = []
    with FmuStepper(fmu_path, {"mu": 0.0, "theta_dot_0": 0.5 * W2}, logger=lambda s, text: heard.append(text)) as st:
        st.advance(0.5)
        saved = st.save()
        st.advance(1.0)
        st.restore(saved)
        st.advance(2.0)
    assert sum("beyond the small-angle limit" in text for text in heard) == 1


def test_instance_names_with_printf_conversions_reach_the_log_intact(fmu_path):
    text = isolated.call("pidamper.benchmarks.fatal_checks:percent_in_instance_name", str(fmu_path))
    assert "damper%s%n%d: mu = -1.0 is not allowed" in text


def test_a_logged_run_keeps_both_warnings_as_notes_at_their_times(fmu_path, tmp_path):
    from pidamper.runlog.logged_run import run_logged
    from pidamper.runlog.mcap_log import read_run

    logged = run_logged({"mu": 0.0, "theta_dot_0": 0.5 * W2}, stop_time=3.0, output_interval=0.01, out_dir=tmp_path,
                        fmu=fmu_path, rrd=False)
    notes = [(t, text) for t, level, text in read_run(logged.mcap)[3] if level == "warning"]
    assert [t for t, _ in notes] == [0.01, 3.0]
    assert "swings 0.5 rad" in notes[0][1] and "largest swings of the run" in notes[1][1]
