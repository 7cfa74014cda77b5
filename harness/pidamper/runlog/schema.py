"""What a logged run consists of: run info, sampled states and impacts (numpy blocks).

The live run and the replay both hand these to the same writers, so an MCAP and a
Rerun recording made from either carry the same data.
"""
import hashlib
import importlib.metadata
import time
import uuid
from pathlib import Path

import numpy as np

STATE_FIELDS = ("time", "F", "a_g", "theta", "theta_dot", "alpha", "alpha_dot", "x", "y", "contact", "impacts",
                "energy", "energy_dissipated", "energy_viscous", "work_in")
STATE_DTYPE = np.dtype([(n, np.int64 if n in ("contact", "impacts") else np.float64) for n in STATE_FIELDS])

IMPACT_FIELDS = ("t", "side", "v_rel_before", "v_rel_after", "energy_lost", "theta", "e", "force_peak",
                 "pressure_peak", "duration", "plastic", "index")
IMPACT_DTYPE = np.dtype([(n, np.int64 if n in ("side", "plastic", "index") else np.float64) for n in IMPACT_FIELDS])
#: the impact fields the materials add (issue 25): zero in runs logged before them
CONTACT_FIELDS = ("e", "force_peak", "pressure_peak", "duration", "plastic")


def floors_dtype(storeys):
    """A building run's floor block (storeys >= 1): time [s], floor displacements x [m] and absolute
    accelerations a [m/s2], storey drifts [m] (floor / storey 1 first) and the base shear [N]."""
    return np.dtype([("time", np.float64), ("x", np.float64, (storeys,)), ("a", np.float64, (storeys,)),
                     ("drift", np.float64, (storeys,)), ("base_shear", np.float64)])


PACKAGES = ("pidamper", "pythonfmu", "fmpy", "numpy", "mcap", "foxglove-sdk", "rerun-sdk")


def to_ns(t):
    """Simulation time [s] to integer nanoseconds (the MCAP log time and Rerun's timeline)."""
    return np.rint(np.asarray(t, dtype=np.float64) * 1e9).astype(np.int64)


def file_sha256(path):
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def run_info(fmu_path, start_values, forcing, start_time, stop_time, output_interval, geometry):
    """Everything that identifies a run (stored as the MCAP's run metadata)."""
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            versions[name] = "not installed"
    wall = time.time_ns()
    return {
        "recording_id": str(uuid.uuid4()),
        "application_id": "pidamper",
        "fmu": {"file": Path(fmu_path).name, "sha256": file_sha256(fmu_path)},
        "start_values": {k: float(v) for k, v in start_values.items()},
        "parameters": parameters(fmu_path, start_values),
        "forcing": {"kind": forcing.kind, "args": forcing.args},
        "start_time": float(start_time),
        "stop_time": float(stop_time),
        "output_interval": float(output_interval),
        "geometry": geometry,
        "versions": versions,
        "wall_clock_start_ns": wall,
        "wall_clock_start": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(wall / 1e9)),
    }


def parameters(fmu_path, start_values):
    """Every parameter of the FMU with the value the run uses (its start value unless set)."""
    import fmpy

    md = fmpy.read_model_description(str(fmu_path))
    values = {v.name: float(v.start) for v in md.modelVariables if v.causality == "parameter"}
    values.update({k: float(v) for k, v in start_values.items() if k in values})
    return values


def geometry(start_values):
    """What the 3D drawing needs: lengths L2, L1 [m], the clearance as a distance [m], w2
    [rad/s] and the fidelity level (from coupled on the particle hangs from the primary's bob)."""
    from pidamper_physics import Params

    integers = ("storeys", "damper_floor", "fidelity", "contact_form", "restitution")  # the run info holds floats
    p = Params.from_variables({k: int(v) if k in integers else v for k, v in start_values.items()})
    contact = p.materials is not None  # the impacts carry their forces
    if p.storeys:  # a building: drawn as the pendulums of its theta and alpha
        return {"L2": p.L2, "L1": p.L1, "clearance": p.d, "w2": p.w2, "fidelity": 2, "storeys": p.storeys,
                "contact": contact}
    clearance = p.L2 * p.d_angle if p.contact_form == 1 else p.d  # the angle form's clearance as a distance
    return {"L2": p.L2, "L1": p.L2 / p.FR ** 2, "clearance": clearance, "w2": p.w2, "fidelity": p.fidelity,
            "contact": contact}


def frames(geometry, states):
    """The drawing of a block of states: (theta, alpha, pivot, carrier).  theta, alpha
    [rad] turn the primary about its pivot at (0, 0, L2) (its bob hangs at the origin, world z
    up) and the particle about `pivot` (n, 3) [m]: the primary's bob from coupled on, else
    (0, 0, L1).  The stops sit at +-clearance about `carrier` (n, 3), the primary's bob, at
    stop_height below it, without turning: the models' gap is horizontal.  The small-angle levels
    are drawn at their horizontal positions x, y [m] (angles asin(x / L2), ...), so a particle
    on a stop is drawn touching it; the nonlinear level at its own angles."""
    L1, L2, level = geometry["L1"], geometry["L2"], geometry.get("fidelity", 0)
    if level >= 3:
        theta, alpha = states["theta"], states["alpha"]
    else:
        x, y = states["x"], states["y"]
        theta = np.arcsin(np.clip(x / L2, -1.0, 1.0))
        alpha = np.arcsin(np.clip(((y - x) if level == 2 else y) / L1, -1.0, 1.0))
    carrier = np.stack([L2 * np.sin(theta), np.zeros_like(theta), L2 * (1.0 - np.cos(theta))], axis=-1)
    pivot = carrier if level >= 2 else np.tile([0.0, 0.0, L1], (len(theta), 1))
    return theta, alpha, pivot, carrier


def stop_height(geometry):
    """Height [m] of the stops in their carrier frame: at the hanging particle's bob."""
    return -geometry["L1"] if geometry.get("fidelity", 0) >= 2 else 0.0
