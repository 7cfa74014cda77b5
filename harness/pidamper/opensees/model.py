"""An engineer's OpenSeesPy model file, run to build the structure, and the ground motion it gets.

A model file is plain Python that builds the structure with ordinary `ops` commands (nodes, masses,
materials, elements, constraints, damping: `modalDamping` or `rayleigh`, gravity if it has any) and
runs no dynamic analysis: pidamper owns the analysis, the ground motion and the units.  It may
`import openseespy.opensees as ops` itself: OpenSeesPy is loaded first with its bundled libraries
(pidamper.oracles.opensees.load), so no LD_LIBRARY_PATH is needed.  A file that does not parse,
raises or calls sys.exit is a ModelError showing its file and line as Python would.
"""
import runpy
import traceback
from pathlib import Path

import numpy as np

from ..forcing.ground_motion import read_record
from ..oracles.opensees import load
from .checks import CouplingError


class ModelError(CouplingError):
    """The model file failed: the message shows its file and line and the exception's own line."""


def _where(err, path):
    """Python's lines for the innermost frame in the model file, then the exception's own."""
    here = path.resolve()
    frames = [f for f in traceback.extract_tb(err.__traceback__) if Path(f.filename).resolve() == here]
    return "".join(traceback.format_list(frames[-1:]) + traceback.format_exception_only(type(err), err)).rstrip()


def build_model(path):
    """Run the model file at `path` in a fresh OpenSees domain; returns the `ops` module."""
    path = Path(path)
    if not path.is_file():
        raise CouplingError(f"--opensees = {str(path)!r} is not allowed: no such file (a Python file that builds "
                            "the structure with openseespy)")
    ops = load()
    ops.wipe()
    try:
        runpy.run_path(str(path), run_name="__opensees_model__")
    except SystemExit as err:
        code = "" if err.code is None else repr(err.code)
        raise ModelError(f"the model file called sys.exit({code}) (a model file builds the structure and returns; "
                         f"pidamper runs the analysis):\n{_where(err, path)}") from None
    except Exception as err:
        raise ModelError(f"the model file failed:\n{_where(err, path)}") from None
    if not ops.getNodeTags():
        raise CouplingError(f"--opensees = {str(path)!r} is not allowed: the file built no nodes")
    return ops


def ground_samples(path, h, stop_time, scale=1.0):
    """The record at `path` (.AT2 or .csv, m/s2 or g as the reader says) at the communication points
    k h, k = 0 .. n - 1, as an FMU input samples it (linear between the record's samples, its last
    value held after its end: `held_note` says when that happens), times `scale`."""
    record = read_record(path)
    forcing = record.scaled(scale).to_forcing() if scale != 1.0 else record.to_forcing()
    n = int(round(stop_time / h))
    return np.array([float(forcing.value(k * h)) for k in range(n)]), record


def held_note(record, ground, h, stop_time):
    """A note when the record ends before the last communication point, (n - 1) h, of a run to
    stop_time [s] (its last value, ground[-1] [m/s2], is then held to the end); else None."""
    if (len(ground) - 1) * h <= record.duration + 1e-9 * h:
        return None
    return (f"the ground-motion record ends at t = {record.duration:g} s, before the stop time {stop_time:g} s: "
            f"its last value, {ground[-1]:g} m/s2, is held to the end")
