"""Run logs: MCAP and .rrd round trips, replay equality, impacts, runs that stop half-way."""
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from rerun.chunk import RrdReader

from pidamper import CoreStepper, forcing
from pidamper.running import isolated
from pidamper.runlog.logged_run import replay, run_logged
from pidamper.runlog.mcap_log import read_run
from pidamper.runlog.schema import STATE_FIELDS, to_ns
from pidamper.runlog.rerun_log import MARKERS, SERIES

os.environ.setdefault("RERUN_ANALYTICS", "0")
W2 = math.sqrt(9.81)
PERIOD = 2 * math.pi / W2
SCENE = {"mu": 0.02, "theta_dot_0": 0.0, "F0": 0.0981, "Omega": W2}
EXTRA = forcing.harmonic(0.03, 0.7 * W2, 0.1, sampled=True)  # exercises the F column


@pytest.fixture(scope="module")
def logged(fmu_path, tmp_path_factory):
    out = tmp_path_factory.mktemp("logs")
    return run_logged(SCENE, EXTRA, stop_time=12 * PERIOD, output_interval=PERIOD / 100, out_dir=out, fmu=fmu_path,
                      block=300)


def rrd_series(path):
    """{entity: (times ns, values)} of every Scalars entity, sorted by time."""
    parts = {}
    for chunk in RrdReader(str(path)).stream():
        batch = chunk.to_record_batch()
        if "Scalars:scalars" not in batch.column_names or "sim_time" not in batch.column_names:
            continue
        entity = batch.schema.metadata[b"rerun:entity_path"].decode().lstrip("/")
        t = batch.column("sim_time").cast("int64").to_numpy()
        v = np.array([row[0] for row in batch.column("Scalars:scalars").to_pylist()], dtype=np.float64)
        parts.setdefault(entity, []).append((t, v))
    out = {}
    for entity, pieces in parts.items():
        t = np.concatenate([p[0] for p in pieces])
        v = np.concatenate([p[1] for p in pieces])
        order = np.argsort(t, kind="stable")
        out[entity] = (t[order], v[order])
    return out


def test_mcap_holds_every_value_bit_for_bit(logged):
    data = logged.result.data
    info, states, impacts, notes = read_run(logged.mcap)
    assert len(states) == len(data)
    for name in STATE_FIELDS:
        assert np.array_equal(states[name], data[name]), name
    with open(logged.mcap, "rb") as handle:
        reader = make_reader(handle)
        summary = reader.get_summary()
        assert {c.compression for c in summary.chunk_indexes} == {"zstd"}
        stamps = [msg.log_time for _, ch, msg in reader.iter_messages(topics=["/damper/state"])]
    assert np.array_equal(np.array(stamps), to_ns(data["time"]))
    assert info["start_values"]["mu"] == 0.02 and info["forcing"]["kind"] == "harmonic"
    assert info["parameters"]["FR"] == 5.0 and len(info["fmu"]["sha256"]) == 64
    assert {"pythonfmu", "fmpy", "rerun-sdk", "mcap"} <= set(info["versions"])


def test_rrd_holds_every_value_bit_for_bit(logged):
    data = logged.result.data
    series = rrd_series(logged.rrd)
    for entity, field, _ in SERIES:
        t, v = series[entity]
        assert np.array_equal(t, to_ns(data["time"])), entity
        assert np.array_equal(v, data[field].astype(np.float64)), entity


def test_impact_messages_match_the_fmu(logged):
    data = logged.result.data
    _, _, impacts, _ = read_run(logged.mcap)
    assert logged.impacts_unrecorded == 0
    assert len(impacts) == data["impacts"][-1] > 20
    assert np.array_equal(impacts["index"], np.arange(1, len(impacts) + 1))
    # the same run on the physics core, its impact times taken from the core's own callback
    core = CoreStepper(SCENE, forcing=EXTRA)
    times = []
    core.core.on_impact = lambda t, *rest: times.append(t)
    for t in data["time"][1:]:
        core.advance(t)
    assert np.array_equal(impacts["t"], np.array(times))
    markers = rrd_series(logged.rrd)[MARKERS]
    assert np.array_equal(markers[0], to_ns(impacts["t"])) and np.array_equal(markers[1], impacts["theta"])


def _rerun_cli():
    return shutil.which("rerun") or str(Path(sys.executable).with_name("rerun"))


