"""The physics' two builds (issue 36): the compiled one (Cython, from the same sources) and the plain
Python give the same outputs bit for bit; the package runs the compiled build only while it is
current and loads, and falls back to the plain Python otherwise (a source edited since, an
extension that does not load, PIDAMPER_PURE=1), saying which; an FMU ships its own compiled copy,
which runs whatever the host process has loaded, and runs the plain Python with its extensions
broken or removed, with the same outputs."""
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from build_fmu.compile import compile_package, unavailable
from build_fmu.locations import sources

ROOT = Path(__file__).resolve().parents[1]
CAN_COMPILE = unavailable() is None
needs_compiler = pytest.mark.skipif(not CAN_COMPILE, reason=f"no compiled build here: {unavailable()}")


def _python(code, env=None, cwd=None):
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=cwd, timeout=600,
                          env={**os.environ, **(env or {})})
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_build_is_said():
    import pidamper_physics

    build = pidamper_physics.BUILD
    assert build.startswith("compiled (") or build.startswith("pure Python (")
    if os.environ.get("PIDAMPER_PURE") == "1":
        assert build == "pure Python (PIDAMPER_PURE=1)"


@needs_compiler
def test_compiled_and_plain_builds_are_bit_for_bit(tmp_path):
    """tools/core_cases.py (every level, contact form, chatter, buildings of 1, 3, 10 storeys, the
    unit, state round trips) in a compiled copy of the package and in the plain one."""
    package = tmp_path / "pidamper_physics"
    shutil.copytree(sources()[1], package, ignore=shutil.ignore_patterns("*.so", "_compiled.txt", "__pycache__"))
    compile_package(package, "pidamper_physics")
    env = {"PYTHONPATH": str(tmp_path)}
    probe = "import pidamper_physics as p, pidamper_physics.modal as m; print(p.BUILD); print(m.__file__)"
    build, where = _python(probe, env).split("\n")[:2]
    assert build.startswith("compiled") and where.endswith(".so") and where.startswith(str(tmp_path))
    run = [sys.executable, str(ROOT / "tools" / "core_cases.py")]
    compiled = subprocess.run(run, capture_output=True, text=True, env={**os.environ, **env}, check=True).stdout
    plain = subprocess.run(run, capture_output=True, text=True, env={**os.environ, **env, "PIDAMPER_PURE": "1"},
                           check=True).stdout
    assert len(compiled) > 1e6 and compiled == plain


@needs_compiler
def test_a_stale_or_broken_compiled_build_falls_back_to_the_plain_python(tmp_path):
    package = tmp_path / "pidamper_physics"
    shutil.copytree(sources()[1], package, ignore=shutil.ignore_patterns("*.so", "_compiled.txt", "__pycache__"))
    compile_package(package, "pidamper_physics")
    env = {"PYTHONPATH": str(tmp_path)}
    probe = "import pidamper_physics as p, pidamper_physics.modal as m; print(p.BUILD); print(m.__file__)"
    source = package / "impact.py"
    text = source.read_text()
    source.write_text(text + "\n")  # edited since it was compiled
    build, where = _python(probe, env).split("\n")[:2]
    assert build == "pure Python (impact.py changed since it was compiled (run python -m build_fmu.compile))"
    assert where.endswith("modal.py")
    source.write_text(text)
    shared = package / "_ccomplex.pxd"  # a typing file the compiled modules cimport (no module of its own)
    typing = shared.read_text()
    shared.write_text(typing + "\n")
    build, where = _python(probe, env).split("\n")[:2]
    assert build.startswith("pure Python (") and "or the shared _ccomplex.pxd" in build
    assert "changed since it was compiled" in build
    assert where.endswith("modal.py")
    shared.write_text(typing)
    build, _ = _python(probe, env).split("\n")[:2]
    assert build.startswith("compiled (")
    broken = next(package.glob("peaks*.so"))
    broken.write_bytes(b"not an extension module")  # an extension that does not load
    build, where = _python(probe, env).split("\n")[:2]
    assert build.startswith("pure Python (an extension did not load") and where.endswith("modal.py")


