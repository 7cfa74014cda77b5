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


ATTACHED = r'''
import gc, json, sys, fmpy
from fmpy.fmi2 import FMU2Slave
path = sys.argv[1]
md = fmpy.read_model_description(path)
fmu = FMU2Slave(guid=md.guid, unzipDirectory=fmpy.extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="a")
fmu.instantiate()
models = [o for o in gc.get_objects() if type(o).__name__ == md.coSimulation.modelIdentifier]
print(json.dumps({"native": [m._native for m in models]}))
fmu.freeInstance()
'''


@pytest.mark.parametrize("model", ["PendulumImpactDamper", "PendulumImpactDamperUnit", "DampedShearBuilding3",
                                   "ShearBuilding3"])
def test_the_layer_links_every_model(fmu_path, model):
    """Where the layer is built it links each model at fmi2Instantiate: the model writes its
    outputs into its buffer and the layer serves reads from there (a link that silently failed
    would leave the FMU correct but slow)."""
    done = subprocess.run([sys.executable, "-c", ATTACHED, str(fmu_path.parent / f"{model}.fmu")],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert json.loads(done.stdout.strip().splitlines()[-1]) == {"native": [True]}

