"""Compile the physics package from its own sources: `python -m build_fmu.compile [--clean]`.

Each module of the package (but `__init__` and `_build`) is compiled by Cython in pure-Python
mode, typed where a `.pxd` beside it says so, into an extension module beside its source, with the
C compiler's strict floating point (-ffp-contract=off, no fast math: the compiled build gives the
plain one's results bit for bit).  A manifest (_build.COMPILED) records the digests of the sources
each extension was compiled from: the package runs the compiled build only while they match
(pidamper_physics/_build.py).

Two places get a compiled build:
- fmu_src/pidamper_physics itself (`python -m build_fmu.compile`), which the harness and the tests
  import;
- the FMU's own copy (fmu_physics), named pidamper_physics_<tag> by a digest of the sources and
  the compile settings.  A Cython module resolves its relative imports through the package name it
  was compiled under (it looks that name up in sys.modules first), so the FMU's copy is compiled
  under the FMU's name, never the source tree's: each FMU runs its own modules whatever else the
  host process has loaded.  It is built once per tag in build/fmu-physics/ and shared by every
  model's FMU.
Without Cython or a C compiler, or with PIDAMPER_PURE=1, nothing is compiled and the plain Python
runs.  The generated C stays in build/.
"""
import argparse
import hashlib
import importlib.util
import os
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from .locations import PHYSICS, sources

#: modules that stay Python: the package's entry, the build selector itself and the plain bodies of
#: the shared C helpers (their .pxd is cimported by the compiled modules: _build.SHARED_TYPING)
PLAIN = ("__init__", "_build", "_ccomplex", "_clist")
#: C flags: optimised, and floating point exactly as the plain build computes it; Cython's own complex
#: type, not C99's (whose x + y*I loses a real part of -0.0; Cython's is CPython's arithmetic, mixed
#: real and complex operands included), its abs() by hypot as CPython's (HAVE_HYPOT: without it
#: Cython takes sqrt(re^2 + im^2), and CPython 3.11's pyconfig.h no longer says it has hypot)
CFLAGS = ["-O2", "-ffp-contract=off", "-fno-fast-math", "-fno-strict-aliasing", "-DCYTHON_CCOMPLEX=0",
          "-DHAVE_HYPOT=1"]
#: Cython's directives (Python semantics kept: division by zero raises, indices are checked)
DIRECTIVES = {"language_level": 3, "binding": False, "embedsignature": False}
ROOT = Path(__file__).resolve().parent.parent
BUILD = ROOT / "build"


def modules(folder):
    """The module names of the physics package in folder that are compiled."""
    return sorted(p.stem for p in Path(folder).glob("*.py") if p.stem not in PLAIN)


def extension_name(name):
    return name + sysconfig.get_config_var("EXT_SUFFIX")


