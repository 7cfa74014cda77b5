"""Study files of `pidamper assess` (assessment.study_file): every field checked before anything runs.
Each bad field is refused naming its table and field with the rule it breaks, from the Python API
(StudyError) and from the command line (exit status 2, no traceback, no output folder, no run)."""
import math

import numpy as np
import pytest

from pidamper.assessment import assess
from pidamper.cli import main

STUDY = """
[study]
name = "small"

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
generator = "kanai-tajimi"
count = 2
seed = 4
duration = 2.0
dt = 0.01
omega_g = 15.6
zeta_g = 0.6
pga = 1.0

[intensity]
measure = "PGV"
levels = [0.1, 0.3, 0.7]

[damage_states]
A = 0.003

[hazard]
k0 = 1.0e-3
k = 2.5

[run]
bootstrap = 50
"""
BUILDING = STUDY[STUDY.index("[building]"):STUDY.index("[configurations.bare]")]
SET = 'set = "fema-p695-far-field"\nrecords = [1, 2]'
GENERATED = STUDY[STUDY.index('generator = '):STUDY.index("\n\n[intensity]")]
LOSSES = '[losses]\ncomponents = "c.csv"\nfloor_area = 200.0\nreplacement_cost = 1e6\nreplacement_days = 300.0\n'

