"""A run as a Rerun recording: one logging function for the live run and the replay.

Layout: time series of the angles (with impact markers), velocities, energies and
the force; an animated 3D view of the two pendulums and the stops; an event log;
the run metadata and parameters as recording properties.  Everything is on the
`sim_time` timeline (integer nanoseconds); nothing depends on the wall clock, so
a replay of a run's MCAP equals the live recording.
"""
import json

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from .mcap_log import impact_text
from .schema import frames, stop_height, to_ns

TIMELINE = "sim_time"

SERIES = (  # entity, state field, colour
    ("plots/angles/theta", "theta", (40, 100, 230)),
    ("plots/angles/alpha", "alpha", (240, 170, 20)),
    ("plots/velocities/theta_dot", "theta_dot", (40, 100, 230)),
    ("plots/velocities/alpha_dot", "alpha_dot", (240, 170, 20)),
    ("plots/energy/energy", "energy", (60, 160, 60)),
    ("plots/energy/energy_dissipated", "energy_dissipated", (200, 60, 50)),
    ("plots/energy/energy_viscous", "energy_viscous", (230, 120, 160)),
    ("plots/energy/work_in", "work_in", (120, 120, 120)),
    ("plots/force/F", "F", (120, 60, 160)),
    ("plots/force/a_g", "a_g", (160, 100, 40)),
    ("plots/impacts/count", "impacts", (200, 60, 50)),
)
MARKERS = "plots/angles/impacts"
#: each impact's peak contact force [N] (runs with materials: geometry["contact"])
CONTACT_FORCE = "plots/contact/force_peak"


VIEWS = ("angles", "velocities", "energy", "force", "floors", "pendulum", "events")


def wanted(info):
    """The Rerun views a run logs (its scene's log.rerun_views; default all)."""
    return set((info.get("log") or {}).get("rerun_views") or VIEWS)


VIEW_OF_GROUP = {"angles": "angles", "velocities": "velocities", "energy": "energy", "force": "force",
                 "impacts": "events"}  # plots/<group>/... -> the view that shows it


def series(views):
    """The SERIES entries the views show."""
    return [entry for entry in SERIES if VIEW_OF_GROUP[entry[0].split("/")[1]] in views]


def blueprint(geometry, views=VIEWS):
    L2 = geometry["L2"]
    eye = rrb.EyeControls3D(position=[0.3 * L2, -1.6 * L2, 0.45 * L2], look_target=[0.0, 0.0, 0.35 * L2],
                            eye_up=[0.0, 0.0, 1.0])
    left = [view for name, view in (
        ("angles", rrb.TimeSeriesView(origin="plots/angles", name="angles [rad] (dots: impacts)")),
        ("velocities", rrb.TimeSeriesView(origin="plots/velocities", name="angular velocities [rad/s]")),
        ("energy", rrb.TimeSeriesView(origin="plots/energy", name="energy [J]")),
        ("force", rrb.TimeSeriesView(origin="plots/force", name="inputs: F [N], a_g [m/s2]")),
        ("floors", rrb.TimeSeriesView(origin="plots/floors", name="floor displacements [m]")),
        ("contact", rrb.TimeSeriesView(origin="plots/contact", name="impacts' peak contact force [N]")))
        if (name in views or (name == "contact" and "events" in views and geometry.get("contact")))
        and (name != "floors" or geometry.get("storeys"))]
    right = [view for name, view in (
        ("pendulum", rrb.Spatial3DView(origin="pendulum", name="pendulums and stops (front view)", eye_controls=eye)),
        ("events", rrb.TextLogView(origin="events", name="events"))) if name in views]
    columns = [rrb.Vertical(*part) for part in (left, right) if part]
    return rrb.Blueprint(rrb.Horizontal(*columns), collapse_panels=True)


def open_recording(info, path=None, serve=False, connect=None):
    """A recording stream for the run, with the chosen sinks: a file, a gRPC server a viewer can
    join, or a viewer at `connect`.  Never spawns a viewer."""
    rec = rr.RecordingStream(info["application_id"], recording_id=info["recording_id"], send_properties=False)
    sinks = []
    if path is not None:
        sinks.append(rr.FileSink(str(path)))
    if connect:
        sinks.append(rr.GrpcSink(connect))
    if serve:
        sinks.append(rr.GrpcServerSink())
    if not sinks:
        raise ValueError("a Rerun recording needs a file, --serve or --connect")
    rec.set_sinks(*sinks, default_blueprint=blueprint(info["geometry"], wanted(info)))
    return rec


