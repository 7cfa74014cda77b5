"""The fields of a design study (`pidamper design`), checked in one pass before anything runs, with
the rules of `pidamper assess`'s study file (assessment.study_file: a refusal names the table and
field, its value and what is allowed).

    [design]            name, description
    [building]          storeys (1..10) and the FMU parameters of the building, as in a study file
    [damper]            the damper's fixed FMU parameters (e, R, E2, nu2, zeta_p, fidelity ...)
    [search]            NAME = [low, high] or {low, high, log}: the searched parameters (SEARCHED)
    [excitations.NAME]  kind "harmonic", "sweep" or "suite" (design.excitations)
    [objectives]        NAME = "METRIC" or {metric, excitations = [...], statistic = "mean" | "max"}
    [constraints]       stroke [m], impact_force [N], contact_pressure [Pa], plastic = false
    [robustness]        stiffness = delta: every objective its worst over the storeys' stiffness
                        x (1 - delta), x 1 and x (1 + delta)
    [optimizer]         sampler ("nsga2", the default with several objectives; "tpe"), trials,
                        batch (trials asked at once: NSGA-II's population), seed
    [page]              building (an assessment study file beside this one: its yielding [building]),
                        records (a FEMA P-695 set), ids (its record IDs; default all), sa = [g, ...] (Sa(T1, 5 %) of its stripes),
                        masses = [mu, ...] (the caps of the chosen designs), sweep (the excitation of
                        the robustness curves), assessment (an assessment study file beside this
                        one whose configurations are the chosen designs and their Warburton TMDs:
                        the page names which is which, or that one is missing): what
                        `pidamper design --page` writes (design.page)
    [run]               step [s]: the sample interval and communication step of the harmonic and
                        swept excitations (default T1 / 200; a record runs at its own interval)
"""
import sys
from dataclasses import dataclass, field
from pathlib import Path

from pidamper_physics import Params

from ..assessment import study_file
from ..assessment.assess import _blame, first_period, start_values
from ..assessment.study_file import (BOOL, MISSING, POSITIVE, TEXT, Rule, StudyError, ascending, integer,
                                     model_fields, number, one_of)
from ..forcing.ground_motion import FEMA_P695_SETS
from . import excitations

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

SECTIONS = ("design", "building", "damper", "search", "excitations", "objectives", "constraints", "robustness",
            "optimizer", "run", "page")
REQUIRED_SECTIONS = {"building": "storeys (1..10) and the FMU parameters of the building",
                     "search": "one searched parameter or more: NAME = [low, high]",
                     "excitations": "one table [excitations.NAME] or more (kind = \"harmonic\", \"sweep\" or "
                                    "\"suite\")",
                     "objectives": "one objective or more: NAME = \"peak_drift\" ..."}
#: the damper parameters a search may vary (FMU names); damper_floor an integer, the rest real
SEARCHED = {"mu": "the mass ratio (of the building's total mass)", "FR": "the frequency ratio (w1 / w_1)",
            "d": "the clearance to the stops [m]", "e": "the coefficient of restitution",
            "zeta_p": "the particle's dashpot ratio", "E2": "the stop's Young's modulus [Pa]",
            "R": "the radius of the particle's contact face [m]", "damper_floor": "the floor it hangs from (1..N)"}
#: what a run gives per objective (design.response), each over the bare building's in the same run
METRICS = {"peak_drift": "the largest peak storey drift ratio (exact running maxima)",
           "peak_accel": "the largest peak absolute floor acceleration (exact running maxima; the damper floor's "
                         "with its largest contact force over its mass)",
           "rms_drift": "the largest RMS storey drift ratio (over the communication points)",
           "rms_accel": "the largest RMS absolute floor acceleration (over the communication points)",
           "peak_base_shear": "the largest |base shear| (at the communication points)",
           "rms_base_shear": "the RMS base shear (over the communication points)",
           "roof_disp": "the largest |roof displacement| relative to the ground (at the communication points)",
           "mu": "the damper's mass ratio itself (its cost; mu searched), not a ratio to the bare building"}