# (what is changed, the field refused, what its rule says)
CASES = [
    # unknown fields, in every table
    (('name = "small"', 'name = "small"\ntitle = "x"'), "study.title", "the fields are name, description, scope"),
    (("zeta_s = 0.02", "zeta_s = 0.02\nstorey_kk = 1.0"), "building.storey_kk", "the fields are storeys"),
    (("e = 0.5", "e = 0.5\nmass = 3.0"), "configurations.damper.mass", "DampedShearBuilding2.fmu"),
    (("count = 2", "count = 2\nbogus = 1"), "suite.bogus", "the fields are"),
    (('measure = "PGV"', 'measure = "PGV"\nzeta_s = 0.05'), "intensity.zeta_s", "the fields are measure, levels, zeta"),
    (("k = 2.5", "k = 2.5\nk1 = 3.0"), "hazard.k1", "the fields are"),
    (("bootstrap = 50", "bootstrap = 50\nsteps = 0.01"), "run.steps", "the fields are step, bootstrap, seed, beta_m"),
    (("[run]", "[ida]\nfirst = 0.1\nstep = 0.3\nfirts = 0.1\n[run]"), "ida.firts", "the fields are"),
    (("[run]", "[p695]\nsdcc = \"dmax\"\n[run]"), "p695.sdcc", "the fields are"),
    (("[run]", LOSSES + "floor_areas = 1.0\n[run]"), "losses.floor_areas", "the fields are"),
    (("[run]", "[extra]\nx = 1\n[run]"), "extra", "the tables of a study file are"),
    # missing tables and fields
    ((BUILDING, ""), "building", "needs its [building] table"),
    (("storeys = 2\n", ""), "building.storeys", "an integer in 0..10"),
    (("levels = [0.1, 0.3, 0.7]", ""), "intensity.levels", "needs levels"),
    (("k = 2.5", ""), "hazard.k", "needs k0 and k"),
    (("k0 = 1.0e-3\nk = 2.5", "points = [[0.2, 1e-3], [0.4, 1e-4]]"), "hazard.source", "citation"),
    (("k = 2.5", "k = 2.5\npoints = [[0.2, 1e-3], [0.4, 1e-4]]\nsource = \"x\""), "hazard", "one of: curve = "),
    (("[run]", "[ida]\nfirst = 0.1\n[run]"), "ida.step", "needs step"),
    # wrong types: nothing truncated, no boolean taken for a number
    (("bootstrap = 50", 'bootstrap = 50\nstep = "fast"'), "run.step", "a number > 0"),
    (("bootstrap = 50", 'bootstrap = "many"'), "run.bootstrap", "an integer >= 1"),
    (("bootstrap = 50", "bootstrap = true"), "run.bootstrap", "an integer >= 1"),
    (("bootstrap = 50", "bootstrap = 50\nseed = 0.7"), "run.seed", "an integer >= 0"),
    (("bootstrap = 50", "bootstrap = 50\nbeta_m = true"), "run.beta_m", "a modelling dispersion"),
    (("zeta_s = 0.02", "zeta_s = true"), "building.zeta_s", "a finite number"),
    (("storeys = 2", "storeys = 2.0"), "building.storeys", "an integer in 0..10"),
    (("zeta_s = 0.02", "zeta_s = 0.02\np_delta = 0.5"), "building.p_delta", "an integer"),
    (("mu = 0.05", 'mu = "0.05"'), "configurations.damper.mu", "a finite number"),
    (('measure = "PGV"', 'measure = "PGV"\nzeta = true'), "intensity.zeta", "a damping ratio in (0, 1)"),
    (("A = 0.003", "A = true"), "damage_states.A", "drift-ratio limit"),
    (('name = "small"', "name = 5"), "study.name", "text"),
    (("count = 2", 'count = "2"'), "suite.count", "an integer >= 1"),
    ((GENERATED, "folder = 5"), "suite.folder", "text"),
    ((GENERATED, SET.replace("[1, 2]", "5")), "suite.records", "record IDs"),
    ((GENERATED, SET + '\nnormalized = "no"'), "suite.normalized", "true or false"),
    (("k0 = 1.0e-3\nk = 2.5", "curve = 5\nsource = \"x\""), "hazard.curve", "text"),
    (("k0 = 1.0e-3\nk = 2.5", "curve = \"h.csv\""), "hazard.source", "citation"),
    (("k = 2.5", "k = 2.5\nextrapolate = \"loglog\""), "hazard.extrapolate", "only with hazard.curve"),
    (("k0 = 1.0e-3\nk = 2.5", "curve = \"h.csv\"\nsource = \"x\"\nextrapolate = \"linear\""), "hazard.extrapolate",
     'one of "none", "loglog"'),
    (("k0 = 1.0e-3\nk = 2.5", "curve = \"h.csv\"\nsource = \"x\"\nrule = \"simpson\""), "hazard.rule",
     'one of "loglog", "semilog", "intervals"'),
    (("[run]", "[ida]\nfirst = 0.1\nstep = 0.3\nincrement = true\n[run]"), "ida.increment", ">= 0"),
    (("[run]", "[p695]\nratings = [1, 2, 3]\n[run]"), "p695.ratings", "three of A, B, C, D"),
    (("[run]", "[p695]\nCt = 0.028\nx = 0.8\n[run]"), "p695", "Ct and x together, with [ida]"),
    (("[run]", "[ida]\nfirst = 0.1\nstep = 0.3\nstripes = \"interpolate\"\n" + LOSSES + "[run]"), "ida.stripes",
     "never interpolated"),
    (("[run]", "[ida]\nfirst = 0.1\nstep = 0.3\nloo_limit = 0.1\n[run]"), "ida.loo_limit", "only with stripes"),
    (("[run]", "[ida]\nfirst = 0.1\nstep = 0.3\nstripes = \"interpolate\"\nloo_limit = 0\n[run]"), "ida.loo_limit",
     "(> 0"),
    (("[run]", "[p695]\nCt = -0.028\n[run]"), "p695.Ct", "(> 0)"),
    (("[run]", "[p695]\nreasons = [\"good\"]\n[run]"), "p695.reasons", "three texts"),
    (("[run]", LOSSES + "realizations = true\n[run]"), "losses.realizations", "an integer >= 1"),
    # values out of their range
    (("bootstrap = 50", "bootstrap = 50\nstep = 0.0"), "run.step", "a number > 0"),
    (("bootstrap = 50", "bootstrap = 50\nstep = -0.01"), "run.step", "a number > 0"),
    (("bootstrap = 50", "bootstrap = 50\nstep = 5.0"), "run.step", "shorter than the shortest record"),
    (("bootstrap = 50", "bootstrap = -5"), "run.bootstrap", "an integer >= 1"),
    (("bootstrap = 50", "bootstrap = 0"), "run.bootstrap", "an integer >= 1"),
    (("bootstrap = 50", "bootstrap = 50\nseed = -1"), "run.seed", "an integer >= 0"),
    (("levels = [0.1, 0.3, 0.7]", "levels = [0.1, 0.3, 0.3, 0.7]"), "intensity.levels", "no level twice"),
    (("levels = [0.1, 0.3, 0.7]", "levels = [0.7, 0.3]"), "intensity.levels", "ascending"),
    (("A = 0.003", "A = 1.5"), "damage_states.A", "in (0, 1)"),
    (("storeys = 2", "storeys = 11"), "building.storeys", "an integer in 0..10"),
    (('measure = "PGV"', 'measure = "SA"'), "intensity.measure", 'one of "Sa", "Sa_avg", "PGA", "PGV"'),
    (('measure = "PGV"\nlevels = [0.1, 0.3, 0.7]', 'measure = "Sa_avg"\nlevels = [0.1, 0.3, 0.7]\n[p695]'),
     "intensity.measure", "FEMA P-695's margin"),
    (("storey_k = [8.0e7, 6.0e7]", "storey_k = [8.0e7, 6.0e7]\nstorey_law = 1\nstorey_dp_pos = [0.02]"),
     "building.storey_dp_pos", "a list of 2"),
    (("k0 = 1.0e-3", "k0 = -1.0"), "hazard.k0", "a number > 0"),
    (("[run]", LOSSES + "repair_days = [180.0, 30.0]\n[run]"), "losses.repair_days", "ascending"),
    (("[run]", LOSSES + "total_loss = 1.5\n[run]"), "losses.total_loss", "in (0, 1]"),
    (("[run]", LOSSES + "demand_dispersion = -0.1\n[run]"), "losses.demand_dispersion", "in [0, 2)"),
    # a building's per-storey fields: one value per storey
    (("storey_k = [8.0e7, 6.0e7]", "storey_k = [8.0e7]"), "building.storey_k", "a list of 2"),
    (("floor_m = [1.0e5, 0.8e5]", "floor_m = [1.0e5, 0.8e5, 1.0e5]"), "building.floor_m", "a list of 2"),
    (("e = 0.5", "e = 0.5\nstorey_Fy = [1.0e6]"), "configurations.damper.storey_Fy", "a list of 2"),
    (("zeta_s = 0.02", "zeta_s = 0.02\nstorey_height = [3.0]"), "building.storey_height", "a list of 2"),
    (("zeta_s = 0.02", 'zeta_s = 0.02\n"storey[3].Fy" = 1.0e6'), "building.storey[3].Fy", "(k = 1..2)"),
    (("zeta_s = 0.02", 'zeta_s = 0.02\n"storey[1].k" = 9.0e7'), "building.storey_k", "both given"),
    (("e = 0.5", 'e = 0.5\n"storey[2].k" = 9.0e7'), "configurations.damper.storey[2].k", "both given"),
    # fields of the wrong model, or that a study sets itself
    (('fidelity = "damped"', 'fidelity = "dampd"'), "building.fidelity", 'one of "linear", "damped"'),
    (('fidelity = "damped"', 'fidelity = "nonlinear"'), "building.fidelity", "the nonlinear level"),
    (("zeta_s = 0.02", "zeta_s = 0.02\nL2 = 2.0"), "building.L2", "the pendulum primary (storeys = 0) only"),
    (("zeta_s = 0.02", "zeta_s = 0.02\nstorey_h = 4.0"), "building.storey_h", "building.storey_height"),
    (("e = 0.5", "e = 0.5\ntheta_dot_0 = 1.0"), "configurations.damper.theta_dot_0", "starts from rest"),
    (("e = 0.5", "e = 0.5\nF0 = 1.0"), "configurations.damper.F0", "starts from rest"),
    (("mu = 0.05", "mu = 0.05\nstoreys = 3"), "configurations.damper.storeys", "give it in [building]"),
    # the FMU's ranges, blamed on the field that gave the value
    (("zeta_s = 0.02", "zeta_s = 1.5"), "building.zeta_s", "it must lie in [0, 1)"),
    (("e = 0.5", "e = 1.5"), "configurations.damper.e", "it must lie in [0, 1]"),
    (("storey_k = [8.0e7, 6.0e7]", "storey_k = [8.0e7, -6.0e7]"), "building.storey_k[2]", "(> 0)"),
]