def log_start(rec, info):
    """Recording properties and static geometry (once, before any block)."""
    rec.send_property("run", rr.AnyValues(
        fmu=info["fmu"]["file"], fmu_sha256=info["fmu"]["sha256"], forcing=json.dumps(info["forcing"]),
        output_interval=info["output_interval"], stop_time=info["stop_time"],
        wall_clock_start=info["wall_clock_start"]))
    rec.send_property("params", rr.AnyValues(**info["parameters"]))
    rec.send_recording_start_time_nanos(int(info["wall_clock_start_ns"]))
    views = wanted(info)
    for entity, field, colour in series(views):
        rec.log(entity, rr.SeriesLines(colors=[colour], names=[field]), static=True)
    if "angles" in views:
        rec.log(MARKERS, rr.SeriesPoints(colors=[(200, 60, 50)], names=["impact"], markers=["circle"],
                                         marker_sizes=[3.0]), static=True)
    if "pendulum" not in views:
        return
    g = info["geometry"]
    L1, L2, c = g["L1"], g["L2"], g["clearance"]
    rec.log("pendulum/primary/rod", rr.LineStrips3D([[[0, 0, 0], [0, 0, -L2]]], colors=[(150, 150, 150)]), static=True)
    rec.log("pendulum/primary/bob", rr.Points3D([[0, 0, -L2]], radii=[0.03], colors=[(40, 100, 230)]), static=True)
    height = stop_height(g)
    rec.log("pendulum/stops", rr.Boxes3D(centers=[[-c, 0, height], [c, 0, height]], half_sizes=[[0.003, 0.04, 0.04]] * 2,
                                         colors=[(230, 80, 50)]), static=True)
    rec.log("pendulum/particle/rod", rr.LineStrips3D([[[0, 0, 0], [0, 0, -L1]]], colors=[(150, 150, 150)]), static=True)
    rec.log("pendulum/particle/bob", rr.Points3D([[0, 0, -L1]], radii=[0.02], colors=[(240, 170, 20)]), static=True)


def log_block(rec, info, states, impacts, floors=None):
    """Log a block of states and impacts, and of a building's floors if any, in columns (one call
    per entity, not per sample)."""
    views = wanted(info)
    if floors is not None and len(floors) and "floors" in views:
        times = [rr.TimeColumn(TIMELINE, duration=to_ns(floors["time"]).astype("timedelta64[ns]"))]
        for k in range(floors["x"].shape[1]):
            rec.send_columns(f"plots/floors/floor_{k + 1}", indexes=times,
                             columns=rr.Scalars.columns(scalars=floors["x"][:, k]))
    if len(states):
        times = [rr.TimeColumn(TIMELINE, duration=to_ns(states["time"]).astype("timedelta64[ns]"))]
        for entity, field, _ in series(views):
            rec.send_columns(entity, indexes=times, columns=rr.Scalars.columns(scalars=states[field].astype(np.float64)))
        if "pendulum" in views:
            _log_frames(rec, times, info["geometry"], states)
    if len(impacts):
        times = [rr.TimeColumn(TIMELINE, duration=to_ns(impacts["t"]).astype("timedelta64[ns]"))]
        if "angles" in views:
            rec.send_columns(MARKERS, indexes=times, columns=rr.Scalars.columns(scalars=impacts["theta"]))
        if "events" in views:
            rec.send_columns("events", indexes=times, columns=rr.TextLog.columns(
                text=[impact_text(row) for row in impacts.tolist()], level=["INFO"] * len(impacts)))
            if info["geometry"].get("contact"):
                rec.send_columns(CONTACT_FORCE, indexes=times, columns=rr.Scalars.columns(scalars=impacts["force_peak"]))


def _log_frames(rec, times, g, states):
    """The pendulum's moving frames (schema.frames): each body turns about its pivot; the
    stops ride on the primary's bob."""
    theta, alpha, pivot, carrier = frames(g, states)
    for entity, angle, origin in (("pendulum/primary", theta, np.tile([0.0, 0.0, g["L2"]], (len(states), 1))),
                                  ("pendulum/particle", alpha, pivot)):
        half = 0.5 * angle
        quaternion = np.zeros((len(states), 4))  # xyzw: rotation by the angle about -y (bob swings to +x)
        quaternion[:, 1] = -np.sin(half)
        quaternion[:, 3] = np.cos(half)
        rec.send_columns(entity, indexes=times, columns=rr.Transform3D.columns(translation=origin, quaternion=quaternion))
    rec.send_columns("pendulum/stops", indexes=times, columns=rr.Transform3D.columns(translation=carrier))


def log_note(rec, t, level, text):
    rec.send_columns("events", indexes=[rr.TimeColumn(TIMELINE, duration=to_ns([t]).astype("timedelta64[ns]"))],
                     columns=rr.TextLog.columns(text=[text], level=[level.upper()]))