STATISTICS = ("mean", "max")
CONSTRAINTS = {"stroke": number(0.0, text="the room for the particle's swing [m] (> 0): the largest |x - y|",
                                lo_open=True),
               "impact_force": number(0.0, text="the largest contact force a stop may take [N] (> 0)", lo_open=True),
               "contact_pressure": number(0.0, text="the largest contact pressure [Pa] (> 0)", lo_open=True),
               "plastic": Rule(lambda v: v is False, "false: no impact may yield the softer body (leave it out to "
                                                     "allow them)")}
SAMPLERS = ("nsga2", "tpe")
FIELDS = {
    "design": {"name": TEXT, "description": TEXT},
    "robustness": {"stiffness": number(0.0, 1.0, "a fraction in (0, 1): the storeys' stiffness x (1 -+ it)", True,
                                       True)},
    "optimizer": {"sampler": one_of(*SAMPLERS), "trials": integer(1, "an integer >= 1 (designs evaluated)"),
                  "batch": integer(2, "an integer >= 2 (trials asked at once; NSGA-II's population)"),
                  "seed": integer(0, "an integer >= 0")},
    "run": {"step": POSITIVE},
    "constraints": CONSTRAINTS,
    "page": {"building": TEXT, "records": one_of(*FEMA_P695_SETS), "sweep": TEXT,
             "ids": Rule(lambda v: isinstance(v, list) and len(v) >= 2 and all(study_file._integer(x) for x in v),
                         "a list of two or more of the set's record IDs (default all)"),
             "sa": ascending(POSITIVE, 1, "ascending Sa(T1, 5 %) levels [g] (> 0)"),
             "masses": ascending(number(0.0, 1.0, "", True, True), 1, "ascending mass ratios in (0, 1): the caps of "
                                 "the chosen designs"),
             "assessment": TEXT},
}
#: [page] defaults
PAGE = {"records": "fema-p695-far-field", "sa": [0.105, 0.22], "masses": [0.01, 0.02, 0.04]}


@dataclass(frozen=True)
class Range:
    """A searched parameter: low, high and whether it is searched on a log scale."""
    low: float
    high: float
    log: bool = False


@dataclass(frozen=True)
class Objective:
    name: str
    metric: str
    excitations: tuple
    statistic: str = "mean"


@dataclass
class Design:
    """A parsed design study (every field checked)."""
    name: str
    source: str
    text: str
    building: dict
    damper: dict
    search: dict
    excitations: dict
    objectives: list
    constraints: dict
    stiffness: float = 0.0
    sampler: str = "nsga2"
    trials: int = 100
    batch: int = 20
    seed: int = 0
    step: float = None
    description: str = ""
    folder: Path = Path(".")
    members: list = field(default_factory=list)
    page: dict = field(default_factory=dict)

    @property
    def storeys(self):
        return self.building["storeys"]

    @property
    def period(self):
        """T1 [s]: the bare elastic building's first period (with P-Delta when it has it)."""
        return first_period(self.building)

    @property
    def variants(self):
        """The storeys' stiffness factors every design runs at."""
        d = self.stiffness
        return (1.0 - d, 1.0, 1.0 + d) if d else (1.0,)


def load(path):
    """The Design of a TOML file (its excitations generated or read)."""
    data, text = study_file.read(path, "design study file")
    return parse(data, str(path), Path(path).parent, text)