@pytest.fixture
def no_runs(monkeypatch):
    """Any run started fails the test."""
    monkeypatch.setattr(assess, "run_table", lambda *a, **k: pytest.fail("a run started"))


def write(tmp_path, change=None):
    path = tmp_path / "study.toml"
    text = STUDY
    if change:
        assert change[0] in text, change
        text = text.replace(*change)
    path.write_text(text)
    return path


@pytest.mark.parametrize("change, field, rule", CASES, ids=[f"{c[1]}: {c[0][1][:30]}" for c in CASES])
def test_a_bad_field_is_refused_by_name_before_any_run(tmp_path, capsys, no_runs, change, field, rule):
    path = write(tmp_path, change)
    with pytest.raises(assess.StudyError) as err:
        assess.load(path)
    assert err.value.name == field and rule in err.value.allowed, str(err.value)
    assert main(["assess", str(path), "--out", str(tmp_path / "out")]) == 2
    said = capsys.readouterr().err
    assert f"{field} = " in said and f"is not allowed: {err.value.allowed}" in said and "Traceback" not in said
    assert not (tmp_path / "out").exists()


def test_the_study_is_valid_and_every_storey_gets_its_own_value(tmp_path):
    """The unchanged study loads, and each per-storey list reaches the FMU for every storey."""
    study = assess.load(write(tmp_path))
    values = assess.tasks(study)[0]["values"]
    assert [values[f"storey[{k}].k"] for k in (1, 2)] == [8.0e7, 6.0e7]
    assert [values[f"floor[{k}].m"] for k in (1, 2)] == [1.0e5, 0.8e5]
    assert study.bootstrap == 50 and study.seed == 0 and study.step is None


