"""Defects at the FMU's boundary to its host, each shown by a test that failed before its fix: a host
could make the model write 8 bytes to any address where the native layer is absent; a freed fatal
instance left the model a view into freed memory; build_fmu's builder and native imported each
other.  (fmi2DeSerializeFMUstate into a variable the host never initialised: tests/test_hosts.py.)
The FMU cases run in child processes."""
import ast
import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import build_fmu

# A host pokes the value reference after the last listed one (the native layer's hidden String)
# with the address of a buffer it owns, then runs; the same run without the poke is the reference.
POKE_HIDDEN_STRING = r'''
import ctypes, json, sys, fmpy
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
path = sys.argv[1]
md = fmpy.read_model_description(path)
vr = {v.name: v.valueReference for v in md.modelVariables}
hidden = len(md.modelVariables)
unzipped = fmpy.extract(path)

def run(name, poke):
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="PendulumImpactDamper", instanceName=name)
    fmu.instantiate(loggingOn=True)
    target = (ctypes.c_double * (hidden + 1))(*[0.25] * (hidden + 1))
    status = None
    if poke:
        try:
            fmu.setString([hidden], [f"{ctypes.addressof(target):x} {hidden}"])
            status = 0
        except FMICallException as err:
            status = err.status
        if status == 3:
            fmu.reset()  # FMI 2.0: after fmi2Error, fmi2Reset
    fmu.setupExperiment(startTime=0.0); fmu.enterInitializationMode()
    fmu.setReal([vr["theta_dot_0"]], [2.0]); fmu.exitInitializationMode()
    for k in range(200):
        fmu.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=0.01)
    theta, = fmu.getReal([vr["theta"]])
    fmu.terminate(); fmu.freeInstance()
    return status, theta, list(target) == [0.25] * (hidden + 1)

(status, theta, untouched), (_, clean, _) = run("poked", True), run("clean", False)
print(json.dumps({"hidden": hidden, "status": status, "untouched": untouched, "same": theta == clean,
                  "strings": [v.name for v in md.modelVariables if v.type == "String"]}))
'''


@pytest.fixture(scope="module")
def plain_fmu(tmp_path_factory):
    """PendulumImpactDamper.fmu built on a machine without a C compiler (nothing on PATH): it keeps
    pythonfmu's own binary, as on Windows."""
    out = tmp_path_factory.mktemp("no_compiler")
    done = subprocess.run([sys.executable, "-m", "build_fmu", "--out", str(out), "--model", "PendulumImpactDamper"],
                          capture_output=True, text=True, env={**os.environ, "PATH": str(out)}, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "no C compiler" in done.stderr
    fmu = out / "PendulumImpactDamper.fmu"
    assert "binaries/linux64/PendulumImpactDamper_pythonfmu.so" not in zipfile.ZipFile(fmu).namelist()
    return fmu


def _poke(fmu):
    done = subprocess.run([sys.executable, "-c", POKE_HIDDEN_STRING, str(fmu)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1]), done.stdout


def test_without_the_native_layer_a_host_cannot_make_the_model_write(plain_fmu):
    """pythonfmu's binary passes any value reference to the model: the hidden String is refused
    with a message at error level, the host's buffer is not written (it was: the model took the
    text as the address of its output buffer), and the run is the same as one never poked.
    pythonfmu 0.7's binary has no fmi2Error: a model that raises makes it answer fmi2Fatal (and a
    later fmi2FreeInstance crash the host), so the model logs the refusal and returns (fmi2OK)."""
    result, log = _poke(plain_fmu)
    assert result["strings"] == []  # modelDescription.xml lists no String variable
    assert result["untouched"] and result["same"] and result["status"] == 0
    assert f"[ERROR] poked: value reference {result['hidden']} is not allowed" in log


def test_with_the_native_layer_the_hidden_string_is_out_of_reach(fmu_path):
    """The layer refuses the value reference before it reaches Python (fmi2Error)."""
    result, log = _poke(fmu_path)
    assert result["strings"] == []
    assert result["untouched"] and result["same"] and result["status"] == 3
    assert f"[ERROR] poked: fmi2SetString: no variable has value reference {result['hidden']}" in log


# fmi2Fatal through the layer (a serialized state whose payload is not the model's JSON), then
# fmi2FreeInstance; then what any code reaching the model object (a gc walk, a debugger) does.
FATAL_THEN_FREE = r'''
import gc, struct, sys, fmpy
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
md = fmpy.read_model_description(sys.argv[1])
fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(sys.argv[1]), modelIdentifier="PendulumImpactDamper",
                instanceName="doomed")
fmu.instantiate()
fmu.setupExperiment(startTime=0.0); fmu.enterInitializationMode(); fmu.exitInitializationMode()
fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.1)
magic, mode, t, _ = struct.unpack_from("=IIdQ", bytes(fmu.serializeFMUstate(fmu.getFMUstate())))
try:
    fmu.deSerializeFMUstate(struct.pack("=IIdQ", magic, mode, t, 8) + b"not json")
except FMICallException as err:
    print("status", err.status)
fmu.freeInstance()
dead = [o for o in gc.get_objects() if type(o).__name__ == "PendulumImpactDamper" and getattr(o, "_native", False)]
print("dead models", len(dead))
for model in dead:
    print("read", len(bytes(model._buffer)))
'''


def _sanitizer_preload():
    """LD_PRELOAD for AddressSanitizer in an uninstrumented process (libstdc++ after it, so that
    its C++ exception interceptor finds __cxa_throw), or None."""
    found = []
    for name in ("libasan.so", "libstdc++.so.6"):
        try:
            path = subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True).stdout.strip()
        except OSError:
            return None
        if not os.path.isabs(path) or not os.path.exists(path):
            return None
        found.append(path)
    return " ".join(found)


