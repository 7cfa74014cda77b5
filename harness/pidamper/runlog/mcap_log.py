"""A run as MCAP: written while the run goes (zstd chunks), read back for replay and tests.

Topics (titled JSON schemas, plotted by Foxglove as they are):
- /damper/state     one message per communication point (STATE_FIELDS)
- /damper/impacts   one message per recorded impact (IMPACT_FIELDS)
- /building/floors  a building's run (storeys >= 1): one message per communication point, arrays x,
                    a, drift (floor / storey 1 first) and base_shear (schema.floors_dtype)
- /run/info         the run metadata once (also the MCAP metadata record "pidamper.run")
- /run/notes        run start, end, failure, impacts not recorded individually
- /log              foxglove.Log: the impacts and notes as log lines
- /tf, /scene       foxglove FrameTransforms and SceneUpdate: the two pendulums and the stops in 3D
Log times are simulation times in integer nanoseconds.
"""
import json
import math

import foxglove
import numpy as np
from foxglove.channels import FrameTransformsChannel, LogChannel, SceneUpdateChannel
from foxglove.mcap import MCAPCompression, MCAPWriteOptions
from foxglove.messages import (Color, CubePrimitive, FrameTransform, FrameTransforms, LinePrimitive, Log, LogLevel,
                               Point3, Pose, Quaternion, SceneEntity, SceneUpdate, SpherePrimitive, Timestamp, Vector3)
from mcap.stream_reader import StreamReader
from mcap.records import Channel, Message, Metadata

from .schema import (IMPACT_DTYPE, IMPACT_FIELDS, STATE_DTYPE, STATE_FIELDS, floors_dtype, frames, stop_height,
                      to_ns)

METADATA_NAME = "pidamper.run"
TOPICS = ("/damper/state", "/damper/impacts", "/building/floors", "/run/info", "/run/notes", "/log", "/tf", "/scene")
CHUNK_SIZE = 256 * 1024  # bytes before compression: a killed run loses at most one chunk

_INT = {"contact", "impacts", "side", "plastic", "index"}


def _schema(title, fields, descriptions):
    return {"title": title, "type": "object",
            "properties": {f: {"type": "integer" if f in _INT else "number", "description": descriptions.get(f, "")}
                           for f in fields}}


STATE_SCHEMA = _schema("pidamper.DamperState", STATE_FIELDS, {
    "time": "s", "F": "N, external force held over the step ending here",
    "a_g": "m/s2, ground acceleration held over the step ending here", "theta": "rad", "theta_dot": "rad/s",
    "alpha": "rad", "alpha_dot": "rad/s", "x": "m", "y": "m", "contact": "0 free, +1/-1 riding that stop",
    "impacts": "impacts so far", "energy": "J", "energy_dissipated": "J, by impacts",
    "energy_viscous": "J, by the dashpots (damped level on)", "work_in": "J"})
IMPACT_SCHEMA = _schema("pidamper.Impact", IMPACT_FIELDS, {
    "t": "s", "side": "+1 or -1", "v_rel_before": "m/s, particle minus primary", "v_rel_after": "m/s",
    "energy_lost": "J", "theta": "rad, primary angle at the impact", "e": "restitution applied",
    "force_peak": "N, peak contact force (0 without materials)", "pressure_peak": "Pa, peak contact pressure",
    "duration": "s, contact duration", "plastic": "1 if the contact yielded the softer body",
    "index": "1-based impact number"})
FLOORS_SCHEMA = {"title": "pidamper.BuildingFloors", "type": "object", "properties": {
    "time": {"type": "number", "description": "s"},
    "x": {"type": "array", "items": {"type": "number"}, "description": "m, floor displacements relative to the ground"},
    "a": {"type": "array", "items": {"type": "number"}, "description": "m/s2, floor absolute accelerations"},
    "drift": {"type": "array", "items": {"type": "number"}, "description": "m, storey drifts"},
    "base_shear": {"type": "number", "description": "N, force of the building on the ground"}}}
NOTE_SCHEMA = {"title": "pidamper.Note", "type": "object",
               "properties": {"time": {"type": "number"}, "level": {"type": "string"}, "text": {"type": "string"}}}
INFO_SCHEMA = {"title": "pidamper.RunInfo", "type": "object"}

_LEVELS = {"info": LogLevel.Info, "warning": LogLevel.Warning, "error": LogLevel.Error}


def _json_rows(block, fields):
    template = "{" + ",".join(f'"{f}":%r' for f in fields) + "}"
    return [(template % tuple(row)).encode() for row in block.tolist()]


