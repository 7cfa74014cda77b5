"""The FMU in independent hosts and checkers: libcosim, the FMU container runtime, a C host,
fmutool; and deployed outside this repository with nothing but fmpy."""
import json
import math
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import fmpy
import fmpy.validation
import numpy as np
import pytest

from pidamper import FmuStepper

W2 = math.sqrt(9.81)
FREE = {"theta_dot_0": 0.7 * W2}
OTHER = {"FR": 2.0, "e": 0.5, "d": 0.05, "theta_dot_0": 1.0}
C_HOST = Path(__file__).parent / "c_host" / "host.c"
STATE_HOST = C_HOST.with_name("state_host.c")


def fmpy_run(fmu_path, values, times, forces=None):
    """theta after each step, the FMU driven by fmpy's FMU2Slave with the host's own times."""
    out = []
    with FmuStepper(fmu_path, values) as s:
        t = 0.0
        for k, t_next in enumerate(times):
            if forces is not None:
                s.set("F", forces[k])
            s.do_step(t, t_next - t)
            t = t_next
            out.append(s.read()[0])
    return np.array(out)


def test_libcosim_two_instances_and_a_manipulated_force(fmu_path):
    from libcosimpy.CosimExecution import CosimExecution  # a test dependency (pyproject): no skip
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    md = fmpy.read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    step_ns, n = 1_000_000, 3000  # libcosim keeps time in integer nanoseconds
    ex = CosimExecution.from_step_size(step_size=step_ns)
    a = ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu_path), instance_name="a"))
    b = ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu_path), instance_name="b"))
    for index, values in ((a, FREE), (b, OTHER)):
        for name, value in values.items():
            ex.real_initial_value(index, vr[name], value)
    manipulator = CosimManipulator.create_override()
    ex.add_manipulator(manipulator=manipulator)
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer=observer)
    forces = [0.05 * math.sin(0.3 * k) for k in range(n)]
    got_a, got_b = [], []
    for k in range(n):
        manipulator.slave_real_values(a, [vr["F"]], [forces[k]])
        assert ex.step()
        got_a.append(observer.last_real_values(a, [vr["theta"]])[0])
        got_b.append(observer.last_real_values(b, [vr["theta"]])[0])
    times = [(k + 1) * step_ns / 1e9 for k in range(n)]
    ref_a = fmpy_run(fmu_path, FREE, times, forces)
    ref_b = fmpy_run(fmu_path, OTHER, times)
    assert observer.last_integer_values(a, [vr["impacts"]])[0] > 20
    assert np.max(np.abs(np.array(got_a) - ref_a)) <= 1e-12 * np.max(np.abs(ref_a))
    assert np.max(np.abs(np.array(got_b) - ref_b)) <= 1e-12 * np.max(np.abs(ref_b))