def parse(data, source="design", folder=Path("."), text=""):
    """The Design of a design study's TOML data; a refusal names the field (StudyError)."""
    def refuse(name, value, rule):
        raise StudyError(source, name, value, rule)

    _check_tables(refuse, data)
    building, damper = dict(data["building"]), dict(data.get("damper", {}))
    storeys = building.get("storeys", MISSING)
    if not (study_file._integer(storeys) and 1 <= storeys <= study_file.MAX_STOREYS):
        refuse("building.storeys", storeys, f"an integer in 1..{study_file.MAX_STOREYS} (a building)")
    fields = model_fields(storeys)
    study_file._check_model(refuse, "building", building, fields, storeys)
    study_file._check_forms(refuse, "building", building, building, storeys)
    for key in ("storeys", "storey_height"):
        if key in damper:
            refuse(f"damper.{key}", damper[key], "the building's: give it in [building]")
    study_file._check_model(refuse, "damper", damper, fields, storeys)
    search = _search(refuse, data["search"], damper, storeys)
    _check_designs(refuse, source, building, damper, search)
    for table, known in FIELDS.items():
        for key, value in data.get(table, {}).items():
            if key not in known:
                refuse(f"{table}.{key}", value, "the fields are " + ", ".join(known))
            if not known[key].ok(value):
                refuse(f"{table}.{key}", value, known[key].text)
    head, optimizer, run = data.get("design", {}), data.get("optimizer", {}), data.get("run", {})
    design = Design(name=head.get("name", Path(source).stem), source=source, text=text, building=building,
                    damper=damper, search=search, excitations=dict(data["excitations"]), objectives=[],
                    constraints=dict(data.get("constraints", {})),
                    stiffness=float(data.get("robustness", {}).get("stiffness", 0.0)), trials=optimizer.get(
                        "trials", 100), batch=optimizer.get("batch", 20), seed=optimizer.get("seed", 0),
                    step=run.get("step"), description=head.get("description", ""), folder=folder)
    design.objectives = _objectives(refuse, data["objectives"], data["excitations"], search)
    design.sampler = optimizer.get("sampler", "nsga2" if len(design.objectives) > 1 else "tpe")
    if design.sampler == "tpe" and len(design.objectives) > 1:
        refuse("optimizer.sampler", "tpe", "\"nsga2\" with several objectives (TPE here searches one)")
    if design.step is None:
        design.step = design.period / 200.0
    design.page = _page(refuse, data.get("page"), folder, storeys, design.excitations)
    design.members = excitations.members(design.excitations, design.period, design.step, folder, source)
    return design


def _page(refuse, spec, folder, storeys, tables):
    """[page] with its defaults, its building the [building] table of the study file it names."""
    if spec is None:
        return {}
    out = {**PAGE, **spec}
    if "building" not in spec:
        refuse("page.building", MISSING, "an assessment study file beside this one, whose [building] is the "
               "yielding building of the recorded set")
    path = folder / spec["building"]
    try:
        building = tomllib.loads(path.read_text())["building"]
    except (OSError, KeyError, tomllib.TOMLDecodeError) as err:
        refuse("page.building", spec["building"], f"a study file with a [building] table ({err.__class__.__name__}: "
               f"{err})")
    if building.get("storeys") != storeys:
        refuse("page.building", spec["building"], f"a building of the study's {storeys} storeys (it has "
               f"{building.get('storeys')})")
    if "assessment" in spec:
        out["assessment"] = _assessment(refuse, folder, spec["assessment"])
    sweep = out.get("sweep", next((n for n, t in tables.items() if t.get("kind") == "sweep"), None))
    if sweep is None or tables.get(sweep, {}).get("kind") != "sweep":
        refuse("page.sweep", sweep, "the name of a sweep excitation (the robustness curves run it)")
    return {**out, "building": building, "file": spec["building"], "sweep": sweep}


def _assessment(refuse, folder, name):
    """[page] assessment: the study file beside this one that assesses the chosen designs (file and
    its configurations tables)."""
    try:
        configurations = tomllib.loads((folder / name).read_text())["configurations"]
    except (OSError, KeyError, tomllib.TOMLDecodeError) as err:
        refuse("page.assessment", name, "an assessment study file beside this one with [configurations.NAME] "
               f"tables: the chosen designs and their TMDs ({err.__class__.__name__}: {err})")
    return {"file": name, "configurations": configurations}


