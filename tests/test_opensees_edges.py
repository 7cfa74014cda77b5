"""`pidamper cosim --opensees` at its edges (issue 35, item 2): every argument checked before
OpenSees starts, refused with exit status 2 as `<name> = <value> is not allowed: <rule>`; a model
file that fails, exits or makes OpenSees end the process reported as a failure, the logs readable;
pidamper's messages on lines of their own.  Every run is a child process (OpenSeesPy never loads in
the test process: test_opensees_cosim)."""
import csv
import math
import subprocess
import sys
from pathlib import Path

import fmpy
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "opensees"
SHEAR3 = (EXAMPLES / "shear3_elastic.py").read_text()
PULSE = str(EXAMPLES / "pulse.csv")
UNIT = ["-p", "m=15000", "-p", "L1=0.0619", "-p", "d=0.02", "-p", "e=0.5"]
PREFIX = "pidamper cosim --opensees: error: "


def cli(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "pidamper.cli", "cosim", *args], capture_output=True, text=True,
                          cwd=cwd, timeout=600)


def marked(tmp_path, body=SHEAR3):
    """A model file that leaves tmp_path/ran when it runs (so a test sees whether OpenSees started)."""
    path = tmp_path / "model.py"
    path.write_text(f"import pathlib\npathlib.Path({str(tmp_path / 'ran')!r}).touch()\n{body}")
    return path


def refused(done, words):
    """Exit 2, one error line naming the value and the rule, no traceback."""
    assert done.returncode == 2, (done.returncode, done.stdout, done.stderr)
    assert words in done.stderr, done.stderr
    assert "Traceback" not in done.stderr, done.stderr


BEFORE_OPENSEES = [
    (["--stop-time", "0"], "--stop-time = 0.0 is not allowed: a finite number > 0 s"),
    (["--stop-time", "-1"], "--stop-time = -1.0 is not allowed: a finite number > 0 s"),
    (["--stop-time", "nan"], "--stop-time = nan is not allowed: a finite number > 0 s"),
    (["--step", "0"], "--step = 0.0 is not allowed: a finite number > 0 s"),
    (["--step", "-0.01"], "--step = -0.01 is not allowed: a finite number > 0 s"),
    (["--step", "nan"], "--step = nan is not allowed: a finite number > 0 s"),
    (["--step", "2"], "--step = 2.0 is not allowed: at most the stop time (1.0 s)"),
    (["--step", "0.3"], "--stop-time = 1.0 is not allowed: a whole number of steps of 0.3 s"),
    (["--substeps", "0"], "--substeps = 0 is not allowed: an integer >= 1"),
    (["--scale", "nan", "--ground-motion", PULSE], "--scale = nan is not allowed: a finite factor"),
    (["--scale", "inf", "--ground-motion", PULSE], "--scale = inf is not allowed: a finite factor"),
    (["--dof", "0"], "--dof = 0 is not allowed: an integer >= 1"),
    (["-p", "foo=1"], "foo = 1.0 is not allowed: -p takes a parameter of the unit (PendulumImpactDamperUnit): "),
    (["-p", "restitution=2.5"], "restitution = 2.5 is not allowed: an integer, one of 0, 1, 2, 3"),
    (["-p", "restitution=7"], "restitution = 7 is not allowed: an integer, one of 0, 1, 2, 3"),
    (["-p", "impulse_aware=0"], "impulse_aware = 0 is not allowed: the coupling sets it"),
]


@pytest.mark.parametrize("extra, words", BEFORE_OPENSEES)
def test_arguments_are_refused_before_opensees_starts(tmp_path, extra, words):
    """The value and its rule named, exit 2, and the model file never ran."""
    args = {"--node": "3", "--step": "0.01", "--stop-time": "1"}
    for flag in ("--step", "--stop-time"):
        if flag in extra:
            args.pop(flag)
    done = cli("--opensees", str(marked(tmp_path)), *[x for kv in args.items() for x in kv], *UNIT, *extra,
               "--no-log")
    refused(done, PREFIX + words)
    assert not (tmp_path / "ran").exists(), "the model file ran before the refusal"


def test_outputs_that_cannot_be_written_are_refused_before_opensees_starts(tmp_path):
    """A CSV under a file, a log folder that is a file: refused before the run, not after it."""
    (tmp_path / "afile").write_text("")
    for extra, words in ((["--csv-out", str(tmp_path / "afile" / "x.csv"), "--no-log"],
                          f"--csv-out = {str(tmp_path / 'afile' / 'x.csv')!r} is not allowed: a file in a folder "
                          f"({tmp_path / 'afile'} is a file)"),
                         (["--out", str(tmp_path / "afile")],
                          f"--out = {str(tmp_path / 'afile')!r} is not allowed: a folder (it is a file)")):
        done = cli("--opensees", str(marked(tmp_path)), "--node", "3", "--step", "0.01", "--stop-time", "1", *UNIT,
                   *extra)
        refused(done, PREFIX + words)
        assert not (tmp_path / "ran").exists(), "the model file ran before the refusal"