def test_fmu_container_runtime(fmu_path, tmp_path):
    """fmu-manipulation-toolbox wraps the FMU in its C container runtime; fmpy runs the container."""
    tool = shutil.which("fmucontainer") or str(Path(sys.executable).with_name("fmucontainer"))
    assert Path(tool).exists(), "fmu-manipulation-toolbox (a test dependency) installs fmucontainer"
    shutil.copy2(fmu_path, tmp_path / "PendulumImpactDamper.fmu")
    (tmp_path / "damper.csv").write_text("rule;from_fmu;from_port;to_fmu;to_port\n"
                                         "FMU;PendulumImpactDamper.fmu;;;\n"
                                         f"START;PendulumImpactDamper.fmu;theta_dot_0;{FREE['theta_dot_0']!r};\n")
    done = subprocess.run([tool, "-container", "damper.csv:0.01", "-fmu-directory", "."], cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    # the container runtime is a C host of its own: run it in a process that has loaded nothing
    # else (in a process that also holds pyarrow, as rerun brings it, its shared libraries clash)
    script = ("import sys, json, fmpy\n"
              "r = fmpy.simulate_fmu(sys.argv[1], stop_time=20.0, output_interval=0.01, output=['theta', 'impacts'])\n"
              "print(json.dumps({'theta': r['theta'].tolist(), 'impacts': int(r['impacts'][-1])}))\n")
    run = subprocess.run([sys.executable, "-c", script, str(tmp_path / "damper.fmu")], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    container = json.loads(run.stdout.strip().splitlines()[-1])
    container = {"theta": np.array(container["theta"]), "impacts": [container["impacts"]]}
    direct = fmpy.simulate_fmu(str(fmu_path), stop_time=20.0, output_interval=0.01, start_values=FREE,
                               output=["theta", "impacts"])
    assert container["impacts"][-1] == direct["impacts"][-1] > 100
    assert np.max(np.abs(container["theta"] - direct["theta"])) <= 1e-12 * np.max(np.abs(direct["theta"]))


@pytest.mark.parametrize("model", ["PendulumImpactDamper", "PendulumImpactDamperUnit"] + [
    f"{family}{n}" for family in ("DampedShearBuilding", "ShearBuilding") for n in (1, 2, 3, 10)])
def test_checkers_pass(fmu_path, model):
    """Every FMU `python -m build_fmu --storeys 1 2 3 10` builds passes fmutool's and fmpy's checks."""
    tool = shutil.which("fmutool") or str(Path(sys.executable).with_name("fmutool"))
    assert Path(tool).exists(), "fmu-manipulation-toolbox (a test dependency) installs fmutool"
    path = fmu_path.with_name(f"{model}.fmu")
    done = subprocess.run([tool, "-input", str(path), "-check"], capture_output=True, text=True)
    text = done.stdout + done.stderr
    assert done.returncode == 0 and "No semantic error" in text and "compliant with FMI-2.0" in text, text
    assert fmpy.validation.validate_fmu(str(path)) == []


def _compile_host(tmp_path, source=C_HOST):
    compiler = shutil.which("gcc") or shutil.which("cc")
    if not compiler:
        pytest.skip("no C compiler")
    headers = Path(fmpy.__file__).parent / "c-code"
    exe = tmp_path / source.stem
    subprocess.run([compiler, "-Wall", "-Wextra", "-Werror", "-I", str(headers), "-o", str(exe), str(source), "-ldl"],
                   check=True)
    return exe


def _unzipped(fmu_path, tmp_path):
    unzipped = tmp_path / "unzipped"
    if not unzipped.exists():
        with zipfile.ZipFile(fmu_path) as z:
            z.extractall(unzipped)
    return unzipped


def _run_host(exe, fmu_path, tmp_path, env, steps=2000, h=0.01, expect=0):
    """(theta, impacts, stderr) of the C host run in `env` (nothing of this process's environment)."""
    md = fmpy.read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    done = subprocess.run([str(exe), str(_unzipped(fmu_path, tmp_path)), md.guid, str(vr["theta_dot_0"]),
                           repr(FREE["theta_dot_0"]), str(vr["theta"]), str(vr["impacts"]), str(steps), repr(h)],
                          capture_output=True, text=True, env=env, timeout=120)
    assert done.returncode == expect, done.stderr[-2000:]
    if expect:
        return None, None, done.stderr
    theta, impacts = done.stdout.split()
    return float(theta), int(impacts), done.stderr


# what a native system simulator started from a desktop has: no Python variables, no LD_*
PLAIN_ENV = {"PATH": "/usr/local/bin:/usr/bin:/bin", "HOME": str(Path.home()), "LANG": "C.UTF-8"}
BUILD_LIBPYTHON = Path(sysconfig.get_config_var("LIBDIR")) / sysconfig.get_config_var("INSTSONAME")


def _fmpy_reference(fmu_path, steps=2000, h=0.01):
    with FmuStepper(fmu_path, FREE) as s:
        t = 0.0
        for _ in range(steps):
            s.do_step(t, h)
            t += h
        return s.read()[0], s.get("impacts")


def test_c_host_without_preload_finds_python_by_itself(fmu_path, tmp_path):
    """dlopen(RTLD_NOW | RTLD_LOCAL) from a plain environment: the FMU starts the build's
    libpython isolated, with that libpython's standard library, although PATH finds another
    Python (Debian's /usr/bin/python3) first."""
    exe = _compile_host(tmp_path)
    if not BUILD_LIBPYTHON.exists():
        pytest.skip(f"this Python has no shared libpython ({BUILD_LIBPYTHON})")
    theta, impacts, err = _run_host(exe, fmu_path, tmp_path, PLAIN_ENV)
    assert f"libpython: {BUILD_LIBPYTHON}" in err
    assert (theta, impacts) == _fmpy_reference(fmu_path)  # the same interpreter: bit for bit


def test_c_host_uses_the_libpython_it_is_pointed_at(fmu_path, tmp_path):
    """PIDAMPER_LIBPYTHON names another Python 3.11 (Debian's): it runs with its own standard
    library (mixing it with the build's makes fmi2Instantiate fail)."""
    other = Path("/usr/lib/x86_64-linux-gnu") / sysconfig.get_config_var("INSTSONAME")
    if not other.exists() or other.resolve() == BUILD_LIBPYTHON.resolve():
        pytest.skip(f"no second libpython of this version at {other}")
    exe = _compile_host(tmp_path)
    theta, impacts, err = _run_host(exe, fmu_path, tmp_path, {**PLAIN_ENV, "PIDAMPER_LIBPYTHON": str(other)})
    assert f"libpython: {other}" in err and str(BUILD_LIBPYTHON) not in err
    ref_theta, ref_impacts = _fmpy_reference(fmu_path)
    assert impacts == ref_impacts and theta == pytest.approx(ref_theta, abs=1e-12)


def test_c_host_without_any_python_says_what_it_looked_for(fmu_path, tmp_path):
    """A layer built for a Python that is nowhere (3.99): fmi2Instantiate returns NULL after a
    message naming each place it looked and how to point it at one."""
    from build_fmu.native import compile_layer

    exe = _compile_host(tmp_path)
    unzipped = _unzipped(fmu_path, tmp_path)
    description = (unzipped / "modelDescription.xml").read_bytes()
    missing = "/nowhere/lib/libpython3.99.so.1.0"
    compile_layer(description, "PendulumImpactDamper", unzipped / "binaries" / "linux64" / "PendulumImpactDamper.so",
                  BUILD_LIBPYTHON=missing, PY_MINOR="3.99")
    _, _, err = _run_host(exe, fmu_path, tmp_path, {**PLAIN_ENV, "PIDAMPER_LIBPYTHON": "/nowhere/else.so"}, expect=3)
    assert "no usable Python 3.99 runtime" in err and "/nowhere/else.so" in err and missing in err
    assert "set PIDAMPER_LIBPYTHON" in err and "libpython3.99.so.1.0:" in err


def test_c_host_with_libpython_preloaded(fmu_path, tmp_path):
    """The old way still works: libpython preloaded (the FMU uses the runtime it finds in the process)."""
    exe = _compile_host(tmp_path)
    if not BUILD_LIBPYTHON.exists():
        pytest.skip(f"this Python has no shared libpython ({BUILD_LIBPYTHON})")
    theta, impacts, _ = _run_host(exe, fmu_path, tmp_path, {**PLAIN_ENV, "LD_PRELOAD": str(BUILD_LIBPYTHON)})
    assert (theta, impacts) == _fmpy_reference(fmu_path)  # same interpreter: bit for bit


def test_c_host_restores_a_state_into_a_variable_it_never_initialised(fmu_path, tmp_path):
    """fmi2DeSerializeFMUstate's FMUstate is an output (FMI 2.0): a C host passes a variable holding
    0xdeadbeef.  The layer writes the new state there without reading or freeing what it held (it
    used to free it: SIGSEGV), and the run from the restored state repeats the first bit for bit."""
    exe = _compile_host(tmp_path, STATE_HOST)
    md = fmpy.read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    done = subprocess.run([str(exe), str(_unzipped(fmu_path, tmp_path)), md.guid, str(vr["theta_dot_0"]),
                           repr(FREE["theta_dot_0"]), str(vr["theta"]), "150", "0.01"],
                          capture_output=True, text=True, env=PLAIN_ENV, timeout=120)
    assert done.returncode == 0, f"exit {done.returncode}: {done.stderr[-2000:]}"
    status, first, again = done.stdout.split()
    assert status == "0" and float(first) == float(again) and float(first) != 0.0


def _oldest_shared_python():
    root = Path.home() / ".pyenv" / "versions"
    found = []
    for lib in root.glob("3.*/lib/libpython3.*.so"):
        version = tuple(int(p) for p in lib.parent.parent.name.split(".")[:2])
        if version >= (3, 8):  # pythonfmu 0.7's own package needs typing.Literal (3.8+)
            found.append((version, lib))
    return min(found) if found else (None, None)


def test_c_host_under_the_oldest_python(fmu_path, tmp_path):
    """A host process holding another Python (3.8, preloaded with its PYTHONHOME): the FMU runs on it."""
    version, lib = _oldest_shared_python()
    if lib is None:
        pytest.skip("no pyenv CPython >= 3.8 with a shared libpython on this machine")
    exe = _compile_host(tmp_path)
    env = {**PLAIN_ENV, "LD_PRELOAD": str(lib), "PYTHONHOME": str(lib.parent.parent)}
    theta, impacts, err = _run_host(exe, fmu_path, tmp_path, env)
    assert f"libpython: {lib}" in err
    ref_theta, ref_impacts = _fmpy_reference(fmu_path)
    assert impacts == ref_impacts
    assert theta == pytest.approx(ref_theta, abs=1e-12), f"Python {version}"


@pytest.mark.slow
@pytest.mark.timeout(600)
def test_deployed_outside_the_repository_with_only_fmpy(fmu_path, tmp_path):
    """A copy of the .fmu in a folder of its own, a fresh virtual environment holding only fmpy."""
    site = tmp_path / "elsewhere"
    site.mkdir()
    fmu = site / "PendulumImpactDamper.fmu"
    shutil.copy2(fmu_path, fmu)
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = venv / "bin" / "python"
    subprocess.run([str(py), "-m", "pip", "install", "--quiet", "fmpy"], check=True, timeout=500)
    script = (
        "import sys, zipfile, io, numpy as np, fmpy, importlib.util\n"
        "assert importlib.util.find_spec('pythonfmu') is None and importlib.util.find_spec('pidamper') is None\n"
        "r = fmpy.simulate_fmu(sys.argv[1], stop_time=20.0, output_interval=0.01)\n"
        "ref = np.genfromtxt(io.BytesIO(zipfile.ZipFile(sys.argv[1]).read("
        "'documentation/PendulumImpactDamper_ref.csv')), delimiter=',', names=True)\n"
        "print(max(float(np.max(np.abs(r[n] - ref[n]))) for n in ref.dtype.names if n != 'time'))\n")
    done = subprocess.run([str(py), "-c", script, str(fmu)], cwd=site, capture_output=True, text=True,
                          env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"})
    assert done.returncode == 0, done.stderr[-3000:]
    assert float(done.stdout.strip()) == 0.0


def test_without_a_c_compiler_the_fmu_keeps_pythonfmus_binary(fmu_path, tmp_path, monkeypatch):
    """A build machine without a C compiler: the layer is not installed, a warning says what that
    costs, and the FMU keeps pythonfmu's plain binary under the model identifier."""
    from build_fmu import native

    plain = native.without_layer(fmu_path, tmp_path / "plain.fmu")
    before = plain.read_bytes()
    monkeypatch.setattr(native.shutil, "which", lambda name: None)
    with pytest.warns(UserWarning, match="no C compiler"):
        assert native.install(plain) is False
    assert plain.read_bytes() == before
    names = zipfile.ZipFile(plain).namelist()
    assert "binaries/linux64/PendulumImpactDamper.so" in names
    assert "binaries/linux64/PendulumImpactDamper_pythonfmu.so" not in names


@pytest.mark.parametrize("model", ["PendulumImpactDamper", "PendulumImpactDamperUnit", "DampedShearBuilding3",
                                   "ShearBuilding3"])
def test_every_fmu_in_a_native_host_under_an_awkward_path(fmu_path, tmp_path, model):
    """Each FMU as a system simulator sees it: unpacked under a path with spaces, an accent and
    parentheses, opened by a C host with RTLD_NOW | RTLD_LOCAL from a plain environment (the FMU
    starts Python by itself, in UTF-8 mode: before, a non-ASCII folder failed fmi2Instantiate there),
    every output read at every step; then fmpy from the same folder, and a step before
    initialization refused with fmi2Error (after fmi2Reset the instance runs)."""
    from fmpy.fmi1 import FMICallException
    from fmpy.fmi2 import FMU2Slave

    from pidamper.benchmarks.floor import build_every_output_host

    fmu = fmu_path.with_name(f"{model}.fmu")
    unzipped = fmpy.extract(str(fmu), unzipdir=str(tmp_path / "José models (copy)"))
    md = fmpy.read_model_description(str(fmu))
    outputs = [f"{v.type[0]}:{v.valueReference}" for v in md.modelVariables if v.causality == "output"]
    exe = build_every_output_host(tmp_path)
    done = subprocess.run([str(exe), unzipped, md.coSimulation.modelIdentifier, md.guid, "200", "0.01"] + outputs,
                          capture_output=True, text=True, env=PLAIN_ENV, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    result = fmpy.simulate_fmu(unzipped, stop_time=1.0, output_interval=0.01)
    assert len(result) == 101 and all(np.isfinite(result[n]).all() for n in result.dtype.names)
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName="early")
    slave.instantiate()
    try:
        with pytest.raises(FMICallException) as err:
            slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.01)
        assert err.value.status == 3  # fmi2Error, not fmi2Fatal; fmi2Reset leaves the error state
        slave.reset()
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.exitInitializationMode()
        slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.01)
        slave.terminate()
    finally:
        slave.freeInstance()
