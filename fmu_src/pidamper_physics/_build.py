"""Which build of this package runs: its modules compiled (Cython, from these very sources) or the
plain Python.  Imported first by the package; never compiled itself.

The compile step (build_fmu.compile) leaves an extension module beside each compiled source and a
manifest, COMPILED, of the sources' digests it compiled from.  The compiled build runs when the
manifest matches every source here (a source edited since, or a manifest of another Python's
extensions, makes it stale), every extension loads, and PIDAMPER_PURE is not "1".  Otherwise this
package's submodules load from their sources only: its folder's path finder is replaced by one
that knows no extension modules, so an extension that is stale, absent or fails to load never
runs (nor breaks the import).  BUILD says which build runs, and why the plain one.
"""
import hashlib
import importlib
import importlib.machinery as machinery
import os
import sys

#: the manifest's file name, beside the sources
COMPILED = "_compiled.txt"
#: typing files any compiled module may cimport (C bodies of plain-Python helpers, never compiled)
SHARED_TYPING = ("_ccomplex.pxd", "_clist.pxd")


def digest(path):
    """SHA-256 of a file's bytes (hex)."""
    with open(path, "rb") as handle:
        return hashlib.sha256(handle.read()).hexdigest()


def typing(folder, name):
    """Digest of what types module `name` in folder: its .pxd with the shared typing files, or '-'
    without a .pxd."""
    pxd = os.path.join(folder, name + ".pxd")
    if not os.path.isfile(pxd):
        return "-"
    parts = [digest(pxd)] + [digest(os.path.join(folder, shared)) for shared in SHARED_TYPING]
    return hashlib.sha256(" ".join(parts).encode()).hexdigest()


def manifest(folder):
    """{module: [digest of its .py, typing() of it, its extension's file name]} of the compile
    step's manifest in folder (empty without one)."""
    path = os.path.join(folder, COMPILED)
    if not os.path.isfile(path):
        return {}
    rows = {}
    with open(path) as handle:
        for line in handle:
            parts = line.split()
            if len(parts) == 4:
                rows[parts[0]] = parts[1:]
    return rows


def _stale(folder, rows):
    """Why the manifest does not describe these sources and this Python, or None."""
    suffix = machinery.EXTENSION_SUFFIXES[0]
    for name, (source, typed, extension) in sorted(rows.items()):
        if digest(os.path.join(folder, name + ".py")) != source:
            return f"{name}.py changed since it was compiled (run python -m build_fmu.compile)"
        if typing(folder, name) != typed:
            return (f"{name}.pxd or the shared {', '.join(SHARED_TYPING)} changed since it was compiled "
                    "(run python -m build_fmu.compile)")
        if not extension.endswith(suffix) or not os.path.isfile(os.path.join(folder, extension)):
            return f"no extension {name}{suffix} for this Python"
    return None


def _sources_only(package, folder):
    """Load the package's submodules from their sources from now on (drop any already loaded)."""
    for name in [n for n in sys.modules if n.startswith(package + ".") and n != __name__]:
        del sys.modules[name]
    sys.path_importer_cache[folder] = machinery.FileFinder(
        folder, (machinery.SourceFileLoader, machinery.SOURCE_SUFFIXES),
        (machinery.SourcelessFileLoader, machinery.BYTECODE_SUFFIXES))
    importlib.invalidate_caches()


def _modules(folder):
    return sorted(name[:-3] for name in os.listdir(folder)
                  if name.endswith(".py") and name[:-3] not in ("__init__", "_build"))


def select(package, folder):
    """Choose the build of `package` (its folder): the compiled one if it is current and loads,
    else the plain Python; returns BUILD's text.  Every module is loaded now, either way: the FMUs
    of several models ship this package under one name (its sources' digest), and the host
    process may have removed the first one's folder by the time another imports a module of it."""
    rows = manifest(folder)
    why = stale(folder)
    if why is None:
        try:
            for name in sorted(rows):
                module = importlib.import_module(f"{package}.{name}")
                if not module.__file__.endswith(tuple(machinery.EXTENSION_SUFFIXES)):
                    raise ImportError(f"{name} loaded from {module.__file__}")
        except ImportError as err:
            why = f"an extension did not load: {err}"
    if why is None:
        return f"compiled ({len(rows)} modules, CPython {sys.version_info[0]}.{sys.version_info[1]})"
    _sources_only(package, folder)
    for name in _modules(folder):
        importlib.import_module(f"{package}.{name}")
    return f"pure Python ({why})"


def stale(folder):
    """Why the compiled build in folder would not run here (None: it is current), without loading it."""
    if os.environ.get("PIDAMPER_PURE") == "1":
        return "PIDAMPER_PURE=1"
    rows = manifest(folder)
    return _stale(folder, rows) if rows else "not compiled"


# loaded as the package's module, choose; loaded by path (build_fmu reads the manifest), do not
BUILD = select(__package__, os.path.dirname(os.path.abspath(__file__))) if __package__ else None
