"""FMUs unpacked once per process: a host that runs one FMU many times (a study's records, a parameter
sweep, a benchmark's repeats) reads its model description and unzips it once, not per run.

    folder, md = unpacked("dist/ShearBuilding3.fmu")
    fmpy.simulate_fmu(folder, model_description=md, ...)

A file that changed since (its size or modification time) is unpacked again into a new folder; an
earlier folder stays until the process exits, since an instance may still run from it.  The folders
are removed at the exit of the process that made them (a forked child never removes its parent's).
They are shared: read them, never write into them.
"""
import atexit
import os
import shutil
import tempfile
import threading

import fmpy

_LOCK = threading.Lock()
_BY_PATH = {}  # absolute path -> ((size, mtime_ns), folder, model description)
_MADE = []  # (pid, folder) of every folder unpacked here


def unpacked(path):
    """(folder, model description) of the FMU file at `path`, unpacked on first use in this process
    and again only when the file changed."""
    path = os.path.abspath(os.fspath(path))
    stat = os.stat(path)
    stamp = (stat.st_size, stat.st_mtime_ns)
    with _LOCK:
        known = _BY_PATH.get(path)
        if known is not None and known[0] == stamp and os.path.isdir(known[1]):
            return known[1], known[2]
        md = fmpy.read_model_description(path)
        folder = fmpy.extract(path, unzipdir=tempfile.mkdtemp(prefix="pidamper_fmu_"))
        _BY_PATH[path] = (stamp, folder, md)
        _MADE.append((os.getpid(), folder))
        return folder, md


@atexit.register
def _remove():
    pid = os.getpid()
    for owner, folder in _MADE:
        if owner == pid:
            shutil.rmtree(folder, ignore_errors=True)
