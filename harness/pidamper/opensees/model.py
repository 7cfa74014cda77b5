"""An engineer's OpenSeesPy model file, run to build the structure, and the ground motion it gets.

A model file is plain Python that builds the structure with ordinary `ops` commands (nodes, masses,
materials, elements, constraints, damping: `modalDamping` or `rayleigh`, gravity if it has any) and
runs no dynamic analysis: pidamper owns the analysis, the ground motion and the units.  It may
`import openseespy.opensees as ops` itself: OpenSeesPy is loaded first with its bundled libraries
(pidamper.oracles.opensees.load), so no LD_LIBRARY_PATH is needed.
"""
import runpy
from pathlib import Path

import numpy as np

from ..forcing.ground_motion import read_record
from ..oracles.opensees import load
from .coupling import CouplingError


def build_model(path):
    """Run the model file at `path` in a fresh OpenSees domain; returns the `ops` module."""
    path = Path(path)
    if not path.is_file():
        raise CouplingError(f"--opensees = {str(path)!r} is not allowed: no such file (a Python file that builds "
                            "the structure with openseespy)")
    ops = load()
    ops.wipe()
    runpy.run_path(str(path), run_name="__opensees_model__")
    if not ops.getNodeTags():
        raise CouplingError(f"--opensees = {str(path)!r} is not allowed: the file built no nodes")
    return ops


def ground_samples(path, h, stop_time, scale=1.0):
    """The record at `path` (.AT2 or .csv, m/s2 or g as the reader says) at the communication points
    k h, k = 0 .. n - 1, as an FMU input samples it (linear between the record's samples, its last
    value held after its end), times `scale`."""
    record = read_record(path)
    forcing = record.scaled(scale).to_forcing() if scale != 1.0 else record.to_forcing()
    n = int(round(stop_time / h))
    return np.array([float(forcing.value(k * h)) for k in range(n)]), record
