"""The reference FMUs a step cost is measured against: the trivial pythonfmu FMU (one Real
input, two Real and one Integer output) and the same FMU compiled from C (the floor of any FMU
under a host), both built on the spot."""
import shutil
import subprocess
import sys
import uuid
import zipfile
from pathlib import Path

NATIVE = Path(__file__).with_name("native")
_DESCRIPTION = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="TrivialC" guid="{guid}" generationTool="pidamper.benchmarks.floor"
  numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="TrivialC" canHandleVariableCommunicationStepSize="true"/>
  <ModelVariables>
    <ScalarVariable name="u" valueReference="0" causality="input" variability="continuous"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="y1" valueReference="1" causality="output" variability="continuous"><Real/></ScalarVariable>
    <ScalarVariable name="y2" valueReference="2" causality="output" variability="continuous"><Real/></ScalarVariable>
    <ScalarVariable name="n" valueReference="3" causality="output" variability="discrete"><Integer/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="2" dependencies="1"/><Unknown index="3" dependencies="1"/><Unknown index="4" dependencies=""/></Outputs>
    <InitialUnknowns><Unknown index="2"/><Unknown index="3"/><Unknown index="4"/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"""


def compiler():
    found = shutil.which("cc") or shutil.which("gcc")
    if not found:
        raise RuntimeError("no C compiler (cc or gcc) on PATH: the compiled floor cannot be built")
    return found


def fmi_headers():
    import fmpy

    return Path(fmpy.__file__).parent / "c-code"


def build_trivial_python(out_dir, reals=2):
    """TrivialPythonFmu.fmu (pythonfmu's plain binary) in out_dir; with `reals` other than 2, the same
    model with that many Real outputs, TrivialPythonFmu<reals>.fmu (the floor for an FMU with as
    many outputs)."""
    script = Path(__file__).with_name("trivial_model.py")
    name = "TrivialPythonFmu" + ("" if reals == 2 else str(reals))
    if reals != 2:
        text = script.read_text().replace('REALS = ("y1", "y2")', f"REALS = {tuple(f'y{k + 1}' for k in range(reals))!r}")
        script = Path(out_dir) / f"{name}.py"
        script.write_text(text.replace("class TrivialPythonFmu(", f"class {name}("))
    cmd = [sys.executable, "-m", "pythonfmu", "build", "-f", str(script), "-d", str(out_dir), "--no-external-tool"]
    subprocess.run(cmd, check=True, capture_output=True)
    return Path(out_dir) / f"{name}.fmu"


def build_trivial_c(out_dir):
    """TrivialC.fmu in out_dir, compiled from native/trivial_fmu.c."""
    out_dir = Path(out_dir)
    lib = out_dir / "TrivialC.so"
    subprocess.run([compiler(), "-shared", "-fPIC", "-O2", "-I", str(fmi_headers()), "-o", str(lib),
                    str(NATIVE / "trivial_fmu.c")], check=True, capture_output=True)
    fmu = out_dir / "TrivialC.fmu"
    with zipfile.ZipFile(fmu, "w") as z:
        z.writestr("modelDescription.xml", _DESCRIPTION.format(guid=uuid.uuid4()))
        z.write(lib, "binaries/linux64/TrivialC.so")
    return fmu


def build_every_output_host(out_dir):
    """The native host of native/every_output_host.c, compiled into out_dir."""
    exe = Path(out_dir) / "every_output_host"
    subprocess.run([compiler(), "-O2", "-I", str(fmi_headers()), "-o", str(exe), str(NATIVE / "every_output_host.c"),
                    "-ldl", "-lm"], check=True, capture_output=True)
    return exe
