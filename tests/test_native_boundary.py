"""What the FMU's native layer handles at the boundary to the host: resource locations with any
legal characters, instance names that are not UTF-8, serialization buffers larger than the
state.  Each case runs in a child process, which must end normally."""
import json
import shutil
import subprocess
import sys

import fmpy
import pytest


RUN_IN = r'''
import json, sys, fmpy
from fmpy.fmi2 import FMU2Slave
unzipped, name = sys.argv[1], sys.argv[2].encode("latin-1")
md = fmpy.read_model_description(unzipped + "/modelDescription.xml")
vr = {v.name: v.valueReference for v in md.modelVariables}
fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="PendulumImpactDamper",
                instanceName=name.decode("latin-1"))
fmu.instantiate()
fmu.setupExperiment(startTime=0.0); fmu.enterInitializationMode()
fmu.setReal([vr["theta_dot_0"]], [2.0]); fmu.exitInitializationMode()
for k in range(300):
    fmu.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=0.01)
theta, = fmu.getReal([vr["theta"]]); impacts, = fmu.getInteger([vr["impacts"]])
state = fmu.getFMUstate()
size = len(fmu.serializeFMUstate(state))
print(json.dumps({"theta": theta, "impacts": impacts, "size": size}))
fmu.freeFMUstate(state); fmu.terminate(); fmu.freeInstance()
'''