def test_replay_equals_the_live_recording(logged, tmp_path):
    out = tmp_path / "replay.rrd"
    info = replay(logged.mcap, out)
    assert info["recording_id"] == RrdReader(str(out)).recordings()[0].recording_id
    done = subprocess.run([_rerun_cli(), "rrd", "compare", "--unordered", str(logged.rrd), str(out)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]


def test_replay_differs_when_the_data_differ(logged, tmp_path):
    """The comparison is not vacuous: a replay with one state value changed is reported."""
    import pidamper.runlog.logged_run as lr

    original = lr.read_run

    def tampered(path):
        info, states, impacts, notes = original(path)
        states["theta"][5] += 1e-12
        return info, states, impacts, notes

    lr.read_run = tampered
    try:
        replay(logged.mcap, tmp_path / "bad.rrd")
    finally:
        lr.read_run = original
    done = subprocess.run([_rerun_cli(), "rrd", "compare", "--unordered", str(logged.rrd), str(tmp_path / "bad.rrd")],
                          capture_output=True, text=True)
    assert done.returncode != 0


def test_impacts_beyond_the_record_are_counted_and_said(fmu_path, tmp_path):
    run = run_logged({"theta_dot_0": 0.7 * W2}, stop_time=6 * PERIOD, output_interval=2 * PERIOD, out_dir=tmp_path,
                     fmu=fmu_path, rrd=False)
    _, _, impacts, notes = read_run(run.mcap)
    assert run.impacts_unrecorded > 0
    assert len(impacts) + run.impacts_unrecorded == run.result.data["impacts"][-1]
    warned = [n for n in notes if n[1] == "warning"]
    assert any("not recorded individually" in text for _, _, text in warned)


def test_failed_run_keeps_readable_logs(fmu_path, tmp_path):
    error = isolated.call("pidamper.benchmarks.fatal_checks:logged_failure", str(fmu_path), str(tmp_path))
    assert error is not None and "F = inf is not allowed" in error
    info, states, _, notes = read_run(tmp_path / "run.mcap")
    assert states["time"][-1] == pytest.approx(1.0) and np.isfinite(states["theta"]).all()
    assert notes[-1][1] == "error" and "F = inf is not allowed" in notes[-1][2]
    with open(tmp_path / "run.mcap", "rb") as handle:
        assert make_reader(handle).get_summary() is not None  # closed properly
    series = rrd_series(tmp_path / "run.rrd")
    assert np.array_equal(series["plots/angles/theta"][1], states["theta"])


def _start_long_run(fmu_path, out):
    cmd = [sys.executable, "-m", "pidamper.cli", "run", "--fmu", str(fmu_path), "--out", str(out),
           "--periods", "100000", "--output-interval", "0.005", "--name", "run"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while time.time() < deadline:  # until the MCAP holds a few chunks
        mcap = out / "run.mcap"
        if mcap.exists() and mcap.stat().st_size > 300_000 and (out / "run.rrd").exists():
            return proc
        time.sleep(0.2)
    proc.kill()
    raise AssertionError("the run wrote nothing")


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT], ids=["killed", "ctrl-c"])
def test_run_stopped_half_way_leaves_readable_files(fmu_path, tmp_path, sig):
    proc = _start_long_run(fmu_path, tmp_path)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    info, states, impacts, notes = read_run(tmp_path / "run.mcap")
    assert len(states) > 100
    assert np.all(np.diff(states["time"]) > 0)
    series = rrd_series(tmp_path / "run.rrd")
    theta_t, theta = series["plots/angles/theta"]
    assert len(theta) > 0
    # whatever the .rrd holds agrees with the MCAP where both have it
    common = np.intersect1d(theta_t, to_ns(states["time"]), return_indices=True)
    assert len(common[0]) > 0 and np.array_equal(theta[common[1]], states["theta"][common[2]])
    if sig == signal.SIGINT:
        assert notes[-1][1] == "error" and "interrupted" in notes[-1][2]
        assert "reads back up to the failure" in err
        with open(tmp_path / "run.mcap", "rb") as handle:
            assert make_reader(handle).get_summary() is not None


def test_foxglove_schemas(logged):
    with open(logged.mcap, "rb") as handle:
        summary = make_reader(handle).get_summary()
    topics = {ch.topic: summary.schemas[ch.schema_id].name for ch in summary.channels.values()}
    assert topics["/damper/state"] == "pidamper.DamperState" and topics["/damper/impacts"] == "pidamper.Impact"
    assert topics["/tf"] == "foxglove.FrameTransforms" and topics["/scene"] == "foxglove.SceneUpdate"
    assert topics["/log"] == "foxglove.Log"


def test_streams_live_to_a_viewer_connection(fmu_path, tmp_path):
    """--connect streams while the run goes: a headless receiver (rerun --save) gets a recording
    equal to the file written beside it."""
    import socket

    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port = sock.getsockname()[1]
    received = tmp_path / "received.rrd"
    # the `rerun` entry script starts the viewer binary as its child: give both a process group
    # of their own and stop the whole group, so no viewer keeps serving after the tests
    receiver = subprocess.Popen([_rerun_cli(), "--port", str(port), "--save", str(received)],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        time.sleep(2.0)
        done = subprocess.run([sys.executable, "-m", "pidamper.cli", "run", "--fmu", str(fmu_path), "--periods", "2",
                               "--out", str(tmp_path), "--name", "run",
                               "--connect", f"rerun+http://127.0.0.1:{port}/proxy"],
                              capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr
        deadline = time.time() + 30
        while time.time() < deadline:
            compare = subprocess.run([_rerun_cli(), "rrd", "compare", "--unordered", str(received),
                                      str(tmp_path / "run.rrd")], capture_output=True, text=True)
            if compare.returncode == 0:
                break
            time.sleep(1.0)
        assert compare.returncode == 0, compare.stderr[-2000:]
    finally:
        _stop_group(receiver)
    with pytest.raises(ProcessLookupError):  # nothing of the group is left
        os.killpg(receiver.pid, 0)


def _stop_group(proc, grace=10.0):
    """SIGTERM the process group of `proc`, SIGKILL what is left after `grace` seconds, reap."""
    os.killpg(proc.pid, signal.SIGTERM)
    deadline = time.time() + grace
    while time.time() < deadline:
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        proc.poll()
        time.sleep(0.1)
    else:
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)
