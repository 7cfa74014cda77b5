"""The FMI 2.0 co-simulation calling sequence as a table: every function in every state, each case
in a child process that drives the FMU's binary through ctypes, as a C host would.

The oracle is the FMI 2.0.4 standard's state table (section 4.2.4, "State Machine of Calling
Sequence from Master to Slave"), written out below independently of the FMU's code: a call
allowed in a state answers fmi2OK, any other answers fmi2Error with a logged message, and no
case ends by a signal.  After every case the child frees the instance and exits normally.
"""
import json
import subprocess
import sys
from pathlib import Path

import fmpy
import pytest

STATES = ("instantiated", "initialization mode", "initialized", "error", "terminated")

# FMI 2.0.4, table of section 4.2.4: the states in which each function may be called
# ("initialized" = stepComplete; after an fmi2Error the FMU is in "error").
ALLOWED = {
    "fmi2SetDebugLogging": set(STATES),
    "fmi2SetupExperiment": {"instantiated"},
    "fmi2EnterInitializationMode": {"instantiated"},
    "fmi2ExitInitializationMode": {"initialization mode"},
    "fmi2DoStep": {"initialized"},
    "fmi2Terminate": {"initialized"},
    "fmi2Reset": set(STATES),
    "fmi2GetReal": {"initialization mode", "initialized", "error", "terminated"},
    "fmi2GetInteger": {"initialization mode", "initialized", "error", "terminated"},
    "fmi2SetReal(input F)": {"instantiated", "initialization mode", "initialized"},
    "fmi2SetReal(tunable e)": {"instantiated", "initialization mode", "initialized"},
    "fmi2SetReal(fixed M, unchanged)": {"instantiated", "initialization mode", "initialized"},
    "fmi2SetInteger(fixed contact_form, unchanged)": {"instantiated", "initialization mode", "initialized"},
    "fmi2GetFMUstate": set(STATES),
    "fmi2SetFMUstate": set(STATES),
    "fmi2SerializeFMUstate": set(STATES),
    "fmi2GetRealStatus": {"initialized", "terminated"},
}
# refused in every state: the wrong type, a value reference that does not exist, an output set,
# a fixed parameter changed after initialization, functions the FMU does not provide
ALWAYS_REFUSED = (
    "fmi2SetReal(Integer impacts)", "fmi2GetReal(Integer contact_form)", "fmi2SetInteger(Real theta)",
    "fmi2GetInteger(Real theta)", "fmi2GetReal(no such vr)", "fmi2SetReal(output theta)",
    "fmi2CancelStep", "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives",
    "fmi2GetDirectionalDerivative",
)

