"""Scenes: every shipped scene runs end to end through `pidamper run` and its logs read back;
invalid scenes are refused with the field, the value and what is allowed; options override fields;
a scene logs only the MCAP topics and Rerun views it asks for."""
import math
import os
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from rerun.chunk import RrdReader

from pidamper.scenes import scene
from pidamper.cli import main
from pidamper.runlog.logged_run import replay
from pidamper.runlog.mcap_log import read_floors, read_run
from pidamper.scenes.scene import SceneError

os.environ.setdefault("RERUN_ANALYTICS", "0")
REQUIRED = ("free-decay", "resonance", "sweep", "ground-motion", "hard-chatter")


def rrd_entities(path):
    """{entity: number of sim_time samples} of a .rrd file."""
    counts = {}
    for chunk in RrdReader(str(path)).stream():
        batch = chunk.to_record_batch()
        entity = batch.schema.metadata[b"rerun:entity_path"].decode().lstrip("/")
        if "sim_time" in batch.column_names:
            counts[entity] = counts.get(entity, 0) + batch.num_rows
        else:
            counts.setdefault(entity, 0)
    return counts


def mcap_topics(path):
    with open(path, "rb") as handle:
        return {channel.topic for channel in make_reader(handle).get_summary().channels.values()}


def write(tmp_path, text, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_the_issue_s_scenes_are_shipped_and_installed():
    assert set(REQUIRED) <= set(scene.shipped())
    for name in REQUIRED:
        assert scene.load(name).description


@pytest.fixture(scope="module")
def ran(fmu_dir, tmp_path_factory):
    """Each shipped scene run by name through the command line, as a user would (each finds the
    FMU of its model in the session's build)."""
    out = tmp_path_factory.mktemp("scenes")
    for name in scene.shipped():
        assert main(["run", name, "--out", str(out), "--csv-out", str(out / f"{name}.csv")]) == 0
    return out


@pytest.mark.parametrize("name", REQUIRED + ("default", "damped-resonance", "large-swing"))
def test_each_shipped_scene_runs_end_to_end_and_its_logs_read_back(ran, name):
    sc = scene.load(name)
    info, states, impacts, notes = read_run(ran / f"{name}.mcap")
    assert info["scene"]["name"] == name and info["scene"]["description"] == sc.description
    t = np.array([s["time"] for s in states])
    h = sc.output_interval
    assert t[0] == 0.0 and t[-1] == pytest.approx(sc.stop_time, abs=1e-12)
    assert np.all(np.diff(t) <= h * (1 + 1e-9)) and len(t) == math.ceil(sc.stop_time / h - 1e-9) + 1
    last = states[-1]
    # the energy balance closes at the end of every scene: E0 + W_in - E = impact + dashpot losses
    balance = states[0]["energy"] + last["work_in"] - last["energy"]
    assert balance == pytest.approx(last["energy_dissipated"] + last["energy_viscous"], abs=1e-9 * max(1.0, states[0]["energy"], last["work_in"]))
    assert last["impacts"] > 0 and len(impacts) == last["impacts"]  # every impact is logged individually
    assert notes[-1][2].startswith("run complete")
    series = rrd_entities(ran / f"{name}.rrd")
    assert series["plots/angles/theta"] == len(states)
    csv = np.genfromtxt(ran / f"{name}.csv", delimiter=",", names=True)
    assert csv.dtype.names == ("time", "F", "a_g") + tuple(sc.outputs)
    assert np.array_equal(csv["theta"], [s["theta"] for s in states])


def test_scenes_exercise_what_they_are_named_for(ran):
    def table(name):
        return np.genfromtxt(ran / f"{name}.csv", delimiter=",", names=True)

    chatter = table("hard-chatter")
    stuck = chatter["contact"] != 0
    longest = max(len(run) for run in "".join("1" if s else "0" for s in stuck).split("0"))
    assert stuck.mean() > 0.5 and longest * 0.01 > 0.4  # long sticking phases (half a period is 1.0 s)
    ground = table("ground-motion")
    assert np.all(ground["F"] == 0) and np.abs(ground["a_g"]).max() == pytest.approx(2.0, rel=1e-6)
    sweep = table("sweep")
    assert sweep["F"].std() > 0.05 and np.all(sweep["a_g"] == 0)
    info = read_run(ran / "resonance.mcap")[0]  # the FMU's built-in drive F0 sin(Omega t + phi), at w2
    p = info["parameters"]
    assert (p["F0"], p["Omega"], p["phi"]) == (0.0981, math.sqrt(9.81), math.pi / 2)
    assert table("resonance")["work_in"][-1] > 0.01


def test_free_decay_logs_only_the_views_it_asks_for(ran):
    series = rrd_entities(ran / "free-decay.rrd")
    assert not any(e.startswith("plots/force") for e in series)  # its scene leaves the input plot out
    assert "plots/force/F" in rrd_entities(ran / "resonance.rrd")


def test_a_scene_file_with_topic_and_view_subsets(fmu_path, tmp_path):
    path = write(tmp_path, """
        description = "subset"
        [parameters]
        theta_dot_0 = 0.8
        [run]
        stop_time = 2.0
        output_interval = 0.02
        [outputs]
        record = ["theta", "impacts"]
        [log]
        mcap_topics = ["/damper/state", "/run/notes"]
        rerun_views = ["angles"]
    """, "subset.toml")
    assert main(["run", str(path), "--fmu", str(fmu_path), "--out", str(tmp_path), "--csv-out",
                 str(tmp_path / "subset.csv")]) == 0
    assert mcap_topics(tmp_path / "subset.mcap") == {"/damper/state", "/run/notes"}
    info, states, impacts, notes = read_run(tmp_path / "subset.mcap")
    assert len(states) == 101 and len(impacts) == 0 and states[-1]["impacts"] > 0
    series = rrd_entities(tmp_path / "subset.rrd")
    assert {"plots/angles/theta", "plots/angles/alpha", "plots/angles/impacts"} <= set(series)
    assert not any(e.startswith(("plots/velocities", "plots/energy", "plots/force", "pendulum")) for e in series)
    header = (tmp_path / "subset.csv").read_text().splitlines()[0]
    assert header == "time,F,a_g,theta,impacts"


def test_options_override_scene_fields(fmu_path, tmp_path, capsys):
    assert main(["run", "resonance", "--fmu", str(fmu_path), "--no-log", "--periods", "1.5", "--output-interval",
                 "0.05", "--omega", "2.5", "-p", "mu=0.05"]) == 0
    text = capsys.readouterr().out
    period = 2 * math.pi / math.sqrt(9.81)
    assert f"to t = {1.5 * period:.6g} s" in text and "steps of 0.05 s" in text
    assert "'Omega': 2.5" in text


def test_a_recorded_accelerogram_runs_from_a_scene_file(fmu_path, tmp_path):
    """The documented way to run a recorded ground motion: a CSV time,a_g next to the scene."""
    t = np.arange(0.0, 3.0001, 0.01)
    np.savetxt(tmp_path / "record.csv", np.column_stack([t, 1.5 * np.sin(7.0 * t)]), delimiter=",",
               header="time,a_g", comments="")
    path = write(tmp_path, '[forcing]\nkind = "csv"\nfile = "record.csv"\n[run]\nstop_time = 3.0\n'
                           'output_interval = 0.01\n[log]\nmcap = false\nrrd = false\n', "quake.toml")
    assert main(["run", str(path), "--fmu", str(fmu_path), "--csv-out", str(tmp_path / "q.csv")]) == 0
    q = np.genfromtxt(tmp_path / "q.csv", delimiter=",", names=True)
    assert np.allclose(q["a_g"][1:], 1.5 * np.sin(7.0 * q["time"][:-1]), atol=1e-12) and np.all(q["F"] == 0)
    assert not (tmp_path / "quake.mcap").exists()


@pytest.mark.parametrize("text, field, value, allowed", [
    ("[parameters]\nmass = 2.0\n", "parameters.mass", "2.0", "FMU parameters are g, M, mu"),
    ("[parameters]\nmu = \"big\"\n", "parameters.mu", "'big'", "a finite number"),
    ("[forcing]\nkind = \"square\"\n", "forcing.kind", "'square'", "one of none, harmonic, sweep"),
    ("[forcing]\nkind = \"harmonic\"\npga = 1.0\n", "forcing.pga", "1.0", "takes F0, Omega"),
    ("[forcing]\nkind = \"csv\"\n", "forcing.file", "None", "a csv forcing needs its file"),
    ("[run]\nstop_time = -1.0\n", "run.stop_time", "-1.0", "it must be > 0"),
    ("[run]\nstop_time = 1.0\nperiods = 2\n", "run", "'stop_time and periods'", "give one of them"),
    ("[run]\nfidelity = \"quantum\"\n", "run.fidelity", "'quantum'", "one of linear, damped, coupled, nonlinear"),
    ("[outputs]\nrecord = [\"theta\", \"speed\"]\n", "outputs.record", "'speed'", "FMU outputs are theta"),
    ("[log]\nmcap_topics = [\"/nope\"]\n", "log.mcap_topics", "'/nope'", "one of /damper/state"),
    ("[log]\nrerun_views = [\"spectrum\"]\n", "log.rerun_views", "'spectrum'", "one of angles"),
    ("[log]\nrrd = \"yes\"\n", "log.rrd", "'yes'", "true or false"),
    ("colour = \"red\"\n", "colour", "'red'", "the top-level fields are"),
    ("[run\n", "file", "'TOML'", "it must be valid TOML"),
    ("[parameters]\nstoreys = 3\nstorey_k = [1e8, 1e8]\n", "parameters.storey_k", "[100000000.0, 100000000.0]",
     "a list of storeys = 3 numbers"),  # storey 3 used to be left at the FMU's default
    ("[parameters]\nstoreys = 3\n\"storey[4].k\" = 1e8\n", "parameters.storey[4].k", "100000000.0",
     "the building's storeys are 1..3"),
    ("[parameters]\nstorey_k = 1e8\n", "parameters.storey_k", "100000000.0", "give storeys >= 1 with it"),
    ("[parameters]\nstoreys = 11\n", "parameters.storeys", "11", "an integer in 0..10"),
    ("[forcing]\nkind = \"fema-p695\"\ncomponent = \"c\"\n", "forcing.component", "'c'", "'a' or 'b'"),
    ("[forcing]\nkind = \"fema-p695\"\nset = \"mine\"\n", "forcing.set", "'mine'", "one of fema-p695-far-field"),
    ("[parameters]\nstoreys = 3\nstorey_law = 1.5\n", "parameters.storey_law", "1.5", "an integer"),
    ("[parameters]\nstorey_dp_pos = 0.02\n", "parameters.storey_dp_pos", "0.02", "give storeys >= 1 with it"),
])
def test_invalid_scenes_are_refused_with_field_value_and_what_is_allowed(tmp_path, text, field, value, allowed):
    path = write(tmp_path, text)
    with pytest.raises(SceneError) as err:
        scene.load(path)
    message = str(err.value)
    assert f"{field} = {value} is not allowed" in message and allowed in message and str(path) in message


def test_unknown_scene_names_list_the_shipped_ones(tmp_path, capsys):
    with pytest.raises(SceneError, match="one of the shipped scenes: .*damped-resonance, default, free-decay"):
        scene.load("no-such-scene")
    assert main(["run", "no-such-scene", "--no-log"]) == 2
    assert "no-such-scene" in capsys.readouterr().err
    assert not list(Path(tmp_path).iterdir())


def test_a_bad_override_is_refused_like_a_bad_field(capsys):
    assert main(["run", "free-decay", "--no-log", "--stop-time", "-3"]) == 2
    assert "run.stop_time = -3.0 is not allowed: it must be > 0" in capsys.readouterr().err


def test_the_guide_s_scene_examples_are_valid_scenes():
    guide = (Path(__file__).parents[1] / "docs" / "guide" / "scenes.md").read_text()
    blocks = guide.split("```toml\n")[1:]
    assert len(blocks) >= 2
    for block in blocks:
        sc = scene.parse(scene.tomllib.loads(block.split("```")[0]), "docs/guide/scenes.md")
        assert sc.stop_time > 0
        if sc.forcing["kind"] != "csv":  # the csv example names a user's file
            assert sc.make_forcing().kind == sc.forcing["kind"]


def test_a_missing_forcing_file_is_named_with_where_it_was_looked_for(tmp_path):
    sc = scene.load(write(tmp_path, '[forcing]\nkind = "csv"\nfile = "missing.csv"\n'))
    with pytest.raises(SceneError, match=f"forcing.file = 'missing.csv' is not allowed: .*{tmp_path / 'missing.csv'}"):
        sc.make_forcing()


@pytest.mark.parametrize("n", [3, 10])
def test_building_scenes_with_and_without_the_damper(ran, n):
    """The building scenes: the same ground motion, every floor recorded, the damper's impacts and
    losses only where it is, the energy balance closed, and the logs read back."""
    def table(name):
        return np.genfromtxt(ran / f"{name}.csv", delimiter=",", names=True, deletechars="")

    damped, bare = table(f"building-{n}"), table(f"building-{n}-bare")
    assert np.array_equal(damped["a_g"], bare["a_g"]) and np.abs(bare["a_g"]).max() == pytest.approx(3.0, rel=1e-6)
    for t in (damped, bare):
        assert {f"floor[{n}].x", f"floor[{n}].a", f"storey[{n}].drift", "base_shear"} <= set(t.dtype.names)
        assert f"floor[{n + 1}].x" not in t.dtype.names
        assert np.array_equal(t["x"], t[f"floor[{n}].x"])  # the damper hangs from the top floor
        drift = t[f"floor[{n}].x"] - t[f"floor[{n - 1}].x"]
        assert np.allclose(t[f"storey[{n}].drift"], drift, rtol=0, atol=1e-15)
        loss = t["energy_dissipated"][-1] + t["energy_viscous"][-1]
        assert t["energy"][0] + t["work_in"][-1] - t["energy"][-1] == pytest.approx(loss, rel=1e-9)
    assert damped["impacts"][-1] > 10 and damped["energy_dissipated"][-1] > 0
    assert bare["impacts"][-1] == 0 and bare["energy_dissipated"][-1] == 0
    states = read_run(ran / f"building-{n}.mcap")[1]
    assert len(states) == len(damped) and states[-1]["impacts"] == damped["impacts"][-1]
    floors = read_floors(ran / f"building-{n}.mcap")  # every floor in the MCAP and the .rrd
    assert floors["x"].shape == (len(damped), n) and np.array_equal(floors["time"], damped["time"])
    for k in range(1, n + 1):
        assert np.array_equal(floors["x"][:, k - 1], damped[f"floor[{k}].x"])
        assert np.array_equal(floors["drift"][:, k - 1], damped[f"storey[{k}].drift"])
    assert np.array_equal(floors["base_shear"], damped["base_shear"])
    assert rrd_entities(ran / f"building-{n}.rrd")[f"plots/floors/floor_{n}"] == len(damped)
    assert read_floors(ran / "default.mcap") is None  # no building, no floors topic


def test_building_replay_carries_the_floors(ran, tmp_path):
    out = tmp_path / "replay.rrd"
    replay(ran / "building-3.mcap", out)
    live, again = rrd_entities(ran / "building-3.rrd"), rrd_entities(out)
    assert {e: c for e, c in again.items() if e.startswith("plots/floors")} == \
        {e: c for e, c in live.items() if e.startswith("plots/floors")} != {}


def test_the_yielding_scenes_yield_and_the_collapse_scene_stops_at_its_collapse(ran):
    """yielding-3 and its bare twin yield (the bare one to a first-storey ductility of about 4, the
    damper lowers it), and so does the twin under Rayleigh damping on the tangent stiffness, whose
    dashpots take less; collapse-3 ends at its collapse, with the drift ratio at the limit."""
    def table(name):
        return np.genfromtxt(ran / f"{name}.csv", delimiter=",", names=True)

    yield_drift = 6.0e5 / 8.0e7 / 3.0  # storey 1's yield drift ratio
    bare, damped, collapse = table("yielding-3-bare"), table("yielding-3"), table("collapse-3")
    tangent = table("yielding-3-tangent")  # the bare twin with Rayleigh damping on the tangent stiffness
    ductility = bare["storey1drift_ratio_max"][-1] / yield_drift
    assert 3.0 < ductility < 5.0
    assert damped["storey1drift_ratio_max"][-1] < bare["storey1drift_ratio_max"][-1]
    assert tangent["energy_viscous"][-1] < bare["energy_viscous"][-1]  # yielding storeys lose their dashpots
    for d in (bare, damped, tangent):
        assert d["energy_hysteretic"][-1] > 0 and not d["collapsed"].any()
        balance = d["work_in"][-1] - d["energy"][-1] - d["energy_dissipated"][-1] - d["energy_viscous"][-1]
        assert balance == pytest.approx(d["energy_hysteretic"][-1], rel=1e-9)
    assert collapse["collapsed"][-1] == 1 and collapse["time"][-1] < 20.0
    assert collapse["storey1drift_ratio_max"][-1] == pytest.approx(0.10, rel=1e-12)


# ---- pidamper run -p: the FMU's names and per-storey lists (issue 35, item 4) ----------------

def scene_of(*argv):
    """The scene `pidamper run ARGV` would run (no FMU involved)."""
    from pidamper.cli import parser
    from pidamper.scenes.command import scene_from_args

    return scene_from_args(parser().parse_args(["run", *argv]))


@pytest.mark.parametrize("given", ["storey[1].Fy=1e5", "storey_Fy=[1e5, 5e5, 3e5]", "storey_Fy=[1e5,5e5,300000]",
                                   " storey_Fy = [1.0e5, 5.0e5, 3.0e5] "])
def test_p_takes_the_fmu_s_names_and_the_scene_files_per_storey_lists(given):
    """Whatever a scene file says, -p says: storey 1's yield force by its FMU name or as the list of
    the scene file (storey 1 first); the other storeys keep the scene's."""
    values = scene_of("yielding-3", "-p", given).start_values
    assert [values[f"storey[{k}].Fy"] for k in (1, 2, 3)] == [1e5, 5e5, 3e5]
    assert scene_of("yielding-3").start_values["storey[1].Fy"] == 6e5
    assert scene_of("yielding-3", "-p", "storey_Fy=2e5").start_values["storey[3].Fy"] == 2e5


def test_p_integer_fields_as_a_scene_file_writes_them():
    """p_delta and restitution are integers in a scene file; -p p_delta=0 used to be read as 0.0
    and refused ("an integer")."""
    assert scene_of("yielding-3", "-p", "p_delta=0").start_values["p_delta"] == 0
    assert scene_of("resonance", "-p", "restitution=0").start_values["restitution"] == 0


def test_a_storey_s_fmu_name_overrides_the_list_in_a_scene_file_and_on_the_command_line(tmp_path):
    path = write(tmp_path, '[parameters]\nstoreys = 3\nstorey_Fy = [6e5, 5e5, 3e5]\n"storey[2].Fy" = 1e6\n')
    values = scene.load(path).start_values
    assert [values[f"storey[{k}].Fy"] for k in (1, 2, 3)] == [6e5, 1e6, 3e5]
    # a list given with -p replaces the scene's list and its storey[k] entries alike
    values = scene_of(str(path), "-p", "storey_Fy=[1e5, 2e5, 3e5]").start_values
    assert [values[f"storey[{k}].Fy"] for k in (1, 2, 3)] == [1e5, 2e5, 3e5]


def test_p_storey_1_by_its_fmu_name_reaches_the_fmu(fmu_dir, tmp_path):
    """The same run, storey 1's yield force given by its FMU name and by the list: bit for bit."""
    tables = {}
    for name, given in (("own", "storey[1].Fy=1e5"), ("list", "storey_Fy=[1e5, 5e5, 3e5]"), ("scene", "mu=0.05")):
        csv = tmp_path / f"{name}.csv"
        assert main(["run", "yielding-3", "--no-log", "--stop-time", "1", "-p", given, "--csv-out", str(csv)]) == 0
        tables[name] = csv.read_text()
    assert tables["own"] == tables["list"] != tables["scene"]


@pytest.mark.parametrize("scene_name, given, expected", [
    ("yielding-3", "bogus=1", ["-p bogus = 1 is not allowed", "FMU parameters are g, M, mu", "storey[k].Fy"]),
    ("yielding-3", "Fy=1e6", ["-p Fy = 1000000.0 is not allowed: did you mean storey_Fy, storey[1].Fy"]),
    ("yielding-3", "storey[1].fy=1e6", ["-p storey[1].fy = 1000000.0 is not allowed: did you mean storey[1].Fy"]),
    ("yielding-3", "storey[4].Fy=1e6", ["-p storey[4].Fy = 1000000.0 is not allowed: the building's storeys are 1..3"]),
    ("yielding-3", "storey_Fy=[6e5, 5e5]", ["-p storey_Fy = [600000.0, 500000.0] is not allowed",
                                            "a list of storeys = 3 numbers (storey 1 first), not 2"]),
    ("yielding-3", "storey_Fy=[6e5, 5e5, \"x\"]", ["-p storey_Fy[3] = 'x' is not allowed: a finite number"]),
    ("yielding-3", "fidelity=1", ["-p fidelity = 1 is not allowed: the level is run.fidelity"]),
    ("resonance", "storey_k=1e8", ["-p storey_k = 100000000.0 is not allowed: a building's parameter: give storeys"]),
    ("resonance", "storey[1].k=1e8", ["-p storey[1].k = 100000000.0 is not allowed: a building's parameter"]),
    ("resonance", "mu=nan", ["-p mu = nan is not allowed: a finite number"]),
])
def test_p_refuses_a_name_or_value_the_fmu_does_not_take_before_it_runs(monkeypatch, capsys, scene_name, given,
                                                                         expected):
    """Refused with exit status 2, naming the -p field (and the closest names), before any FMU runs
    (resonance -p storey_k=1e8 used to reach fmpy: "The start values ... could not be set", exit 1)."""
    from pidamper.scenes import command

    def no_run(*args, **kwargs):
        raise AssertionError("the FMU ran")

    monkeypatch.setattr(command, "run", no_run)
    monkeypatch.setattr(command, "run_logged", no_run)
    assert main(["run", scene_name, "--no-log", "-p", given]) == 2
    err = capsys.readouterr().err
    assert f"pidamper run {scene_name}: " in err
    for text in expected:
        assert text in err


def test_p_values_that_are_no_number_nor_list_are_refused_by_the_parser(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["run", "yielding-3", "--no-log", "-p", "storey_Fy=6e5,5e5"])
    assert exit_.value.code == 2
    assert "'6e5,5e5' is not a number or a list of numbers as a scene file writes it" in capsys.readouterr().err


def test_the_deteriorating_scenes_collapse_by_sidesway_before_the_drift_guard(ran):
    """imk-3 and its bare twin (IMKBilin storeys, P-Delta, a FEMA P-695 record): each run stops at the
    building's own collapse, by sidesway of storey 1, below the drift ratio guard collapse_drift =
    0.3; the storeys' hysteretic energy closes the balance up to there."""
    for name in ("imk-3", "imk-3-bare"):
        d = np.genfromtxt(ran / f"{name}.csv", delimiter=",", names=True)
        _, _, _, notes = read_run(ran / f"{name}.mcap")
        assert d["collapsed"][-1] == 1 and d["time"][-1] < 10.0
        assert 0.05 < d["storey1drift_ratio_max"][-1] < 0.3
        assert any("storey 1 lost its lateral strength under P-Delta (sidesway)" in text for _, _, text in notes)
        balance = d["work_in"][-1] - d["energy"][-1] - d["energy_dissipated"][-1] - d["energy_viscous"][-1]
        assert balance == pytest.approx(d["energy_hysteretic"][-1], rel=1e-9)