@needs_compiler
def test_an_edited_shared_typing_file_regenerates_the_c_of_the_typed_modules(tmp_path):
    """Cythonize's timestamps miss a shared .pxd cimported as `from . cimport _clist`: the compile
    step removes the generated C of every module whose sources or typing changed since it was made,
    so that cythonize makes it again (and only those: a module without a .pxd keeps its C)."""
    from build_fmu import compile as step

    package = tmp_path / "pidamper_physics"
    shutil.copytree(sources()[1], package, ignore=shutil.ignore_patterns("*.so", "_compiled.txt", "__pycache__"))
    select = step.selector(package)
    names = step.modules(package)
    work = tmp_path / "work"
    (work / "pidamper_physics").mkdir(parents=True)
    made = step._forget_changed_c(package, work, "pidamper_physics", names, select)
    (work / step.GENERATED).write_text("".join(f"{name} {digests}\n" for name, digests in made.items()))
    for name in names:
        (work / "pidamper_physics" / f"{name}.c").write_text("/* generated */")
    assert step._forget_changed_c(package, work, "pidamper_physics", names, select) == made
    assert all((work / "pidamper_physics" / f"{name}.c").is_file() for name in names)  # nothing changed
    shared = package / "_clist.pxd"
    shared.write_text(shared.read_text() + "\n")
    step._forget_changed_c(package, work, "pidamper_physics", names, select)
    left = {name for name in names if (work / "pidamper_physics" / f"{name}.c").is_file()}
    assert left == {name for name in names if not (package / f"{name}.pxd").is_file()}
    assert "modal" not in left and "eigen" in left


def _fmu_run(fmu, extra_env=None):
    """Every output of 300 steps of the FMU under a ground motion, and what it said of its physics."""
    code = f"""
import fmpy, json, pidamper_physics
from pidamper import forcing
from pidamper.running.instance import FmuInstance
said = []
md = fmpy.read_model_description({str(fmu)!r})
names = [v.name for v in md.modelVariables if v.causality == "output"]
signal = forcing.kanai_tajimi(3.0, pga=4.0, seed=5, dt=0.01)
rows = []
with FmuInstance({str(fmu)!r}, {{"fidelity": 1, "zeta_s": 0.02, "storey[1].Fy": 2e5, "p_delta": 1}},
                 logger=lambda s, t: said.append(t)) as f:
    for k in range(300):
        f.set("a_g", float(signal.value(0.01 * k)))
        f.do_step(0.01 * k, 0.01)
        rows.append([repr(f.get(n)) for n in names])
print(json.dumps([said[0], rows]))
"""
    import json

    return json.loads(_python(code, extra_env))


@needs_compiler
def test_the_fmu_runs_its_own_compiled_physics_and_the_plain_python_without_it(fmu_dir, tmp_path):
    """DampedShearBuilding3 (yielding, the damper impacting) in a process that has the source
    tree's physics loaded: compiled; its extensions broken, or removed: the plain Python, every
    output of every step the same."""
    fmu = fmu_dir / "DampedShearBuilding3.fmu"
    said, compiled = _fmu_run(fmu)
    assert "physics compiled" in said
    with zipfile.ZipFile(fmu) as z:
        names = z.namelist()
        extensions = [n for n in names if n.startswith("resources/pidamper_physics_") and n.endswith(".so")]
        assert len(extensions) > 20 and not any(n.endswith(".c") for n in names)
        for label, keep in (("broken", lambda n: True), ("removed", lambda n: n not in extensions)):
            copy = tmp_path / label / fmu.name
            copy.parent.mkdir()
            with zipfile.ZipFile(copy, "w") as out:
                for n in filter(keep, names):
                    out.writestr(n, b"garbage" if n in extensions and label == "broken" else z.read(n))
            said, rows = _fmu_run(copy)
            assert "physics pure Python" in said and rows == compiled, label