def _check_tables(refuse, data):
    study_file.check_tables(refuse, data, SECTIONS, REQUIRED_SECTIONS, "a design study")
    for key, rule in REQUIRED_SECTIONS.items():
        if not data[key]:
            refuse(key, data[key], f"a design study needs its [{key}] table: {rule}")


def _search(refuse, spec, damper, storeys):
    """{name: Range} of [search]: [low, high] or {low, high, log}, low < high, not also in [damper]."""
    out = {}
    for name, value in spec.items():
        where = f"search.{name}"
        if name not in SEARCHED:
            refuse(where, value, "the searched parameters are " + "; ".join(f"{k}: {v}" for k, v in SEARCHED.items()))
        if name in damper:
            refuse(where, value, f"a parameter either searched or fixed: damper.{name} = {damper[name]!r} fixes it")
        if isinstance(value, list) and len(value) == 2:
            value = {"low": value[0], "high": value[1]}
        if not isinstance(value, dict) or set(value) - {"low", "high", "log"} or not {"low", "high"} <= set(value):
            refuse(where, value, "[low, high] or {low = ..., high = ..., log = true}")
        kind = integer(1, "an integer") if name == "damper_floor" else study_file.NUMBER
        low, high, log = value["low"], value["high"], value.get("log", False)
        if not (kind.ok(low) and kind.ok(high) and low < high):
            refuse(where, [low, high], f"low < high, each {kind.text}")
        if name == "damper_floor" and high > storeys:
            refuse(where, [low, high], f"floors within 1..{storeys}")
        if not BOOL.ok(log) or (log and low <= 0):
            refuse(f"{where}.log", log, "true or false; true only with low > 0")
        out[name] = Range(float(low) if name != "damper_floor" else low, float(high) if name != "damper_floor"
                          else high, log)
    return out


def corners(search):
    """The designs that bound the box: every parameter at its low, then each at its high alone."""
    low = {name: r.low for name, r in search.items()}
    return [low] + [{**low, name: r.high} for name, r in search.items()]


def _check_designs(refuse, source, building, damper, search):
    """Every corner of the search box is a design the FMU takes; else the range that gives the value."""
    for point in corners(search):
        try:
            Params.from_variables(start_values({**building, **damper, **point}))
        except ValueError as err:
            name = getattr(err, "name", None)
            if name in search:
                refuse(f"search.{name}", [search[name].low, search[name].high], err.allowed)
            raise _blame(err, source, building, "damper", damper) from None


def _objectives(refuse, spec, tables, search):
    out = []
    for name, value in spec.items():
        where = f"objectives.{name}"
        if isinstance(value, str):
            value = {"metric": value}
        if not isinstance(value, dict) or set(value) - {"metric", "excitations", "statistic"}:
            refuse(where, value, "a metric (\"peak_drift\" ...) or {metric, excitations = [...], statistic}")
        metric = value.get("metric", MISSING)
        if metric not in METRICS:
            refuse(f"{where}.metric", metric, "one of " + ", ".join(f'"{m}" ({t})' for m, t in METRICS.items()))
        names = value.get("excitations", list(tables))
        if not (isinstance(names, list) and names and all(n in tables for n in names)):
            refuse(f"{where}.excitations", names, "a list of the study's excitations: " + ", ".join(tables))
        if metric == "mu" and "mu" not in search:
            refuse(f"{where}.metric", metric, "a run's metric: \"mu\" only with mu searched ([search] mu = [low, "
                   "high])")
        statistic = value.get("statistic", "mean")
        if statistic not in STATISTICS:
            refuse(f"{where}.statistic", statistic, "\"mean\" (over the excitations' runs of the ratio to the bare "
                   "building's) or \"max\" (the worst run's)")
        out.append(Objective(name, metric, tuple(names), statistic))
    return out
