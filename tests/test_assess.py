"""`pidamper assess`: the whole path on a tiny suite (runs, resume, Parquet, page, figures), the IDA of
the bare building against linearity, a suite of .AT2 files, and what the console says (progress in
lines, NaN with its reason, the page's run count); refusals of bad study files: test_study_file.py."""
import contextlib
import csv
import io
import json
import re
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest

from pidamper.assessment import assess
from pidamper.forcing import ground_motion
from pidamper.cli import main

TINY = """
[study]
name = "tiny"
description = "three short records, three stripes"

[building]
storeys = 2
floor_m = [1.0e5, 0.8e5]
storey_k = [8.0e7, 6.0e7]
zeta_s = 0.02
fidelity = "damped"

[configurations.bare]
mu = 0.0
d = 100.0

[configurations.damper]
mu = 0.05
FR = 0.95
d = 0.01
e = 0.5

[suite]
{suite}

[intensity]
measure = "PGV"
levels = [0.1, 0.15, 0.2, 0.3, 0.45, 0.7]

[damage_states]
A = 0.003
B = 0.006

[hazard]
k0 = 1.0e-3
k = 2.5

[run]
bootstrap = 50
"""
GENERATED = 'generator = "kanai-tajimi"\ncount = 4\nseed = 4\nduration = 3.0\ndt = 0.01\nomega_g = 15.6\n' \
            'zeta_g = 0.6\npga = 1.0'


def write(tmp_path, suite=GENERATED, name="tiny.toml"):
    path = tmp_path / name
    path.write_text(TINY.replace("{suite}", suite))
    return path


@pytest.fixture(scope="module")
def tiny(fmu_dir, tmp_path_factory):
    folder = tmp_path_factory.mktemp("assess")
    study = write(folder)
    out = folder / "out"
    assert main(["assess", str(study), "--out", str(out), "--workers", "2"]) == 0  # DampedShearBuilding2.fmu
    return study, out


def test_the_whole_path_writes_a_page_figures_and_a_tidy_table(tiny):
    study, out = tiny
    page = (out / "README.md").read_text()
    for figure in ("ida.png", "fragility.png"):
        assert f"]({figure})" in page and (out / figure).stat().st_size > 10_000
    table = pq.read_table(out / "runs.parquet").to_pydict()
    assert len(table["key"]) == 4 * 6 * 2 and set(table["configuration"]) == {"bare", "damper"}
    assert all(v > 0 for v in table["drift_ratio"]) and all(s in (1, 2) for s in table["drift_storey"])
    bare = [i for i, c in zip(table["impacts"], table["configuration"]) if c == "bare"]
    assert bare == [0] * 24 and max(i for i, c in zip(table["impacts"], table["configuration"]) if c == "damper") > 0
    # the risk table: one row per damage state, the MAF of each configuration and their ratio
    for state in ("A", "B"):
        assert re.search(rf"^\| {state} \| [0-9.e+-]+ \| [0-9.e+-]+ \| \*\*[0-9.e+-]+\*\* \|$", page, flags=re.M)
    assert "```toml" in page and "pidamper assess" in page


def test_a_second_run_resumes_without_running_again(tiny, fmu_dir):
    study, out = tiny
    before = (out / "runs.csv").read_text()
    rows, _, _ = assess.assess(study, out, fmu=str(fmu_dir / "DampedShearBuilding2.fmu"), progress=False)
    assert (out / "runs.csv").read_text() == before and len(rows) == 48


def test_the_bare_building_scales_linearly_with_intensity(tiny):
    """Linear building, no damper: every demand is proportional to the record's scale factor."""
    study, out = tiny
    table = pq.read_table(out / "runs.parquet").to_pydict()
    per_record = {}
    for rec, level, conf, drift, acc in zip(table["record"], table["level"], table["configuration"],
                                            table["drift_ratio"], table["floor_accel"]):
        if conf == "bare":
            per_record.setdefault(rec, []).append((drift / level, acc / level))
    assert len(per_record) == 4
    for values in per_record.values():
        drifts, accels = np.array(values).T
        assert np.ptp(drifts) <= 1e-12 * drifts.mean() and np.ptp(accels) <= 1e-12 * accels.mean()


def test_records_are_scaled_to_their_stripe(tiny):
    study = assess.load(tiny[0])
    for task in assess.tasks(study)[:6]:
        record = study.records[task["record_index"]]
        assert study.intensity(record.scaled(task["factor"])) == pytest.approx(task["level"], rel=1e-12)


def test_a_suite_of_at2_files(tmp_path):
    folder = tmp_path / "records"
    folder.mkdir()
    for seed in (1, 2):
        rec = ground_motion.kanai_tajimi(2.0, 0.01, 15.6, 0.6, pga=2.0, seed=seed)
        ground_motion.write_at2(folder / f"r{seed}.AT2", rec)
    study = assess.load(write(tmp_path, 'folder = "records"'))
    assert [r.name for r in study.records] == ["r1", "r2"] and len(assess.tasks(study)) == 2 * 6 * 2


def test_the_shipped_study_is_valid_and_small_enough():
    study = assess.load(Path(__file__).parent.parent / "studies" / "three-storey.toml")
    runs = len(assess.tasks(study))
    assert runs == 12 * 20 * 2 and study.period == pytest.approx(0.4992, abs=1e-3)


