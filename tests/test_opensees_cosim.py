"""The damper unit on an OpenSees model (issue 26): pidamper.opensees against our exact building FMU
(elastic and yielding), momentum through the impulses, the command line with its CSV and logs, and
bad input.  Every OpenSees run happens in a child process (running.isolated, hard_exit: see there
why); the exact side is DampedShearBuilding3.fmu."""
import csv
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from pidamper.running import isolated

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "opensees"


def convergence(yielding, steps):
    return isolated.call("pidamper.benchmarks.opensees_cosim:convergence", yielding, list(steps), hard_exit=True,
                         timeout=600)


def test_elastic_building_converges_at_second_order():
    """OpenSees + unit against the exact DampedShearBuilding3: the roof's error falls as h^2 to 1e-4
    of the peak at h = 0.000625 s; every run has the exact run's impacts; the node's momentum jumps
    by the unit's impulse."""
    result = convergence(False, [0.01, 0.0025, 0.000625])
    rows = result["rows"]
    errors = [row["error"] for row in rows]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] <= 1e-4, errors
    order = math.log(errors[1] / errors[2]) / math.log(4.0)
    assert order >= 1.8, (errors, order)
    assert all(row["impacts"] == result["impacts"] for row in rows) and result["impacts"] > 5
    assert max(row["momentum"] for row in rows) <= 1e-9


def test_yielding_building_agrees_within_1e3():
    """Steel01 storeys with P-Delta in OpenSees + unit against DampedShearBuilding3's exact yielding
    storeys: within 1e-3 of the peak at the finer step, better than at the coarser."""
    result = convergence(True, [0.005, 0.00125])
    errors = [row["error"] for row in result["rows"]]
    assert result["hysteretic"] > 0.0  # the storeys yield
    assert errors[1] < errors[0] and errors[1] <= 1e-3, errors


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "pidamper.cli", "cosim", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=600)


UNIT = ["-p", "m=15000", "-p", "L1=0.0619", "-p", "d=0.02", "-p", "e=0.5"]


def test_command_line_writes_the_csv_and_the_logs(tmp_path):
    """The documented command on the shipped example: one CSV row per step with the columns the
    issue names, the MCAP and .rrd written, the roof against DampedShearBuilding3 driven by the same
    record (the FMU samples it at the same communication points) within the coupling's error."""
    import fmpy

    from pidamper import find_fmu
    from pidamper.forcing.ground_motion import read_record
    from pidamper.opensees.log import read_cosim

    h, stop = 0.0025, 3.0
    done = cli("--opensees", str(EXAMPLES / "shear3_elastic.py"), "--node", "3", "--dof", "1", "--ground-motion",
               str(EXAMPLES / "pulse.csv"), "--step", str(h), "--stop-time", str(stop), *UNIT,
               "--csv-out", str(tmp_path / "run.csv"), "--out", str(tmp_path), "--name", "run")
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "run.csv") as handle:
        rows = list(csv.reader(handle))
    assert rows[0][:5] == ["time", "x", "v", "a_abs", "F_s"] and "impacts" in rows[0] and "r" in rows[0]
    assert len(rows) == 1 + int(round(stop / h)) + 1
    table = np.array(rows[1:], dtype=float)
    info, topics = read_cosim(tmp_path / "run.mcap")
    assert info["nodes"] == [3] and len(topics["/opensees/unit[1]"]) == len(table)
    assert (tmp_path / "run.rrd").stat().st_size > 0
    record = read_record(EXAMPLES / "pulse.csv")
    ref = fmpy.simulate_fmu(str(find_fmu(storeys=3)), stop_time=stop, output_interval=h, step_size=h,
                            input=np.array([(t, v) for t, v in zip(record.time, record.accel)],
                                           dtype=[("time", float), ("a_g", float)]),
                            start_values={"mu": 0.05, "FR": 1.0, "d": 0.02, "e": 0.5, "fidelity": 1, "zeta_s": 0.02},
                            output=["floor[3].x", "impacts"])
    x = table[:, rows[0].index("x")]
    assert np.abs(x - ref["floor[3].x"]).max() <= 2e-3 * np.abs(ref["floor[3].x"]).max()
    assert table[-1, rows[0].index("impacts")] == ref["impacts"][-1]