def _stamp(ns):
    return Timestamp(sec=int(ns // 1_000_000_000), nsec=int(ns % 1_000_000_000))


def _axis_angle(angle):
    """Quaternion of a rotation by `angle` about -y (a positive angle swings the bob to +x)."""
    return Quaternion(x=0.0, y=-math.sin(0.5 * angle), z=0.0, w=math.cos(0.5 * angle))


class McapLog:
    """Writes one run to an MCAP file as it goes."""

    def __init__(self, path, info):
        self.info = info
        self.geometry = info["geometry"]
        self.topics = set((info.get("log") or {}).get("mcap_topics") or TOPICS)
        self.context = context = foxglove.Context()  # channels close when their context is dropped
        options = MCAPWriteOptions(compression=MCAPCompression.Zstd, chunk_size=CHUNK_SIZE)
        self.writer = foxglove.open_mcap(str(path), allow_overwrite=True, context=context, writer_options=options)
        self.writer.write_metadata(METADATA_NAME, {"recording_id": info["recording_id"], "info": json.dumps(info)})
        self.state = foxglove.Channel("/damper/state", schema=STATE_SCHEMA, context=context)
        self.impacts = foxglove.Channel("/damper/impacts", schema=IMPACT_SCHEMA, context=context)
        self.notes = foxglove.Channel("/run/notes", schema=NOTE_SCHEMA, context=context)
        self.floors = None  # opened with a building's first floor block
        self.log = LogChannel("/log", context=context)
        self.tf = FrameTransformsChannel("/tf", context=context)
        t0 = int(to_ns(info["start_time"]))
        self.static = (foxglove.Channel("/run/info", schema=INFO_SCHEMA, context=context),
                       SceneUpdateChannel("/scene", context=context))
        if "/run/info" in self.topics:
            self.static[0].log(json.dumps(info), log_time=t0)
        if "/scene" in self.topics:
            self.static[1].log(self._scene(t0), log_time=t0)

    def write(self, states, impacts, floors=None):
        """Append a block of states (STATE_DTYPE) and impacts (IMPACT_DTYPE), and of a building's
        floors (schema.floors_dtype) if any."""
        times = to_ns(states["time"]).tolist()
        topics = self.topics
        if floors is not None and "/building/floors" in topics:
            if self.floors is None:
                self.floors = foxglove.Channel("/building/floors", schema=FLOORS_SCHEMA, context=self.context)
            for row in floors:
                self.floors.log(json.dumps({"time": float(row["time"]), "x": row["x"].tolist(), "a": row["a"].tolist(),
                                            "drift": row["drift"].tolist(), "base_shear": float(row["base_shear"])}),
                                log_time=int(to_ns(row["time"])))
        if "/damper/state" in topics:
            for ns, payload in zip(times, _json_rows(states, STATE_FIELDS)):
                self.state.log(payload, log_time=ns)
        if "/tf" in topics:
            self._write_frames(times, states)
        impact_ns = to_ns(impacts["t"]).tolist()
        for ns, payload, row in zip(impact_ns, _json_rows(impacts, IMPACT_FIELDS), impacts.tolist()):
            if "/damper/impacts" in topics:
                self.impacts.log(payload, log_time=ns)
            if "/log" in topics:
                self.log.log(Log(timestamp=_stamp(ns), level=LogLevel.Info, message=impact_text(row),
                                 name="pidamper"), log_time=ns)

    def _write_frames(self, times, states):
        """The pendulum's frames (schema.frames): each body turns about its pivot; the stops
        ride on the primary's bob without turning."""
        theta, alpha, pivot, carrier = frames(self.geometry, states)
        top = Vector3(x=0.0, y=0.0, z=self.geometry["L2"])
        level = Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)
        for ns, theta, alpha, (px, _, pz), (cx, _, cz) in zip(times, theta.tolist(), alpha.tolist(),
                                                             pivot.tolist(), carrier.tolist()):
            stamp = _stamp(ns)
            self.tf.log(FrameTransforms(transforms=[
                FrameTransform(timestamp=stamp, parent_frame_id="world", child_frame_id="primary",
                               translation=top, rotation=_axis_angle(theta)),
                FrameTransform(timestamp=stamp, parent_frame_id="world", child_frame_id="particle",
                               translation=Vector3(x=px, y=0.0, z=pz), rotation=_axis_angle(alpha)),
                FrameTransform(timestamp=stamp, parent_frame_id="world", child_frame_id="stops",
                               translation=Vector3(x=cx, y=0.0, z=cz), rotation=level),
            ]), log_time=ns)

    def note(self, t, level, text):
        ns = int(to_ns(t))
        if "/run/notes" in self.topics:
            self.notes.log(json.dumps({"time": float(t), "level": level, "text": text}), log_time=ns)
        if "/log" in self.topics:
            self.log.log(Log(timestamp=_stamp(ns), level=_LEVELS[level], message=text, name="pidamper"),
                         log_time=ns)

    def flush(self):
        self.writer.flush()

    def close(self):
        self.writer.close()

    def _scene(self, t0):
        g = self.geometry
        L1, L2, c = g["L1"], g["L2"], g["clearance"]
        rod = Color(r=0.6, g=0.6, b=0.6, a=1.0)

        def pendulum(frame, length, colour):
            return SceneEntity(
                timestamp=_stamp(t0), frame_id=frame, id=frame,
                lines=[LinePrimitive(points=[Point3(x=0, y=0, z=0), Point3(x=0, y=0, z=-length)], thickness=0.01,
                                     scale_invariant=False, color=rod)],
                spheres=[SpherePrimitive(pose=Pose(position=Vector3(x=0, y=0, z=-length),
                                                   orientation=Quaternion(x=0, y=0, z=0, w=1)),
                                         size=Vector3(x=0.05, y=0.05, z=0.05), color=colour)])

        height = stop_height(g)
        stops = SceneEntity(timestamp=_stamp(t0), frame_id="stops", id="stops", cubes=[
            CubePrimitive(pose=Pose(position=Vector3(x=s * c, y=0, z=height), orientation=Quaternion(x=0, y=0, z=0, w=1)),
                          size=Vector3(x=0.005, y=0.08, z=0.08), color=Color(r=0.9, g=0.3, b=0.2, a=0.8))
            for s in (-1.0, 1.0)])
        return SceneUpdate(entities=[pendulum("primary", L2, Color(r=0.2, g=0.4, b=0.9, a=1.0)),
                                     pendulum("particle", L1, Color(r=0.95, g=0.7, b=0.1, a=1.0)), stops])


def impact_text(row):
    """One log line for an impact row (a tuple in IMPACT_FIELDS order)."""
    t, side, before, after, lost, theta, e, force, pressure, duration, plastic, index = row
    contact = (f"; peak force {force:.4g} N, pressure {pressure / 1e6:.4g} MPa, {duration * 1e3:.4g} ms"
               f"{', plastic' if plastic else ''}" if force else "")
    return (f"impact {index} at t = {t:.9f} s on stop {side:+d}: v_rel {before:+.6g} -> {after:+.6g} m/s, "
            f"e = {e:.4g}, lost {lost:.6g} J{contact}")


def read_messages(path, metadata_name, topics):
    """(the JSON `info` of the metadata record `metadata_name` or None, {topic: [messages as
    dicts]} of `topics`) of an MCAP, read up to its last complete chunk (a file cut short by a
    crash); a file whose metadata could not be read raises ValueError."""
    info, channels, out = None, {}, {topic: [] for topic in topics}
    with open(path, "rb") as handle:
        try:
            for record in StreamReader(handle).records:
                if isinstance(record, Metadata) and record.name == metadata_name:
                    info = json.loads(record.metadata["info"])
                elif isinstance(record, Channel):
                    channels[record.id] = record.topic
                elif isinstance(record, Message):
                    topic = channels.get(record.channel_id)
                    if topic in out:
                        out[topic].append(json.loads(record.data))
        except Exception as err:  # a truncated file: keep what was complete
            if info is None:
                raise ValueError(f"{path}: no pidamper run metadata could be read ({err})") from err
    return info, out


def read_run(path):
    """(info, states, impacts, notes) of an MCAP run; a file cut short by a crash is read up to
    its last complete chunk.  notes: list of (time, level, text)."""
    info, topics = read_messages(path, METADATA_NAME, ("/damper/state", "/damper/impacts", "/run/notes"))
    if info is None:
        raise ValueError(f"{path}: not a pidamper run (no '{METADATA_NAME}' metadata record)")
    notes = [(note["time"], note["level"], note["text"]) for note in topics["/run/notes"]]
    return (info, _to_array(topics["/damper/state"], STATE_DTYPE), _to_array(topics["/damper/impacts"], IMPACT_DTYPE),
            notes)


def read_floors(path):
    """A building run's floors (schema.floors_dtype) from its MCAP, or None (no building)."""
    rows, floors_channel = [], None
    with open(path, "rb") as handle:
        try:
            for record in StreamReader(handle).records:
                if isinstance(record, Channel) and record.topic == "/building/floors":
                    floors_channel = record.id
                elif isinstance(record, Message) and record.channel_id == floors_channel:
                    rows.append(json.loads(record.data))
        except Exception:  # a truncated file: keep what was complete
            pass
    if not rows:
        return None
    out = np.zeros(len(rows), dtype=floors_dtype(len(rows[0]["x"])))
    for name in out.dtype.names:
        out[name] = [row[name] for row in rows]
    return out


def _to_array(rows, dtype):
    out = np.zeros(len(rows), dtype=dtype)
    for name in dtype.names:
        out[name] = [row.get(name, 0) for row in rows]  # fields a run of an older build lacks: 0
    return out