CHILD = r'''
import ctypes, json, sys
from ctypes import (CFUNCTYPE, POINTER, Structure, byref, c_char_p, c_double, c_int, c_size_t, c_uint,
                    c_void_p, create_string_buffer)
lib_path, unzipped, guid, vr_json, state, call = sys.argv[1:7]
vr = json.loads(vr_json)
lib = ctypes.CDLL(lib_path)
messages = []
LOGGER = CFUNCTYPE(None, c_void_p, c_char_p, c_int, c_char_p, c_char_p, c_char_p)
@LOGGER
def logger(env, name, status, category, fmt, arg):
    text = arg if fmt == b"%s" else fmt
    messages.append([status, (text or b"").decode("utf-8", "replace")])
class Callbacks(Structure):
    _fields_ = [("logger", LOGGER), ("allocate", c_void_p), ("free", c_void_p), ("step", c_void_p),
                ("env", c_void_p)]
libc = ctypes.CDLL(None)
callbacks = Callbacks(logger, ctypes.cast(libc.calloc, c_void_p), ctypes.cast(libc.free, c_void_p), None, None)
lib.fmi2Instantiate.restype = c_void_p
lib.fmi2Instantiate.argtypes = [c_char_p, c_int, c_char_p, c_char_p, POINTER(Callbacks), c_int, c_int]
c = lib.fmi2Instantiate(b"table", 1, guid.encode(), ("file://" + unzipped + "/resources").encode(),
                        byref(callbacks), 0, 1)  # logging on: the host wants the messages
assert c, messages
c = c_void_p(c)
def vrs(*names):
    return (c_uint * len(names))(*[vr[n] if isinstance(n, str) else n for n in names])
def st(function, *args):
    return getattr(lib, function)(c, *args)
def setup():
    return st("fmi2SetupExperiment", 0, c_double(0.0), c_double(0.0), 0, c_double(0.0))
def go(target):
    order = ["instantiated", "initialization mode", "initialized", "terminated"]
    if target == "error":
        go("initialized")
        assert st("fmi2SetReal", vrs("e"), c_size_t(1), (c_double * 1)(1.5)) == 3  # refused by the model
        return
    steps = {"initialization mode": lambda: setup() or st("fmi2EnterInitializationMode"),
             "initialized": lambda: st("fmi2ExitInitializationMode"),
             "terminated": lambda: st("fmi2Terminate")}
    for s in order[1:order.index(target) + 1]:
        assert steps[s]() == 0, (s, messages)
saved = c_void_p()
if state != "instantiated":  # a state to restore, taken where it is allowed
    go("initialization mode")
    assert st("fmi2GetFMUstate", byref(saved)) == 0
    lib.fmi2FreeInstance(c)
    c = c_void_p(lib.fmi2Instantiate(b"table", 1, guid.encode(), ("file://" + unzipped + "/resources").encode(),
                                     byref(callbacks), 0, 1))
    saved = c_void_p()
go(state)
if saved.value is None:
    assert st("fmi2GetFMUstate", byref(saved)) == 0, messages
del messages[:]
R, I = c_double * 4, c_int * 4
def serialize():
    size = c_size_t()
    s = st("fmi2SerializedFMUstateSize", saved, byref(size))
    if s: return s
    buf = create_string_buffer(size.value + 100)  # a larger buffer than needed: the state is not over-read
    s = st("fmi2SerializeFMUstate", saved, buf, c_size_t(size.value + 100))
    if s: return s
    back = c_void_p()
    return st("fmi2DeSerializeFMUstate", buf, size, byref(back)) or st("fmi2FreeFMUstate", byref(back))
calls = {
    "fmi2SetDebugLogging": lambda: st("fmi2SetDebugLogging", 0, c_size_t(0), None),
    "fmi2SetupExperiment": setup,
    "fmi2EnterInitializationMode": lambda: st("fmi2EnterInitializationMode"),
    "fmi2ExitInitializationMode": lambda: st("fmi2ExitInitializationMode"),
    "fmi2DoStep": lambda: st("fmi2DoStep", c_double(0.0), c_double(0.01), 1),
    "fmi2Terminate": lambda: st("fmi2Terminate"),
    "fmi2Reset": lambda: st("fmi2Reset"),
    "fmi2GetReal": lambda: st("fmi2GetReal", vrs("theta", "energy"), c_size_t(2), R()),
    "fmi2GetInteger": lambda: st("fmi2GetInteger", vrs("impacts", "contact"), c_size_t(2), I()),
    "fmi2SetReal(input F)": lambda: st("fmi2SetReal", vrs("F"), c_size_t(1), R(0.5)),
    "fmi2SetReal(tunable e)": lambda: st("fmi2SetReal", vrs("e"), c_size_t(1), R(0.7)),
    "fmi2SetReal(fixed M, unchanged)": lambda: st("fmi2SetReal", vrs("M"), c_size_t(1), R(1.0)),
    "fmi2SetInteger(fixed contact_form, unchanged)": lambda: st("fmi2SetInteger", vrs("contact_form"), c_size_t(1), I(0)),
    "fmi2GetFMUstate": lambda: st("fmi2GetFMUstate", byref(c_void_p())),
    "fmi2SetFMUstate": lambda: st("fmi2SetFMUstate", saved),
    "fmi2SerializeFMUstate": serialize,
    "fmi2GetRealStatus": lambda: st("fmi2GetRealStatus", 2, byref(c_double())),
    "fmi2SetReal(Integer impacts)": lambda: st("fmi2SetReal", vrs("impacts"), c_size_t(1), R(3.0)),
    "fmi2GetReal(Integer contact_form)": lambda: st("fmi2GetReal", vrs("contact_form"), c_size_t(1), R()),
    "fmi2SetInteger(Real theta)": lambda: st("fmi2SetInteger", vrs("theta"), c_size_t(1), I(1)),
    "fmi2GetInteger(Real theta)": lambda: st("fmi2GetInteger", vrs("theta"), c_size_t(1), I()),
    "fmi2GetReal(no such vr)": lambda: st("fmi2GetReal", vrs(10 ** 6), c_size_t(1), R()),
    "fmi2SetReal(output theta)": lambda: st("fmi2SetReal", vrs("theta"), c_size_t(1), R(0.1)),
    "fmi2CancelStep": lambda: st("fmi2CancelStep"),
    "fmi2SetRealInputDerivatives": lambda: st("fmi2SetRealInputDerivatives", vrs("F"), c_size_t(1), I(1), R(1.0)),
    "fmi2GetRealOutputDerivatives": lambda: st("fmi2GetRealOutputDerivatives", vrs("theta"), c_size_t(1), I(1), R()),
    "fmi2GetDirectionalDerivative": lambda: st("fmi2GetDirectionalDerivative", vrs("theta"), c_size_t(1), vrs("F"),
                                               c_size_t(1), R(1.0), R()),
}
status = calls[call]()
again = calls[call]() if call in ("fmi2SetReal(Integer impacts)",) else None  # two refusals in a row
lib.fmi2FreeFMUstate(c, byref(saved))
lib.fmi2FreeInstance(c)
print(json.dumps({"status": status, "again": again, "messages": messages}))
'''


