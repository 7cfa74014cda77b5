"""Harness: measures against closed forms, forcing signals, the run API and the command line."""
import math
import subprocess
import sys

import numpy as np
import pytest

from pidamper import CoreStepper, forcing, measures, run
from pidamper.running import isolated
from pidamper.cli import main

W2 = math.sqrt(9.81)
PERIOD = 2 * math.pi / W2


class DampedOscillator:
    """Closed-form viscously damped oscillator behind the stepper protocol (test oracle)."""

    def __init__(self, zeta, w=W2, amp=0.3):
        self.zeta, self.w, self.amp, self.t = zeta, w, amp, 0.0
        self.wd = w * math.sqrt(1 - zeta * zeta)

    def advance(self, t):
        self.t = t

    def read(self):
        t, z, w, wd = self.t, self.zeta, self.w, self.wd
        decay = self.amp * math.exp(-z * w * t)
        return decay * math.sin(wd * t), decay * (wd * math.cos(wd * t) - z * w * math.sin(wd * t))

    def save(self):
        return {"t": self.t}

    def restore(self, s):
        self.t = s["t"]

    def discard(self, s):
        pass


@pytest.mark.parametrize("zeta", [0.01, 0.05, 0.3])
def test_damping_ratio_of_a_viscous_oscillator(zeta):
    """Peaks e^{-zeta w t} sin(wd t): delta = 2 pi zeta / sqrt(1 - zeta^2) exactly, every cycle."""
    ratios, peaks = measures.damping_ratio(DampedOscillator(zeta), PERIOD, dt=PERIOD / 37)
    delta = 2 * math.pi * zeta / math.sqrt(1 - zeta * zeta)
    assert ratios["printed"] == pytest.approx(delta / (2 * math.pi), rel=1e-12)
    assert ratios["exact"] == pytest.approx(zeta, rel=1e-12)
    assert ratios["accumulated"] == pytest.approx(3 * delta / (2 * math.pi), rel=1e-12)
    # the peaks are the true maxima, located on the continuous solution (coarse grid of 37 per period)
    wd = W2 * math.sqrt(1 - zeta * zeta)
    t_peak = math.atan(math.sqrt(1 - zeta * zeta) / zeta) / wd
    assert peaks[0].t == pytest.approx(t_peak, abs=1e-7)
    assert peaks[1].t - peaks[0].t == pytest.approx(2 * math.pi / wd, abs=1e-7)


def test_max_amplitude_of_undamped_resonance_equals_the_envelope():
    """mu = 0, cosine forcing from rest: theta = F0/(2 M w2 L2) t sin(w2 t), max at the last crest."""
    F0, n = 0.0981, 10
    params = {"mu": 0.0, "d": 10.0, "F0": F0, "Omega": W2, "phi": math.pi / 2, "theta_dot_0": 0.0}
    best = measures.max_abs_theta(CoreStepper(params), n * PERIOD, PERIOD / 50)
    t = (n - 0.25) * PERIOD  # last crest of |t sin(w t)| before n T: tan(w t) = -w t
    for _ in range(50):
        t -= (math.sin(W2 * t) + W2 * t * math.cos(W2 * t)) / (2 * W2 * math.cos(W2 * t) - W2 * W2 * t * math.sin(W2 * t))
    assert abs(best.theta) == pytest.approx(F0 / (2 * W2) * abs(t * math.sin(W2 * t)), rel=1e-12)
    assert best.t == pytest.approx(t, abs=1e-7)


def test_amplitude_ratio_is_one_without_damper_and_below_one_with():
    base = {"mu": 0.0, "F0": 0.0981, "Omega": W2, "theta_dot_0": 0.0}
    ratio, _, _ = measures.amplitude_ratio(CoreStepper(base), CoreStepper(base), 5 * PERIOD, PERIOD / 40)
    assert ratio == 1.0
    ratio, _, _ = measures.amplitude_ratio(CoreStepper({**base, "mu": 0.02}), CoreStepper(base), 20 * PERIOD,
                                           PERIOD / 40)
    assert 0.0 < ratio < 1.0


def test_sampled_harmonic_is_a_zero_order_hold_of_the_builtin_one():
    """The sampled signal equals the built-in force held over each step: FMU run against the
    core fed the same held values (exact), and the hold error shrinks like the step."""
    params = {"mu": 0.02, "theta_dot_0": 0.0}
    errors = []
    for h in (0.02, 0.01):
        sampled = run(params, forcing.harmonic(0.5, 0.8 * W2, 0.0, sampled=True), stop_time=6.0, output_interval=h)
        exact = run(params, forcing.harmonic(0.5, 0.8 * W2, 0.0), stop_time=6.0, output_interval=h)
        errors.append(np.abs(sampled.data["theta"] - exact.data["theta"]).max())
        core = CoreStepper(params, forcing=forcing.harmonic(0.5, 0.8 * W2, 0.0, sampled=True))
        for t, theta in zip(sampled.data["time"][1:], sampled.data["theta"][1:]):
            core.advance(t)
            assert core.read()[0] == pytest.approx(theta, abs=1e-13)
    assert 1.6 < errors[0] / errors[1] < 2.4  # O(h)