def selector(folder):
    """The package's _build module loaded by path (its functions; it chooses nothing so loaded)."""
    spec = importlib.util.spec_from_file_location("_pidamper_build_selector", Path(folder) / "_build.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def unavailable():
    """Why the physics cannot be compiled here (None: it can)."""
    if os.environ.get("PIDAMPER_PURE") == "1":
        return "PIDAMPER_PURE=1"
    if importlib.util.find_spec("Cython") is None:
        return "Cython is not installed"
    compiler = (sysconfig.get_config_var("CC") or "cc").split()[0]
    if shutil.which(compiler) is None:
        return f"no C compiler ({compiler})"
    return None


def settings():
    """What besides the sources decides the compiled files: Cython's version, the flags, the ABI."""
    import Cython

    return f"Cython {Cython.__version__} {' '.join(CFLAGS)} {DIRECTIVES} {sysconfig.get_config_var('EXT_SUFFIX')}"


def compile_package(folder, package, quiet=True):
    """Compile the package `package` whose folder is `folder` (named so) in place, and write its
    manifest; the extension modules built.  Raises if Cython or the compiler fails."""
    from Cython.Build import cythonize
    from setuptools import Distribution, Extension

    folder = Path(folder)
    names = modules(folder)
    work = BUILD / "cython" / package
    extensions = [Extension(f"{package}.{name}", [f"{package}/{name}.py"], extra_compile_args=CFLAGS)
                  for name in names]
    cwd = os.getcwd()
    select = selector(folder)
    generated = _forget_changed_c(folder, work, package, names, select)
    os.chdir(folder.parent)  # extension names map to paths under the package's parent
    try:
        ext = cythonize(extensions, compiler_directives=DIRECTIVES, build_dir=str(work), quiet=quiet,
                        nthreads=os.cpu_count() or 1)
        (work / GENERATED).write_text("".join(f"{name} {digests}\n" for name, digests in generated.items()))
        dist = Distribution({"name": package, "ext_modules": ext})
        cmd = dist.get_command_obj("build_ext")
        cmd.inplace, cmd.parallel = True, os.cpu_count() or 1
        cmd.build_temp, cmd.build_lib = str(work / "temp"), str(work / "lib")
        stamp = work / "settings.txt"  # the C is recompiled when the flags changed, not only the sources
        cmd.force = not stamp.is_file() or stamp.read_text() != settings()
        cmd.ensure_finalized()
        cmd.run()
        stamp.write_text(settings())
    finally:
        os.chdir(cwd)
    lines = []
    for name in names:
        lines.append(f"{name} {select.digest(folder / f'{name}.py')} {select.typing(folder, name)} "
                     f"{extension_name(name)}\n")
    (folder / select.COMPILED).write_text("".join(lines))
    return [folder / extension_name(name) for name in names]


#: what each generated C file in the work folder was made from: module, digests of its .py and its
#: typing (_build.typing), the settings
GENERATED = "generated.txt"


def _forget_changed_c(folder, work, package, names, select):
    """Remove the generated C of each module whose .py, typing or settings differ from those it was
    made from (the work folder's GENERATED): cythonize's own timestamps miss a shared .pxd that a
    module cimports with `from . cimport` (_build.SHARED_TYPING), a C file made from another copy of
    the sources, and new directives.  Returns what the C will be made from."""
    record = work / GENERATED
    made = dict(line.split(" ", 1) for line in record.read_text().splitlines()) if record.is_file() else {}
    made_with = hashlib.sha256(settings().encode()).hexdigest()[:16]
    current = {name: f"{select.digest(folder / f'{name}.py')} {select.typing(folder, name)} {made_with}"
               for name in names}
    for name, digests in current.items():
        if made.get(name) != digests:
            (work / package / f"{name}.c").unlink(missing_ok=True)
    return current


def physics_files(folder):
    """The physics package's sources and typing files (what both builds are made of)."""
    return sorted(p for p in Path(folder).glob("*") if p.suffix in (".py", ".pxd"))


def fmu_tag(folder):
    """12 hex digits naming the FMU's physics package: its sources, and the compile settings when
    it will be compiled (unavailable() is None)."""
    digest = hashlib.sha256()
    for path in physics_files(folder):
        digest.update(path.name.encode() + b"\0" + path.read_bytes() + b"\0")
    digest.update((settings() if unavailable() is None else "plain Python").encode())
    return digest.hexdigest()[:12]


def fmu_physics(folder=None):
    """(folder, package name, build text) of the physics package an FMU ships: compiled under its
    own name in build/fmu-physics/ (once per tag; a lock keeps concurrent builds apart), or the
    plain sources copied there when it cannot be compiled."""
    from filelock import FileLock

    folder = Path(folder or sources()[1])
    name = f"{PHYSICS}_{fmu_tag(folder)}"
    target = BUILD / "fmu-physics" / name
    why = unavailable()
    target.parent.mkdir(parents=True, exist_ok=True)
    with FileLock(str(target) + ".lock"):
        ready = (target / selector(folder).COMPILED) if why is None else (target / "__init__.py")
        if not ready.is_file():
            shutil.rmtree(target, ignore_errors=True)
            target.mkdir()
            for path in physics_files(folder):
                shutil.copy2(path, target / path.name)
            if why is None:
                for extension in compile_package(target, name):
                    strip(extension)
    return target, name, (f"pure Python ({why})" if why else f"compiled ({len(modules(target))} modules)")


def strip(path):
    """Strip an extension module of what loading it does not need (symbols, debug information)."""
    tool = shutil.which("strip")
    if tool is not None:
        subprocess.run([tool, "--strip-unneeded", str(path)], check=True)


def shipped(folder):
    """The files of an FMU's physics package folder (fmu_physics) that go into the FMU."""
    select = selector(folder)
    rows = select.manifest(folder)
    return physics_files(folder) + ([Path(folder) / select.COMPILED] + [Path(folder) / row[2] for row in rows.values()]
                                    if rows else [])


def clean(folder):
    """Remove the extension modules and the manifest (the plain Python runs)."""
    for path in Path(folder).glob("*" + sysconfig.get_config_var("EXT_SUFFIX")):
        path.unlink()
    (Path(folder) / selector(folder).COMPILED).unlink(missing_ok=True)


def main(argv=None):
    p = argparse.ArgumentParser(prog="python -m build_fmu.compile", description=__doc__.split("\n")[0])
    p.add_argument("--clean", action="store_true", help="remove the compiled modules (the plain Python runs)")
    args = p.parse_args(argv)
    folder = sources()[1]
    if args.clean:
        clean(folder)
        print(f"removed the compiled modules of {folder}")
        return 0
    why = unavailable()
    if why is not None:
        print(f"not compiled ({why}): the plain Python runs", file=sys.stderr)
        return 0
    built = compile_package(folder, PHYSICS)
    print(f"compiled {len(built)} modules of {folder} ({sysconfig.get_config_var('EXT_SUFFIX')})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
