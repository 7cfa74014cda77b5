"""SSP and OSP system structures of the coupled system, written beside the FMUs."""
import shutil
import zipfile
from pathlib import Path
from xml.sax.saxutils import quoteattr

from .components import component_fmus
from .scenario import BUILDING, SYSTEM, UNIT, Scenario


def _connections(scn, impulse_aware):
    j = scn.floor
    pairs = [("building", f"floor[{j}].a", "unit", "a_s"), ("unit", "F_s", "building", f"F[{j}]")]
    if impulse_aware:
        pairs += [("unit", "J_s", "building", f"J[{j}]"), ("unit", "t_J", "building", f"t_J[{j}]")]
    return pairs


def write_osp(path, scn, impulse_aware=False, h=0.001, fmu_dir="."):
    """OspSystemStructure.xml (libcosim) of the coupled system at `path`; the FMUs are found in
    `fmu_dir` relative to it."""
    def initial(values, fmi_types):
        rows = []
        for name, value in values.items():
            kind = fmi_types.get(name, "Real")
            text = repr(int(value)) if kind == "Integer" else repr(float(value))
            rows.append(f'        <InitialValue variable={quoteattr(name)}><{kind} value="{text}"/></InitialValue>')
        return "\n".join(rows)

    integers = {"impulse_aware": "Integer"}
    connections = "\n".join(
        f'    <VariableConnection><Variable simulator="{a}" name={quoteattr(va)}/>'
        f'<Variable simulator="{b}" name={quoteattr(vb)}/></VariableConnection>'
        for a, va, b, vb in _connections(scn, impulse_aware))
    text = f"""<?xml version="1.0" encoding="UTF-8"?>
<!-- {SYSTEM}: the pendulum impact damper unit on floor {scn.floor} of a shear building
     ({'impulse-aware' if impulse_aware else 'mean-force'} coupling); written by pidamper.cosim -->
<OspSystemStructure xmlns="http://opensimulationplatform.com/MSMI/OSPSystemStructure" version="0.1">
  <StartTime>0.0</StartTime>
  <BaseStepSize>{h!r}</BaseStepSize>
  <Algorithm>fixedStep</Algorithm>
  <Simulators>
    <Simulator name="building" source="{fmu_dir}/{scn.building_model}.fmu">
      <InitialValues>
{initial(scn.building_values(), integers)}
      </InitialValues>
    </Simulator>
    <Simulator name="unit" source="{fmu_dir}/{UNIT}.fmu">
      <InitialValues>
{initial(scn.unit_values(impulse_aware), integers)}
      </InitialValues>
    </Simulator>
  </Simulators>
  <Connections>
{connections}
  </Connections>
</OspSystemStructure>
"""
    Path(path).write_text(text)
    return Path(path)


def ssd_text(scn, impulse_aware=False, h=0.001):
    """SystemStructure.ssd (SSP 1.0) of the coupled system, the FMUs under resources/."""
    def connectors(rows):
        return "\n".join(f'          <ssd:Connector name={quoteattr(name)} kind="{kind}"><ssc:Real/></ssd:Connector>'
                         for name, kind in rows)

    def parameters(values):
        rows = []
        for name, value in values.items():
            typed = (f'<ssv:Integer value="{int(value)}"/>' if name == "impulse_aware"
                     else f'<ssv:Real value="{float(value)!r}"/>')
            rows.append(f'                  <ssv:Parameter name={quoteattr(name)}>{typed}</ssv:Parameter>')
        return "\n".join(rows)

    def binding(name, values):
        return f"""        <ssd:ParameterBindings>
          <ssd:ParameterBinding>
            <ssd:ParameterValues>
              <ssv:ParameterSet version="1.0" name="{name}">
                <ssv:Parameters>
{parameters(values)}
                </ssv:Parameters>
              </ssv:ParameterSet>
            </ssd:ParameterValues>
          </ssd:ParameterBinding>
        </ssd:ParameterBindings>"""

    j = scn.floor
    b_rows = [(f"floor[{j}].a", "output"), (f"F[{j}]", "input"), ("a_g", "input")]
    u_rows = [("a_s", "input"), ("F_s", "output")]
    if impulse_aware:
        b_rows += [(f"J[{j}]", "input"), (f"t_J[{j}]", "input")]
        u_rows += [("J_s", "output"), ("t_J", "output")]
    b_rows += [(f"floor[{k + 1}].x", "output") for k in range(scn.storeys)]
    u_rows += [("r", "output")]
    connections = "\n".join(
        f'      <ssd:Connection startElement="{a}" startConnector={quoteattr(va)} endElement="{b}" '
        f'endConnector={quoteattr(vb)}/>' for a, va, b, vb in _connections(scn, impulse_aware))
    mode = "impulse-aware" if impulse_aware else "mean-force"
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription"
    xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon"
    xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues"
    xmlns:osp="http://opensimulationplatform.com/SSP/OSPAnnotations"
    version="1.0" name="{SYSTEM}"
    description="pendulum impact damper unit on floor {j} of a shear building, {mode} coupling">
  <ssd:System name="{SYSTEM}">
    <ssd:Elements>
      <ssd:Component name="building" type="application/x-fmu-sharedlibrary" source="resources/{scn.building_model}.fmu">
        <ssd:Connectors>
{connectors(b_rows)}
        </ssd:Connectors>
{binding("building", scn.building_values())}
      </ssd:Component>
      <ssd:Component name="unit" type="application/x-fmu-sharedlibrary" source="resources/{UNIT}.fmu">
        <ssd:Connectors>
{connectors(u_rows)}
        </ssd:Connectors>
{binding("unit", scn.unit_values(impulse_aware))}
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
{connections}
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0.0" stopTime="{scn.stop_time!r}">
    <ssd:Annotations>
      <ssc:Annotation type="com.opensimulationplatform">
        <osp:Algorithm><osp:FixedStepAlgorithm baseStepSize="{h!r}"/></osp:Algorithm>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:DefaultExperiment>
</ssd:SystemStructureDescription>
"""


def write_ssp(path, scn, fmus, impulse_aware=False, h=0.001):
    """An .ssp archive: SystemStructure.ssd and the two FMUs under resources/."""
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("SystemStructure.ssd", ssd_text(scn, impulse_aware, h))
        for role, name in ((BUILDING, scn.building_model), (UNIT, UNIT)):
            z.write(fmus[role], f"resources/{name}.fmu")
    return Path(path)


def export_system(out_dir, scn=None, fmus=None, h=0.001):
    """Write the coupled system beside the FMUs in out_dir: DamperOnBuilding.ssp (mean force),
    DamperOnBuilding-impulse.ssp, OspSystemStructure.xml (mean force) and
    OspSystemStructure-impulse.xml (libcosim).  Returns the paths."""
    scn = scn or Scenario()
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    fmus = fmus or component_fmus(storeys=scn.storeys)
    for name, path in ((scn.building_model, fmus[BUILDING]), (UNIT, fmus[UNIT])):
        if Path(path).resolve() != (out / f"{name}.fmu").resolve():
            shutil.copy2(path, out / f"{name}.fmu")
    return [write_ssp(out / f"{SYSTEM}.ssp", scn, fmus, False, h),
            write_ssp(out / f"{SYSTEM}-impulse.ssp", scn, fmus, True, h),
            write_osp(out / "OspSystemStructure.xml", scn, False, h),
            write_osp(out / "OspSystemStructure-impulse.xml", scn, True, h)]