def test_run_result_columns_and_csv(tmp_path):
    res = run({"theta_dot_0": 1.0}, forcing.sweep(0.1, 0.5 * W2, 1.5 * W2, 4.0), stop_time=4.0, output_interval=0.05)
    names = res.data.dtype.names
    assert names[:2] == ("time", "F") and "energy_dissipated" in names
    assert len(res.data) == 81 and res.data["time"][-1] == pytest.approx(4.0)
    t = res.data["time"]
    assert res.data["F"][1] == pytest.approx(0.0)  # held from t = 0
    assert res.data["F"][5] == pytest.approx(0.1 * math.sin(0.5 * W2 * t[4] + W2 / 8.0 * t[4] ** 2))
    path = tmp_path / "r.csv"
    res.write_csv(path)
    back = np.genfromtxt(path, delimiter=",", names=True)
    assert np.array_equal(back["theta"], res.data["theta"])


def test_csv_forcing_validation(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("time,F\n0,0\n0.1,nan\n")
    with pytest.raises(ValueError, match=r"line 3.*finite"):
        forcing.from_csv(bad)
    bad.write_text("t,force\n0,0\n")
    with pytest.raises(ValueError, match="header"):
        forcing.from_csv(bad)
    bad.write_text("time,F\n0,0\n0.2,1\n0.1,2\n")
    with pytest.raises(ValueError, match="line 4.*time 0.1"):
        forcing.from_csv(bad)
    good = tmp_path / "good.csv"
    good.write_text("time,F\n0,0\n1,2\n")
    sig = forcing.from_csv(good)
    assert sig.value(0.25) == pytest.approx(0.5) and sig.args["samples"] == 2


def test_cli_run_writes_csv_and_reports_errors(tmp_path, capsys):
    out = tmp_path / "res.csv"
    assert main(["run", "--forcing", "harmonic", "--periods", "2", "--output-interval", "0.02",
                 "-p", "mu=0.02", "--csv-out", str(out), "--out", str(tmp_path)]) == 0
    assert "impacts" in capsys.readouterr().out and out.is_file()
    assert (tmp_path / "default.mcap").is_file() and (tmp_path / "default.rrd").is_file()  # named by the scene
    bad = tmp_path / "bad.csv"
    bad.write_text("time,F\n0,0\n0.1,inf\n")
    assert main(["run", "--forcing", "csv", "--csv", str(bad), "--out", str(tmp_path)]) == 2
    assert "not allowed" in capsys.readouterr().err
    # an FMU error ends that process's use of the FMU (fmi2Fatal): run it as its own process
    done = subprocess.run([sys.executable, "-m", "pidamper.cli", "run", "-p", "e=1.5", "--periods", "1", "--no-log"],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "e = 1.5 is not allowed" in done.stderr


def test_agrees_with_independent_prototypes_of_the_physics_notes():
    """Figures an independent prototype measured (shared/notes/physics.md, sections 6 and 7),
    to the digits quoted there: forced ratio 0.40 / 0.16 at 10 / 25 periods (w2 = 1, mu = 0.1,
    sine forcing F0/M = 0.01), free-decay damping 0.032 (displacement form, A0 = 0.7 rad)."""
    base = {"g": 1.0, "L2": 1.0, "mu": 0.1, "e": 0.2, "d": 0.1, "FR": 5.0, "F0": 0.01, "Omega": 1.0, "phi": 0.0,
            "theta_dot_0": 0.0}
    for periods, expected in ((10, 0.40), (25, 0.16)):
        ratio, _, bare = measures.amplitude_ratio(CoreStepper(base), CoreStepper({**base, "mu": 0.0}),
                                                  periods * 2 * math.pi, 2 * math.pi / 100)
        assert round(ratio, 2) == expected
        assert abs(bare.theta) == pytest.approx(math.pi * periods / 100, rel=1e-12)  # F0/(2 M w2) t at t = N T
    free = {"mu": 0.1, "FR": 5.0, "d": 0.1, "e": 0.2, "theta_dot_0": 0.7 * W2}
    ratios, _ = measures.damping_ratio(CoreStepper(free), PERIOD)
    assert round(ratios["printed"], 3) == 0.032


def test_a_run_failing_half_way_keeps_its_rows(fmu_path):
    """A force that turns non-finite at t = 1 s: the FMU refuses that step, and the rows
    before it come back with the error (in a child process: the FMU fails with fmi2Fatal)."""
    result = isolated.call("pidamper.benchmarks.fatal_checks:bad_input", str(fmu_path), float("inf"))
    assert "F = inf is not allowed" in result["error"]
    assert result["last_time"] == pytest.approx(1.0) and result["rows"] == 21 and result["finite"]