def _run(unzipped, name="plain"):
    done = subprocess.run([sys.executable, "-c", RUN_IN, str(unzipped), name], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def reference(fmu_path, tmp_path_factory):
    unzipped = fmpy.extract(str(fmu_path), unzipdir=str(tmp_path_factory.mktemp("plain")))
    return unzipped, _run(unzipped)


@pytest.mark.parametrize("folder", ["models (copy)", "C++ projects", "José", "a+b", "100%done", "50%20off"])
def test_resource_folder_with_any_legal_characters(reference, tmp_path, folder):
    """fmpy writes the resource location as a percent-encoded URI; the layer decodes it (pythonfmu
    alone decoded only %20 and crashed the host on the rest)."""
    unzipped, expected = reference
    target = tmp_path / folder
    shutil.copytree(unzipped, target)
    assert _run(target) == expected and expected["impacts"] > 10


def test_instance_name_that_is_not_utf8(reference):
    """An ANSI host's Latin-1 name (café): the model runs under it (pythonfmu alone crashed)."""
    unzipped, expected = reference
    assert _run(unzipped, "caf\u00e9") == expected


DESERIALIZE_INTO_GARBAGE = r'''
import ctypes, json, sys, fmpy
from fmpy.fmi2 import FMU2Slave
unzipped = sys.argv[1]
md = fmpy.read_model_description(unzipped + "/modelDescription.xml")
vr = {v.name: v.valueReference for v in md.modelVariables}
fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="PendulumImpactDamper", instanceName="a")
fmu.instantiate()
fmu.setupExperiment(startTime=0.0); fmu.enterInitializationMode()
fmu.setReal([vr["theta_dot_0"]], [2.0]); fmu.exitInitializationMode()
for k in range(100):
    fmu.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=0.01)
state = fmu.getFMUstate()
blob = fmu.serializeFMUstate(state)
fmu.freeFMUstate(state)
theta, = fmu.getReal([vr["theta"]])
for k in range(100, 150):
    fmu.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=0.01)
out = ctypes.c_void_p(0xDEADBEEF)  # what an uninitialised FMUstate variable of a host may hold
buf = (ctypes.c_char * len(blob)).from_buffer_copy(blob)
status = fmu.dll.fmi2DeSerializeFMUstate(fmu.component, buf, ctypes.c_size_t(len(blob)), ctypes.byref(out))
assert status == 0 and out.value != 0xDEADBEEF, status
fmu.setFMUstate(out)
restored, = fmu.getReal([vr["theta"]])
fmu.freeFMUstate(out); fmu.terminate(); fmu.freeInstance()
print(json.dumps({"theta": theta, "restored": restored}))
'''


def test_deserialize_neither_reads_nor_frees_what_the_host_left_in_the_state_pointer(reference):
    """FMUstate is an output of fmi2DeSerializeFMUstate (FMI 2.0): a host may pass an uninitialised
    variable. The layer used to free what it pointed to (a crash on 0xDEADBEEF); now the state
    comes back and restores the model's state to the last bit."""
    unzipped, _ = reference
    done = subprocess.run([sys.executable, "-c", DESERIALIZE_INTO_GARBAGE, str(unzipped)], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, (done.returncode, done.stderr[-2000:])
    values = json.loads(done.stdout.strip().splitlines()[-1])
    assert values["restored"] == values["theta"] != 0.0


SET_THE_LINK = r'''
import ctypes, json, sys, fmpy
from fmpy.fmi2 import FMU2Slave
unzipped = sys.argv[1]
md = fmpy.read_model_description(unzipped + "/modelDescription.xml")
link = max(v.valueReference for v in md.modelVariables) + 1  # the hidden String variable
count = link  # value references 0 .. link - 1: what the layer would pass
target = (ctypes.c_double * (count + 1))()  # memory of the host's choosing
messages = []
fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier="PendulumImpactDamper", instanceName="a")
fmu.instantiate(loggingOn=True, callbacks=None)
fmu.fmi2SetDebugLogging(fmu.component, 1, 0, None)
try:
    fmu.setString([link], [f"{ctypes.addressof(target):#x} {count}"])
except Exception as err:
    messages.append(str(err))
print(json.dumps({"written": any(target[k] != 0.0 for k in range(count + 1))}))
fmu.freeInstance()
'''


def test_a_host_cannot_point_the_model_at_its_own_memory_without_the_layer(fmu_path, tmp_path):
    """Where the native layer is absent (pythonfmu's own binary: Windows, no C compiler), a host
    can set the hidden link variable; the model takes a link only when the layer vouches for it
    (sys._pidamper_link), so nothing is written to the address the host names."""
    from build_fmu import native

    plain = native.without_layer(fmu_path, tmp_path / "plain.fmu")
    unzipped = fmpy.extract(str(plain), unzipdir=str(tmp_path / "plain"))
    done = subprocess.run([sys.executable, "-c", SET_THE_LINK, unzipped], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert json.loads(done.stdout.strip().splitlines()[-1]) == {"written": False}
    assert "_native_link" in done.stdout + done.stderr and "set by the FMU's native layer only" in done.stdout + done.stderr


ATTACHED = r'''
import gc, json, sys, fmpy
from fmpy.fmi2 import FMU2Slave
path = sys.argv[1]
md = fmpy.read_model_description(path)
fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="a")
fmu.instantiate()
models = [o for o in gc.get_objects() if type(o).__name__ == md.coSimulation.modelIdentifier]
print(json.dumps({"native": [m._native for m in models], "offer_left": hasattr(sys, "_pidamper_link")}))
fmu.freeInstance()
'''


@pytest.mark.parametrize("model", ["PendulumImpactDamper", "PendulumImpactDamperUnit", "ShearBuilding"])
def test_the_layer_still_links_every_model_and_withdraws_its_offer(fmu_path, model):
    """The vouched link works where the layer is built: each model takes the buffer (its outputs
    are then served from it), and sys._pidamper_link is gone after fmi2Instantiate."""
    done = subprocess.run([sys.executable, "-c", ATTACHED, str(fmu_path.parent / f"{model}.fmu")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert json.loads(done.stdout.strip().splitlines()[-1]) == {"native": [True], "offer_left": False}


FREE_AFTER_FATAL = r'''
import gc, json, sys, fmpy
from fmpy.fmi2 import FMU2Slave
path = sys.argv[1]
md = fmpy.read_model_description(path)
fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="a")
fmu.instantiate()
model, = [o for o in gc.get_objects() if type(o).__name__ == md.coSimulation.modelIdentifier]
linked = model._buffer is not None


def escapes():
    raise RuntimeError("a bug: an exception past the model's guard")


model.terminate = escapes  # pythonfmu answers fmi2Fatal for an escaped exception
fmu.setupExperiment(startTime=0.0); fmu.enterInitializationMode(); fmu.exitInitializationMode()
try:
    fmu.terminate()
    status = "ok"
except Exception as err:
    status = str(err)
fmu.freeInstance()
print(json.dumps({"linked": linked, "status": status, "view_after_free": model._buffer is not None}))
'''


def test_after_a_fatal_error_the_model_forgets_the_buffer_the_layer_frees(fmu_path):
    """fmi2FreeInstance frees the layer's output buffer; the model must not keep a view of it,
    after a fatal error too (it used to: its memoryview then pointed into freed memory)."""
    done = subprocess.run([sys.executable, "-c", FREE_AFTER_FATAL, str(fmu_path)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result["linked"] and "(fatal)" in result["status"], result
    assert result["view_after_free"] is False, result