def test_an_unknown_parameter_lists_the_units_parameters(tmp_path):
    """-p foo=1 names foo and lists every parameter the unit FMU declares (the one the coupling
    sets, impulse_aware, aside), not an FMI calling-sequence message."""
    from pidamper import find_fmu

    done = cli("--opensees", str(marked(tmp_path)), "--node", "3", "--step", "0.01", "--stop-time", "1", *UNIT,
               "-p", "foo=1", "--no-log")
    refused(done, PREFIX + "foo = 1.0 is not allowed")
    md = fmpy.read_model_description(str(find_fmu(model="PendulumImpactDamperUnit")))
    names = [v.name for v in md.modelVariables if v.causality == "parameter" and v.name != "impulse_aware"]
    listed = done.stderr.split("(PendulumImpactDamperUnit): ")[1].split(" (")[0].strip()
    assert listed.split(", ") == names, listed
    assert "fmi2Terminate" not in done.stderr


@pytest.mark.parametrize("direction", ["0", "2"])
def test_a_direction_the_model_has_not_is_refused(tmp_path, direction):
    """--direction 0 or 2 on a model of one degree of freedom per node: refused once the model is
    built, before any analysis (no OpenSees index errors, no steps run)."""
    done = cli("--opensees", str(EXAMPLES / "shear3_elastic.py"), "--node", "3", "--step", "0.01", "--stop-time", "1",
               "--ground-motion", PULSE, "--direction", direction, *UNIT, "--no-log")
    refused(done, PREFIX + f"--direction = {direction} is not allowed: a degree of freedom every node of the model "
                           "has, 1..1")
    assert "setR" not in done.stderr and "steps of" not in done.stdout


def test_a_dof_the_node_has_not_is_refused():
    done = cli("--opensees", str(EXAMPLES / "frame2d.py"), "--node", "31", "--dof", "4", "--step", "0.01",
               "--stop-time", "0.1", *UNIT, "--no-log")
    refused(done, PREFIX + "--dof = 4 is not allowed: node 31 has degrees of freedom 1..3")


def read_table(path):
    with open(path) as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array(rows[1:], dtype=float)


def test_a_record_shorter_than_the_run_holds_its_last_value_and_says_so(tmp_path):
    """The record ends (at 1 m/s2) before the stop time: stderr says so and names the held value;
    the run equals the run on the record extended by its last value (what an FMU input does)."""
    short = tmp_path / "short.csv"
    short.write_text("time,a_g\n0.0,0.0\n0.01,0.5\n0.02,1.0\n0.03,1.0\n")
    longer = tmp_path / "longer.csv"
    longer.write_text("time,a_g\n0.0,0.0\n0.01,0.5\n" + "".join(f"{k / 100:.2f},1.0\n" for k in range(2, 31)))
    runs = []
    for record in (short, longer):
        out = tmp_path / f"{record.stem}.out.csv"
        done = cli("--opensees", str(EXAMPLES / "shear3_elastic.py"), "--node", "3", "--step", "0.01",
                   "--stop-time", "0.3", "--ground-motion", str(record), *UNIT, "--csv-out", str(out), "--no-log")
        assert done.returncode == 0, done.stderr
        runs.append((done, read_table(out)))
    (said, (header, held)), (quiet, (_, extended)) = runs
    assert ("the ground-motion record ends at t = 0.03 s, before the stop time 0.3 s: its last value, 1 m/s2, "
            "is held to the end") in said.stderr, said.stderr
    assert "is held" not in quiet.stderr
    assert np.array_equal(held, extended)
    assert abs(held[-1, header.index("x")]) > 1e-4  # the held 1 m/s2 moved the roof


@pytest.mark.parametrize("body, line, last", [
    ("import openseespy.opensees as ops\nops.wipe()\nops.node(1, 0.0\n", 5, "SyntaxError: '(' was never closed"),
    ("import openseespy.opensees as ops\nops.wipe()\nx = 1 / 0\n", 5, "ZeroDivisionError: division by zero"),
    ("def storey(k):\n    raise ValueError(f'storey {k} has no stiffness')\n\nstorey(2)\n", 4,
     "ValueError: storey 2 has no stiffness"),
])
def test_a_model_file_that_fails_is_shown_at_its_line(tmp_path, body, line, last):
    """The user's file and line (the innermost frame in it) and the exception's own line, no
    pidamper traceback."""
    path = marked(tmp_path, body)
    done = cli("--opensees", str(path), "--node", "1", "--step", "0.01", "--stop-time", "1", *UNIT, "--no-log")
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert f'File "{path}", line {line}' in done.stderr and last in done.stderr, done.stderr
    assert "Traceback" not in done.stderr and "pidamper/" not in done.stderr, done.stderr


