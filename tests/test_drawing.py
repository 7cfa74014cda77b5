"""The 3D drawing (Foxglove /tf + /scene in the MCAP, the pendulum entities of the .rrd) puts the
bodies where the model has them, at every level: the bob positions rebuilt from the logged
transforms equal the model's horizontal positions, the particle hangs from the primary's bob from
the coupled level on, and a particle riding a stop is drawn touching it."""
import os

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_protobuf.decoder import DecoderFactory
from rerun.chunk import RrdReader
from scipy.spatial.transform import Rotation

from pidamper.runlog.logged_run import run_logged
from pidamper.runlog.mcap_log import read_run

os.environ.setdefault("RERUN_ANALYTICS", "0")
HUNG = {"mu": 0.1, "FR": 2.0, "d": 0.15, "e": 0.05, "theta_dot_0": 3.13, "alpha_dot_0": -12.52,
        "zeta_s": 0.01}  # the large-swing scene (1 rad swings, a 0.25 m wire) with e = 0.05: it rides
CHATTER = {"mu": 0.3, "FR": 0.5, "d": 0.005, "e": 0.05, "theta_dot_0": 1.0}  # the hard-chatter scene
LEVELS = {"linear": CHATTER, "coupled": {**CHATTER, "fidelity": 2}, "nonlinear": {**HUNG, "fidelity": 3}}
L2 = 1.0


@pytest.fixture(scope="module", params=list(LEVELS))
def drawn(request, fmu_path, tmp_path_factory):
    out = tmp_path_factory.mktemp(request.param)
    run = run_logged(LEVELS[request.param], stop_time=4.0, output_interval=0.01, out_dir=out, fmu=fmu_path)
    _, states, _, _ = read_run(run.mcap)
    p = LEVELS[request.param]
    return request.param, (L2 / p["FR"] ** 2, p["d"]), states, mcap_frames(run.mcap), rrd_frames(run.rrd)


def bob(origin, quat, length):
    """World position of a bob hanging `length` below a frame at `origin` turned by `quat` (xyzw)."""
    return np.asarray(origin) + Rotation.from_quat(quat).apply([0.0, 0.0, -length])


def mcap_frames(path):
    """{frame: (n, 7) array of translation xyz and rotation xyzw}, one row per /tf message."""
    rows = {}
    with open(path, "rb") as handle:
        reader = make_reader(handle, decoder_factories=[DecoderFactory()])
        for _, _, _, proto in reader.iter_decoded_messages(topics=["/tf"]):
            for tf in proto.transforms:
                tr, rot = tf.translation, tf.rotation
                rows.setdefault(tf.child_frame_id, []).append([tr.x, tr.y, tr.z, rot.x, rot.y, rot.z, rot.w])
    return {frame: np.array(v) for frame, v in rows.items()}


def rrd_frames(path):
    """{entity: (n, 7) array of translation and quaternion (identity where none)}, by sim time."""
    parts = {}
    for chunk in RrdReader(str(path)).stream():
        batch = chunk.to_record_batch()
        entity = batch.schema.metadata[b"rerun:entity_path"].decode().lstrip("/")
        if not entity.startswith("pendulum/") or "sim_time" not in batch.column_names:
            continue
        t = batch.column("sim_time").cast("int64").to_numpy()
        tr = np.array([row[0] for row in batch.column("Transform3D:translation").to_pylist()])
        if "Transform3D:quaternion" in batch.column_names:
            q = np.array([row[0] for row in batch.column("Transform3D:quaternion").to_pylist()])
        else:
            q = np.tile([0.0, 0.0, 0.0, 1.0], (len(t), 1))
        parts.setdefault(entity, []).append((t, np.hstack([tr, q])))
    out = {}
    for entity, pieces in parts.items():
        t = np.concatenate([p[0] for p in pieces])
        out[entity] = np.concatenate([p[1] for p in pieces])[np.argsort(t, kind="stable")]
    return out


def positions(frames, names, L1):
    """Positions [m] of the primary bob, the particle bob and the stops' carrier (n, 3 each)."""
    primary, particle, stops = (frames[n] for n in names)
    xb = bob(primary[:, :3], primary[:, 3:], L2)
    yp = bob(particle[:, :3], particle[:, 3:], L1)
    return xb, yp, stops[:, :3]


@pytest.mark.parametrize("source", ["mcap", "rrd"])
def test_the_drawing_puts_the_bodies_where_the_model_has_them(drawn, source):
    level, (L1, D), states, from_mcap, from_rrd = drawn
    names = (("primary", "particle", "stops") if source == "mcap" else
             ("pendulum/primary", "pendulum/particle", "pendulum/stops"))
    frames = from_mcap if source == "mcap" else from_rrd
    xb, yp, carrier = positions(frames, names, L1)
    assert len(xb) == len(states)
    assert np.allclose(carrier, xb, atol=1e-12)  # the stops ride on the primary's bob
    touching = states["contact"] != 0
    assert touching.sum() > 5
    # each body is drawn at the model's horizontal position; a riding particle touches its stop
    assert np.allclose(xb[:, 0], states["x"], atol=1e-12)
    assert np.allclose(yp[:, 0], states["y"], atol=1e-12)
    assert np.allclose(np.abs(yp[touching, 0] - carrier[touching, 0]), D, atol=1e-12)
    pivot = frames[names[1]][:, :3]
    if level == "linear":  # a fixed pivot, drawn at the horizontal positions
        assert np.array_equal(pivot, np.tile([0.0, 0.0, L1], (len(pivot), 1)))
    else:  # hung from the bob
        assert np.allclose(pivot, xb, atol=1e-12)
    if level == "nonlinear":  # drawn at its own angles, far beyond the small-angle range
        assert np.allclose(Rotation.from_quat(frames[names[0]][:, 3:]).magnitude(), np.abs(states["theta"]), atol=1e-12)
        assert np.max(np.abs(states["theta"])) > 0.9