@pytest.fixture(scope="module")
def fmu_files(fmu_path, tmp_path_factory):
    unzipped = Path(fmpy.extract(str(fmu_path), unzipdir=str(tmp_path_factory.mktemp("table"))))
    md = fmpy.read_model_description(str(fmu_path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    lib = unzipped / "binaries" / "linux64" / f"{md.coSimulation.modelIdentifier}.so"
    return str(lib), str(unzipped), md.guid, json.dumps(vr)


CASES = [(state, call) for call in list(ALLOWED) + list(ALWAYS_REFUSED) for state in STATES]


@pytest.mark.parametrize("state, call", CASES, ids=[f"{c} in {s}" for s, c in CASES])
def test_every_call_in_every_state_answers(fmu_files, state, call):
    lib, unzipped, guid, vr = fmu_files
    done = subprocess.run([sys.executable, "-c", CHILD, lib, unzipped, guid, vr, state, call],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, f"exit {done.returncode}: {done.stderr[-1500:]}"
    result = json.loads(done.stdout.strip().splitlines()[-1])
    expected = 0 if state in ALLOWED.get(call, ()) else 3  # fmi2OK, else fmi2Error
    assert result["status"] == expected, result
    if expected == 3:
        errors = [text for status, text in result["messages"] if status >= 3]
        assert errors and all(text.startswith("table: ") for text in errors), result
    if result["again"] is not None:
        assert result["again"] == 3


RECOVER = r'''
import sys, fmpy
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
md = fmpy.read_model_description(sys.argv[1])
vr = {v.name: v.valueReference for v in md.modelVariables}
fmu = FMU2Slave(guid=md.guid, unzipDirectory=sys.argv[2], modelIdentifier="PendulumImpactDamper", instanceName="r")
fmu.instantiate(); fmu.setupExperiment(startTime=0.0); fmu.enterInitializationMode()
fmu.setReal([vr["theta_dot_0"]], [2.0])
try:
    fmu.setReal([vr["theta"]], [0.1])  # an output: refused, the instance is in the error state
    raise SystemExit("accepted")
except FMICallException:
    pass
try:
    fmu.exitInitializationMode()
    raise SystemExit("left the error state without a restart")
except FMICallException:
    pass
state = fmu.getFMUstate()  # taken in the error state: what the model held when the error came
fmu.setFMUstate(state)     # back to initialization mode, where the error interrupted it
fmu.exitInitializationMode()
for k in range(100):  # fmpy's grid: t_k = k h
    fmu.doStep(currentCommunicationPoint=k * 0.01, communicationStepSize=(k + 1) * 0.01 - k * 0.01)
print(repr(fmu.getReal([vr["theta"]])[0]))
fmu.freeFMUstate(state); fmu.terminate(); fmu.freeInstance()
'''


def test_a_state_saved_after_an_error_restores_where_the_error_came(fmu_path, tmp_path):
    """FMI 2.0 lets a host restart from a saved state after fmi2Error: the state taken in the error
    state restores the mode the error interrupted (here initialization mode), and the run goes on
    as if the refused call had never been made."""
    unzipped = fmpy.extract(str(fmu_path), unzipdir=str(tmp_path / "u"))
    done = subprocess.run([sys.executable, "-c", RECOVER, str(fmu_path), unzipped], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:] + done.stdout
    clean = fmpy.simulate_fmu(str(fmu_path), stop_time=1.0, output_interval=0.01, start_values={"theta_dot_0": 2.0},
                              output=["theta"])
    assert float(done.stdout.strip().splitlines()[-1]) == clean["theta"][-1]