def test_a_model_file_that_calls_sys_exit_is_a_failure(tmp_path):
    path = marked(tmp_path, SHEAR3 + "import sys\nsys.exit(0)\n")
    done = cli("--opensees", str(path), "--node", "3", "--step", "0.01", "--stop-time", "1", *UNIT,
               "--csv-out", str(tmp_path / "run.csv"), "--no-log")
    assert done.returncode == 2, (done.returncode, done.stdout, done.stderr)
    assert "the model file called sys.exit(0)" in done.stderr and f'File "{path}", line ' in done.stderr, done.stderr
    assert not (tmp_path / "run.csv").exists()


def test_opensees_ending_the_process_is_a_failure(tmp_path):
    """modalDamping, then a node: OpenSees calls exit() (status 0) in the first analysis step.
    Reported, exit 2, no CSV."""
    model = tmp_path / "modal_then_node.py"
    model.write_text(SHEAR3 + "ops.node(9, 0.0)\n")
    done = cli("--opensees", str(model), "--node", "3", "--ground-motion", PULSE, "--step", "0.01",
               "--stop-time", "1", *UNIT, "--csv-out", str(tmp_path / "run.csv"), "--out", str(tmp_path))
    assert done.returncode == 2, (done.returncode, done.stdout, done.stderr)
    assert PREFIX + "OpenSees ended the process (exit status 0) " in done.stderr, done.stderr
    assert not (tmp_path / "run.csv").exists() and "wrote" not in done.stdout


EXIT_MIDWAY = """
import ctypes, sys
from pidamper.opensees import coupling
analyze = coupling.Coupling._analyze
def ending(self, span):
    if self.done == 700:
        ctypes.CDLL(None).exit(0)  # as OpenSees's C code does
    analyze(self, span)
coupling.Coupling._analyze = ending
from pidamper.cli import main
main(sys.argv[1:])
"""


def test_an_exit_in_the_middle_of_the_run_keeps_the_logs(tmp_path):
    """A C exit(0) inside the analysis after 700 steps: exit 2, the time named, and the MCAP reads
    back every step done (701 rows, the first at t = 0), the .rrd written."""
    from pidamper.opensees.log import read_cosim

    model = str(EXAMPLES / "shear3_elastic.py")
    done = subprocess.run([sys.executable, "-c", EXIT_MIDWAY, "cosim", "--opensees", model, "--node", "3",
                           "--ground-motion", PULSE, "--step", "0.005", "--stop-time", "5", *UNIT,
                           "--out", str(tmp_path), "--name", "cut", "--csv-out", str(tmp_path / "cut.csv")],
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 2, (done.returncode, done.stdout, done.stderr)
    assert "OpenSees ended the process (exit status 0) in the co-simulation after 700 of 1000 steps (t = 3.5 s)" \
        in done.stderr, done.stderr
    _, topics = read_cosim(tmp_path / "cut.mcap")
    rows = topics["/opensees/unit[1]"]
    assert len(rows) == 701 and rows[-1]["time"] == pytest.approx(3.5) and all(math.isfinite(r["x"]) for r in rows)
    assert (tmp_path / "cut.rrd").stat().st_size > 0 and not (tmp_path / "cut.csv").exists()


def test_cosim_help_shows_the_opensees_options():
    done = subprocess.run([sys.executable, "-m", "pidamper.cli", "cosim", "--help"], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    for option in ("--master", "--opensees MODEL.py", "--node", "--ground-motion", "--direction", "--substeps",
                   "--csv-out"):
        assert option in done.stdout, option


def test_messages_start_on_a_line_of_their_own():
    """shear3_elastic.py's eigen call leaves OpenSees's warning without a newline; the refusal that
    follows starts a line."""
    done = cli("--opensees", str(EXAMPLES / "shear3_elastic.py"), "--node", "7", "--step", "0.01",
               "--stop-time", "1", *UNIT, "--no-log")
    assert done.returncode == 2 and "VERY SLOW" in done.stderr, done.stderr
    lines = [line for line in done.stderr.splitlines() if "pidamper cosim --opensees" in line]
    assert lines and all(line.startswith(PREFIX) for line in lines), done.stderr