def test_a_fatal_instance_freed_leaves_the_model_no_view_into_freed_memory(fmu_path):
    """After fmi2Fatal the layer never touches the instance's Python objects again, so the model
    object lives on; fmi2FreeInstance then freed the buffer its memoryview pointed into, and
    reading it was a heap use after free (AddressSanitizer).  The buffer now belongs to the model."""
    preload = _sanitizer_preload()
    if preload is None:
        pytest.skip("gcc's AddressSanitizer runtime (libasan) is not installed")
    env = {**os.environ, "LD_PRELOAD": preload, "ASAN_OPTIONS": "detect_leaks=0"}
    done = subprocess.run([sys.executable, "-c", FATAL_THEN_FREE, str(fmu_path)], capture_output=True, text=True,
                          env=env, timeout=300)
    assert "AddressSanitizer" not in done.stderr, done.stderr[-3000:]
    assert done.returncode == 0, done.stderr[-2000:]
    lines = done.stdout.splitlines()
    assert "status 4" in lines and "dead models 1" in lines  # fmi2Fatal, and the model object was reached
    assert any(line.startswith("read ") and int(line.split()[1]) > 0 for line in lines)


def _local_imports(path, modules):
    """The modules of `modules` that the module at `path` imports (at any depth, inside functions too)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            found.update([node.module.split(".")[0]] if node.module else [a.name for a in node.names])
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("build_fmu."):
            found.add(node.module.split(".")[1])
        elif isinstance(node, ast.Import):
            found.update(a.name.split(".")[1] for a in node.names if a.name.startswith("build_fmu."))
    return found & modules


def test_build_fmu_has_no_import_circle():
    """build_fmu's modules import each other one way only (builder and native imported each other)."""
    package = Path(build_fmu.__file__).parent
    modules = {p.stem for p in package.glob("*.py")} - {"__init__", "__main__"}
    graph = {m: _local_imports(package / f"{m}.py", modules) for m in modules}
    assert graph["builder"] >= {"native"}  # the search sees the imports (this one stays)

    def circle(start, node, path):
        for nxt in sorted(graph[node]):
            if nxt == start:
                return path + [nxt]
            if nxt not in path:
                found = circle(start, nxt, path + [nxt])
                if found:
                    return found
        return None

    circles = [c for c in (circle(m, m, [m]) for m in sorted(modules)) if c]
    assert not circles, " -> ".join(circles[0])