def test_two_units_on_two_floors(tmp_path):
    """A unit on every floor of the top two: both step, each node's momentum jumps by its impulse."""
    done = cli("--opensees", str(EXAMPLES / "shear3_elastic.py"), "--node", "2", "--node", "3",
               "--ground-motion", str(EXAMPLES / "pulse.csv"), "--step", "0.005", "--stop-time", "3", *UNIT,
               "--csv-out", str(tmp_path / "two.csv"), "--no-log")
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "two.csv") as handle:
        header = next(csv.reader(handle))
    assert "unit[1].x" in header and "unit[2].impacts" in header
    assert "unit 2 on node 3" in done.stdout


BAD = [
    (["--node", "7"], "node = 7 is not allowed"),
    (["--node", "3", "--dof", "2"], "dof = 2 is not allowed: node 3 has degrees of freedom 1..1"),
    (["--node", "3", "-p", "M_s=0"], "M_s = 0.0 is not allowed"),
    (["--node", "3", "-p", "M_s=-5"], "M_s = -5.0 is not allowed"),
    (["--node", "3", "-p", "e=2"], "e = 2.0 is not allowed"),
    (["--node", "0"], "node = 0, dof = 1 is not allowed: that degree of freedom is constrained"),
]


@pytest.mark.parametrize("extra, words", BAD)
def test_bad_input_is_named(extra, words):
    done = cli("--opensees", str(EXAMPLES / "shear3_elastic.py"), "--step", "0.01", "--stop-time", "0.1",
               *UNIT, *extra, "--no-log")
    assert done.returncode == 2 and words in done.stderr, done.stderr


def test_an_opensees_failure_names_the_time_and_keeps_the_log(tmp_path):
    """A storey that runs away (no post-yield stiffness, P-Delta far beyond it): OpenSees stops
    converging; the error names the time, the MCAP reads back every step up to there."""
    from pidamper.opensees.log import read_cosim

    model = tmp_path / "runaway.py"
    model.write_text(
        "import openseespy.opensees as ops\n"
        "ops.wipe()\nops.model('basic', '-ndm', 1, '-ndf', 1)\nops.node(0, 0.0)\nops.fix(0, 1)\n"
        "ops.node(1, 0.0)\nops.mass(1, 1e5)\n"
        "ops.uniaxialMaterial('Steel01', 1, 1e4, 8e7, 0.0)\nops.element('zeroLength', 1, 0, 1, '-mat', 1, '-dir', 1)\n"
        "ops.uniaxialMaterial('Elastic', 2, -5e6)\nops.element('zeroLength', 2, 0, 1, '-mat', 2, '-dir', 1)\n")
    done = cli("--opensees", str(model), "--node", "1", "--ground-motion", str(EXAMPLES / "pulse.csv"),
               "--step", "0.01", "--stop-time", "20", "-p", "m=500", "-p", "L1=1.0", "-p", "d=0.05",
               "--out", str(tmp_path), "--name", "runaway")
    assert done.returncode == 2, (done.stdout, done.stderr)
    assert "OpenSees did not converge in the step from t = " in done.stderr, done.stderr
    _, topics = read_cosim(tmp_path / "runaway.mcap")
    rows = topics["/opensees/unit[1]"]
    assert 10 < len(rows) < 2001 and all(math.isfinite(r["x"]) for r in rows)


def test_missing_model_file_is_named(tmp_path):
    done = cli("--opensees", str(tmp_path / "nope.py"), "--node", "1", "--step", "0.01", "--stop-time", "1")
    assert done.returncode == 2 and "no such file" in done.stderr


def test_frame_example_attaches_to_the_floor_through_its_constraint(tmp_path):
    """The 2D frame (plastic hinges, P-Delta columns, gravity held, a rigid floor by equalDOF):
    the unit on the roof's retained joint sees the floor's whole mass (60 t) as M_s, and the run
    under the recorded motion goes through."""
    done = cli("--opensees", str(EXAMPLES / "frame2d.py"), "--node", "31", "--ground-motion",
               str(EXAMPLES / "northridge-mul009.csv"), "--step", "0.01", "--stop-time", "3", "-p", "m=9000",
               "-p", "L1=0.157", "-p", "d=0.05", "-p", "e=0.5", "--no-log")
    assert done.returncode == 0, done.stderr
    assert "(M_s 60000 kg)" in done.stdout, done.stdout