@pytest.mark.parametrize("workers", ["0", "-1"])
def test_workers_below_one_are_refused(tmp_path, capsys, no_runs, workers):
    with pytest.raises(SystemExit) as done:
        main(["assess", str(write(tmp_path)), "--out", str(tmp_path / "out"), "--workers", workers])
    assert done.value.code == 2
    said = capsys.readouterr().err
    assert f"--workers: {workers} is not allowed: at least 1" in said and "Traceback" not in said
    assert not (tmp_path / "out").exists()


PENDULUM = ("storeys = 2\nfloor_m = [1.0e5, 0.8e5]\nstorey_k = [8.0e7, 6.0e7]", "storeys = 0\nL2 = 0.5")


@pytest.mark.parametrize("table", ["ida", "p695", "losses"])
def test_what_needs_a_building_is_refused_on_the_pendulum_primary(tmp_path, capsys, no_runs, table):
    """[ida], [p695] and [losses] need a building's collapse and storeys: with storeys = 0 they are
    refused when the file is read, not after the runs."""
    extra = {"ida": "[ida]\nfirst = 0.1\nstep = 0.3\n", "p695": '[p695]\nsdc = "dmax"\n', "losses": LOSSES}[table]
    path = write(tmp_path, PENDULUM)
    path.write_text(path.read_text().replace("[run]", extra + "[run]"))
    with pytest.raises(assess.StudyError) as err:
        assess.load(path)
    assert err.value.name == table and "a building (storeys >= 1)" in err.value.allowed
    assert main(["assess", str(path), "--out", str(tmp_path / "out"), "--engine", "core"]) == 2
    assert not (tmp_path / "out").exists()