def test_the_pendulum_primary_works_as_well(tmp_path):
    """storeys = 0: the pendulum primary, its displacement over the storey height as the drift; the
    core and the FMU engines agree (the same model), and without the damper the drift is linear."""
    path = write(tmp_path)
    text = path.read_text().replace("storeys = 2\nfloor_m = [1.0e5, 0.8e5]\nstorey_k = [8.0e7, 6.0e7]\nzeta_s = 0.02",
                                    "storeys = 0\nzeta_s = 0.02\nL2 = 0.5")
    text = text.replace("A = 0.003\nB = 0.006", "A = 0.01\nB = 0.02").replace("d = 0.01", "d = 0.05")
    path.write_text(text)
    study = assess.load(path)
    assert study.period == pytest.approx(2 * 3.141592653589793 * (0.5 / 9.81) ** 0.5)
    rows = [assess.run_task(t, "core") for t in assess.tasks(study)[:4]]
    bare = [r for r in rows if r["configuration"] == "bare"]
    assert bare[1]["drift_ratio"] / bare[1]["level"] == pytest.approx(bare[0]["drift_ratio"] / bare[0]["level"],
                                                                      rel=1e-12)
    assert all(r["drift_storey"] == 1 and r["drift_ratio"] > 0 for r in rows)


@pytest.fixture(scope="module", params=["interpolate", "run"])
def said(request, fmu_dir, tmp_path_factory):
    """A small study with an IDA (2 records x 2 configurations, 3 runs each) and its stripes read off
    the IDA curves or run, through the command line with stdout and stderr not a terminal: (study,
    out, stdout, stderr).  Damage state C is beyond every run (no fit)."""
    folder = tmp_path_factory.mktemp("said")
    study = write(folder, GENERATED.replace("count = 4", "count = 2").replace("duration = 3.0", "duration = 1.0"))
    text = study.read_text().replace("levels = [0.1, 0.15, 0.2, 0.3, 0.45, 0.7]", "levels = [0.1, 0.3, 0.7]")
    text = text.replace("B = 0.006", "B = 0.006\nC = 0.5").replace(
        "[run]", f'[ida]\nfirst = 0.1\nstep = 0.3\nmax_runs = 3\nstripes = "{request.param}"\n\n[run]')
    study.write_text(text)
    out, stdout, stderr = folder / "out", io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        assert main(["assess", str(study), "--out", str(out), "--workers", "1"]) == 0
    return study, out, stdout.getvalue(), stderr.getvalue()


def test_progress_is_said_in_lines_when_stderr_is_not_a_terminal(said):
    """A line as each configuration's IDAs (and stripe runs) are all done, with the tasks done and the
    total; a line as each stage ends."""
    study, out, _, stderr = said
    lines = stderr.splitlines()
    for conf in ("bare", "damper"):
        assert sum(re.fullmatch(rf"pidamper assess: IDA: configuration {conf} done; [34] of 4 IDAs done \(\d+ runs\), "
                                r"\d+ s", line) is not None for line in lines) == 1, stderr
    assert "pidamper assess: IDA: 4 of 4 IDAs to run\n" in stderr and "4 of 4 IDAs done (12 runs)" in stderr
    if "stripes = \"run\"" in study.read_text():  # the 4 runs at 0.1 are the IDAs' first ones
        assert re.search(r"stripe runs: configuration (bare|damper) done; 8 of 8 runs done", stderr)
    for stage in ("IDA runs", "damage-state fits", "page"):
        assert f"pidamper assess: {stage} finished, " in stderr


def test_a_missing_figure_in_the_console_comes_with_its_reason(said):
    """No 'nan' on the console: a damage state without a fit says why, as the page does."""
    _, out, stdout, _ = said
    assert "nan" not in stdout.lower()
    line = next(line for line in stdout.splitlines() if line.startswith("C: "))
    assert line == ("C: MAF bare none (no fit: no run reached it), MAF damper none (no fit: no run reached it); "
                    "ratio damper none (no fit for bare and damper)")
    page = (out / "README.md").read_text()
    assert "| C | none (no fit: no run reached it) | none (no fit: no run reached it) |" in page


def test_the_console_and_the_page_count_the_same_runs(said):
    """Every FMU run is counted once: the IDAs' runs (ida.csv) and the stripe runs, none of which
    runs when the stripes are read off the IDA curves."""
    study, out, stdout, _ = said
    with (out / "ida.csv").open(newline="") as handle:
        ida = sum(len(json.loads(row["runs"])) for row in csv.DictReader(handle))
    stripes = 2 * 2 * 2 if "stripes = \"run\"" in study.read_text() else 0  # at 0.1 the IDA ran them
    console = int(re.match(r"(\d+) runs \(", stdout).group(1))
    page = int(re.search(r"Python [0-9.]+: (\d+) runs \(", (out / "README.md").read_text()).group(1))
    assert console == page == ida + stripes == 12 + stripes


def test_a_journal_counts_only_the_studys_configurations(tmp_path):
    """assess.journaled: a journal copied in from another study (other configurations, its
    [uncertainty] runs) counts only this study's runs; the IDA journal counts the runs of its IDAs."""
    with (tmp_path / "runs.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["key", "configuration"])
        for i, conf in enumerate(["bare", "damper", "damper", "damper@storeys+", "bare@damping-", "other",
                                  "other@storeys+"]):
            writer.writerow([f"k{i}", conf])
    with (tmp_path / "ida.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["key", "configuration", "runs"])
        writer.writerows([["a", "bare", "[1, 2, 3]"], ["b", "other", "[1, 2]"], ["c", "damper", "[1]"]])
    confs = {"bare": {}, "damper": {}}
    assert assess.journaled(tmp_path / "runs.csv", confs) == 3
    assert assess.journaled(tmp_path / "runs.csv", confs, perturbed=True) == 2
    assert assess.journaled(tmp_path / "ida.csv", confs) == 4
    assert assess.journaled(tmp_path / "none.csv", confs) == 0
