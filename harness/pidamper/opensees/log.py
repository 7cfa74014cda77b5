"""A co-simulation with OpenSees logged as every run is: MCAP (Foxglove) and a Rerun recording,
written block by block while it goes, so both read back up to a failure.

MCAP topics: /opensees/unit[i] one message per communication point (time, the node's x, v, a_abs,
the unit's outputs by their FMU names), /opensees/impulses one per impulse (t_J, unit, J, the node's
velocity jump the node shows), /run/info (the run's description, also the MCAP metadata record), /log (notes and
impulses as log lines).  Rerun: the same series under plots/unit_<i>/..., impulses in an event log.
"""
import json
import uuid

import foxglove
import numpy as np
import rerun as rr
from foxglove.channels import LogChannel
from foxglove.mcap import MCAPCompression, MCAPWriteOptions
from foxglove.messages import Log, LogLevel, Timestamp

from ..runlog.mcap_log import read_messages
from ..runlog.schema import to_ns
from .coupling import UNIT_OUTPUTS

METADATA_NAME = "pidamper.opensees"
NODE_FIELDS = ("x", "v", "a_abs")


def _stamp(ns):
    return Timestamp(sec=int(ns // 1_000_000_000), nsec=int(ns % 1_000_000_000))


class CosimLog:
    """The sinks of one co-simulation: `mcap` and `rrd` paths (either may be None)."""

    def __init__(self, info, units, mcap=None, rrd=None):
        self.units = units
        self.writer = self.rec = None
        info = {**info, "recording_id": str(uuid.uuid4())}
        if mcap is not None:
            self.context = context = foxglove.Context()
            options = MCAPWriteOptions(compression=MCAPCompression.Zstd, chunk_size=64 * 1024)
            self.writer = foxglove.open_mcap(str(mcap), allow_overwrite=True, context=context, writer_options=options)
            self.writer.write_metadata(METADATA_NAME, {"info": json.dumps(info)})
            schema = {"title": "pidamper.OpenSeesAttachment", "type": "object",
                      "properties": {f: {"type": "number"} for f in ("time",) + NODE_FIELDS + UNIT_OUTPUTS}}
            self.channels = [foxglove.Channel(f"/opensees/unit[{i + 1}]", schema=schema, context=context)
                             for i in range(units)]
            self.impulse_channel = foxglove.Channel("/opensees/impulses", schema={
                "title": "pidamper.OpenSeesImpulse", "type": "object",
                "properties": {f: {"type": "number"} for f in ("t_J", "unit", "J", "velocity_jump")}},
                context=context)
            self.log = LogChannel("/log", context=context)
            foxglove.Channel("/run/info", schema={"type": "object"}, context=context).log(json.dumps(info), log_time=0)
        if rrd is not None:
            self.rec = rr.RecordingStream("pidamper", recording_id=info["recording_id"], send_properties=False)
            self.rec.save(str(rrd))
            self.rec.send_property("run", rr.AnyValues(info=json.dumps(info)))

    def write(self, time, nodes, units, impulses):
        """A block: time (k,), per unit nodes (k, 3) and units (k, len(UNIT_OUTPUTS)), impulses
        (t_J, unit index, J, the node's velocity jump) that fell in it."""
        ns = to_ns(time).tolist()
        if self.writer is not None:
            for i in range(self.units):
                for t, n_ns, node, unit in zip(time.tolist(), ns, nodes[i].tolist(), units[i].tolist()):
                    row = {"time": t, **dict(zip(NODE_FIELDS, node)), **dict(zip(UNIT_OUTPUTS, unit))}
                    self.channels[i].log(json.dumps(row), log_time=n_ns)
            for t_J, i, J, jump in impulses:
                t_ns = int(to_ns(t_J))
                self.impulse_channel.log(json.dumps({"t_J": t_J, "unit": i + 1, "J": J, "velocity_jump": jump}),
                                         log_time=t_ns)
                self.log.log(Log(timestamp=_stamp(t_ns), level=LogLevel.Info, name="pidamper",
                                 message=f"unit {i + 1}: impulse {J:.6g} N s at t = {t_J:.9f} s"), log_time=t_ns)
            self.writer.flush()
        if self.rec is not None and len(time):
            times = [rr.TimeColumn("sim_time", duration=np.asarray(ns).astype("timedelta64[ns]"))]
            for i in range(self.units):
                for j, name in enumerate(NODE_FIELDS):
                    self.rec.send_columns(f"plots/unit_{i + 1}/node/{name}", indexes=times,
                                          columns=rr.Scalars.columns(scalars=nodes[i][:, j]))
                for j, name in enumerate(UNIT_OUTPUTS):
                    self.rec.send_columns(f"plots/unit_{i + 1}/{name}", indexes=times,
                                          columns=rr.Scalars.columns(scalars=units[i][:, j].astype(float)))
            if impulses:
                stamps = [rr.TimeColumn("sim_time", duration=to_ns([k[0] for k in impulses]).astype("timedelta64[ns]"))]
                self.rec.send_columns("events", indexes=stamps, columns=rr.TextLog.columns(
                    text=[f"unit {i + 1}: impulse {J:.6g} N s" for _, i, J, _ in impulses],
                    level=["INFO"] * len(impulses)))
            self.rec.flush()

    def note(self, t, text, level="INFO"):
        ns = int(to_ns(t))
        if self.writer is not None:
            self.log.log(Log(timestamp=_stamp(ns), level=LogLevel.Error if level == "ERROR" else LogLevel.Warning
                             if level == "WARN" else LogLevel.Info, message=text, name="pidamper"), log_time=ns)
            self.writer.flush()
        if self.rec is not None:
            self.rec.set_time("sim_time", duration=np.timedelta64(ns, "ns"))
            self.rec.log("events", rr.TextLog(text, level=level))
            self.rec.flush()

    def drop_rerun(self):
        """Close the Rerun recording as it is (it reads back up to its last block) and write no more
        to it: inside a C exit (exits.py) Arrow's C++ state, which new rows go through, may already
        be torn down (a segfault); closing it and the MCAP (Rust only) is safe there."""
        if self.rec is not None:
            self.rec.flush()
            self.rec = None

    def close(self):
        if self.writer is not None:
            self.writer.close()
            self.writer = None
        if self.rec is not None:
            self.rec.flush()
            self.rec = None


def read_cosim(path, units=1):
    """(info, {topic: [messages]}) of an MCAP the CosimLog wrote (`units` units), read up to its last
    complete chunk."""
    topics = [f"/opensees/unit[{i + 1}]" for i in range(units)] + ["/opensees/impulses"]
    return read_messages(path, METADATA_NAME, topics)