def test_what_needs_the_fmu_is_refused_with_the_core_engine(tmp_path, capsys, no_runs):
    path = write(tmp_path)
    text = path.read_text().replace('measure = "PGV"', 'measure = "Sa"')  # (P-695's margin is in Sa)
    path.write_text(text.replace("[run]", '[p695]\nsdc = "dmax"\n[run]'))
    assert main(["assess", str(path), "--out", str(tmp_path / "out"), "--engine", "core"]) == 2
    said = capsys.readouterr().err
    assert "--engine = 'core' is not allowed: [p695] needs a building (storeys >= 1) run through its FMU" in said
    assert not (tmp_path / "out").exists()


def test_a_study_in_sa_avg_scales_its_records_by_sa_avg(tmp_path):
    """measure = "Sa_avg": a record's intensity is its Sa_avg at the building's T1 [g] (the geometric
    mean of Sa over 0.2 T1 .. 3 T1), its label says so."""
    from pidamper.forcing import spectra
    from pidamper.forcing.ground_motion import kanai_tajimi

    path = write(tmp_path, ('measure = "PGV"', 'measure = "Sa_avg"'))
    study = assess.load(path)
    record = kanai_tajimi(4.0, 0.01, 15.6, 0.6, pga=2.0, seed=1)
    assert study.intensity(record) == spectra.sa_avg(record, study.period, study.zeta) / assess.G
    assert study.label.startswith("Sa_avg(0.2 - 3 T1") and study.unit == "g"


def test_the_page_compares_collapse_dispersion_under_sa_and_sa_avg(tmp_path):
    """intensity_dispersion: the same capacities measured by Sa(T1) and by Sa_avg (each record's own
    ratio from its spectrum at the ten periods 0.2 T1 .. 3 T1, recomputed here), the dispersion of
    each (records that collapsed only), and the runs scaled by more than 10 counted."""
    from pidamper.forcing import spectra

    study = assess.load(write(tmp_path, ('measure = "PGV"', 'measure = "Sa"')))
    caps = {0: 0.8, 1: 1.7}
    traces = [{"record_index": i, "configuration": conf, "im_record": 0.1 * (i + 1), "capacity": caps[i],
               "runs": [[0.5, False, None], [caps[i], True, None], [2.5 * (i + 1), True, None]]}
              for conf in study.configurations for i in (0, 1)]
    rows = assess.intensity_dispersion(study, traces)
    ratio = []
    for record in study.records[:2]:
        sa = spectra.response_spectrum(record.accel, record.dt, np.linspace(0.2, 3.0, 10) * study.period,
                                       study.zeta)["Sa"]
        ratio.append(math.exp(np.mean(np.log(sa))) / spectra.sa(record, study.period, study.zeta))
    for conf, row in rows.items():
        ln_sa = [math.log(caps[i] / (0.1 * (i + 1)) * spectra.sa(study.records[i], study.period, study.zeta) / assess.G)
                 for i in (0, 1)]
        ln_avg = [x + math.log(r) for x, r in zip(ln_sa, ratio)]
        assert row["beta_sa"] == pytest.approx(np.std(ln_sa, ddof=1), rel=1e-9)
        assert row["beta_sa_avg"] == pytest.approx(np.std(ln_avg, ddof=1), rel=1e-9)
        # scale factors: 0.5/0.1, 8, 25; 0.5/0.2, 8.5, 25
        assert (row["beyond"], row["runs"], row["largest"]) == (2, 6, pytest.approx(25.0))
    assert "Sa_avg" in "\n".join(assess.dispersion_lines(study, traces))
