"""The fields of a study file (`pidamper assess`), checked in one pass before anything runs.

FIELDS holds, per table of the file, every field it may have and its rule; [building] and each
[configurations.NAME] take the parameters of the FMU that runs the building (model_fields: the
FMU's own variable table, each Real a finite number and each Integer an integer, with the
per-storey lists of the study's storey count), [damage_states] any name.  `check(data, source)`
refuses the first field that is unknown, missing or breaks its rule with a StudyError naming it:
`<source>: <table>.<field> = <value> is not allowed: <rule>`.  What needs the FMU's ranges, the
files named or the records (assess.parse) is checked right after, still before any run.
"""
import math
import sys
from dataclasses import dataclass
from pathlib import Path

from pidamper_fmu.particle_tables import PENDULUM_ONLY, tables
from pidamper_physics.imk_storeys import IMK_DEFAULTS
from pidamper_physics.params import LEVELS, MAX_STOREYS

from ..errors import FieldError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


class StudyError(FieldError):
    """A study field with a value that is not allowed."""


class _Missing:
    def __repr__(self):
        return "(missing)"


MISSING = _Missing()  # the value a refusal shows for a required field that is not there


@dataclass(frozen=True)
class Rule:
    """What a field allows: ok(value) and its text in a refusal."""
    ok: object
    text: str


def _number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _integer(v):
    return isinstance(v, int) and not isinstance(v, bool)


def number(lo=-math.inf, hi=math.inf, text="a finite number", lo_open=False, hi_open=False):
    def ok(v):
        return _number(v) and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
    return Rule(ok, text)


def integer(lo, text):
    return Rule(lambda v: _integer(v) and v >= lo, text)


def one_of(*choices):
    return Rule(lambda v: isinstance(v, str) and v in choices, "one of " + ", ".join(f'"{c}"' for c in choices))


def ascending(item, least, text):
    """A list of at least `least` items, each item.ok, strictly ascending (no duplicates)."""
    def ok(v):
        return (isinstance(v, list) and len(v) >= least and all(item.ok(x) for x in v)
                and all(a < b for a, b in zip(v, v[1:])))
    return Rule(ok, text)


NUMBER = number()
POSITIVE = number(0.0, text="a number > 0", lo_open=True)
TEXT = Rule(lambda v: isinstance(v, str), "text (a quoted string)")
BOOL = Rule(lambda v: isinstance(v, bool), "true or false")
TABLE = Rule(lambda v: isinstance(v, dict), "a table { ... }")

MEASURES = ("Sa", "Sa_avg", "PGA", "PGV")
#: the tables of a study file, those it must have, and each one's fields (None: any name)
SECTIONS = ("study", "building", "configurations", "suite", "intensity", "damage_states", "hazard", "losses", "p695",
            "ida", "uncertainty", "run")
REQUIRED_SECTIONS = {
    "building": "storeys and the FMU parameters of the building",
    "configurations": "one table [configurations.NAME] or more (FMU parameters on top of the building; mu = 0 for "
                      "none)",
    "suite": "the ground motions: set = ..., folder = ... or generator = ...",
    "intensity": "levels = [...] (and measure, zeta)",
    "hazard": "curve = a site hazard curve's file (CSV or USGS JSON) with its source, k0 and k, or points = [[IM, "
              "rate], [IM, rate]] with their source",
}
#: [ida]: incremental dynamic analysis to collapse by hunt and fill (ida.hunt_and_fill), per record and
#: configuration, each record scaled by its own intensity; its capacities then give the collapse fragility
IDA_FIELDS = {"first": "the first intensity (levels' unit, > 0)", "step": "the hunt's first step (> 0)",
              "increment": "the hunt's step growth (>= 0; default step / 2)",
              "tolerance": "the bracket's relative width (0..1; default 0.05)",
              "max_runs": "runs per record (an integer >= 2; default 10)",
              "stripes": "the stripes' demands: \"run\" (every record run at every stripe, scaled by its own "
                         "intensity, the IDA's runs at a stripe taken as they are; the default) or \"interpolate\" (read "
                         "off the IDA curves, no stripe runs; not with [losses])",
              "loo_limit": "with stripes = \"interpolate\": the largest 90th-percentile leave-one-out error of the "
                           "peak demands read off the IDA curves (> 0; default 0.25)"}
#: [p695]: FEMA P-695's collapse margin (p695.margin): seismic design category, the ratings of design
#: requirements, test data and model (Table 7-2), the record set of the spectral shape factor
P695_FIELDS = {"sdc": ("dmax", "dmin", "cmax", "cmin", "bmax", "bmin"), "ratings": "three of A, B, C, D",
               "record_set": ("farfield", "nearfield")}
#: [losses] fields: the performance model and what replacing the building costs (FEMA P-58)
LOSS_FIELDS = {"components": "a CSV of FEMA P-58 components (pelicun's format), beside the study file",
               "floor_area": "the floor area of one storey [m2] (> 0)",
               "replacement_cost": "the building's replacement cost [USD 2011] (> 0)",
               "replacement_days": "the days to replace it [days] (> 0)",
               "realizations": "loss realizations per record (an integer >= 1; default 50)",
               "repair_days": "repair-time thresholds [days] for the annual frequencies, ascending (default [30, "
                              "180])",
               "demand_dispersion": "FEMA P-58's modelling dispersion beta_m added to every demand of a realization, in "
                                    "[0, 2) (default 0; FEMA P-58-1: sqrt(beta_c^2 + beta_q^2), 0.25 each for an average building "
                                    "definition and model)",
               "total_loss": "FEMA P-58's total-loss threshold: a realization whose repairs would cost more than this "
                             "fraction of the replacement cost is replaced, in (0, 1] (default: none)"}

FIELDS = {
    "study": {"name": TEXT, "description": TEXT, "scope": TEXT, "changes": TEXT},
    "intensity": {"measure": one_of(*MEASURES),
                  "levels": ascending(POSITIVE, 2, "two or more ascending positive numbers, no level twice"),
                  "zeta": number(0.0, 1.0, "a damping ratio in (0, 1)", True, True)},
    "damage_states": None,
    "hazard": {"k0": POSITIVE, "k": POSITIVE, "curve": TEXT, "imt": TEXT, "site": TEXT,
               "period": number(0.0, text="the spectral period of the curve's measure [s] (> 0)", lo_open=True),
               "extrapolate": one_of("none", "loglog"), "rule": one_of("loglog", "semilog", "intervals"),
               "points": Rule(lambda v: isinstance(v, list) and len(v) == 2 and all(
                   isinstance(p, list) and len(p) == 2 and all(POSITIVE.ok(x) for x in p) for p in v),
                   "two [IM, annual rate] pairs of positive numbers"),
               "source": Rule(lambda v: isinstance(v, str) and v.strip() != "", "where the hazard comes from "
                              "(text; required with points and curve: their citation)")},
    "run": {"step": POSITIVE, "bootstrap": integer(1, "an integer >= 1 (resamples)"),
            "seed": integer(0, "an integer >= 0"),
            "beta_m": number(0.0, 2.0, "a modelling dispersion in [0, 2) (FEMA P-695 Table 7-2: 0.10 superior to "
                             "0.50 poor)", hi_open=True)},
    "ida": {"first": number(0.0, text=IDA_FIELDS["first"], lo_open=True),
            "step": number(0.0, text=IDA_FIELDS["step"], lo_open=True),
            "increment": number(0.0, text=IDA_FIELDS["increment"]),
            "tolerance": number(0.0, 1.0, IDA_FIELDS["tolerance"], True, True),
            "max_runs": integer(2, IDA_FIELDS["max_runs"]),
            "stripes": Rule(lambda v: v in ("interpolate", "run"), IDA_FIELDS["stripes"]),
            "loo_limit": number(0.0, text=IDA_FIELDS["loo_limit"], lo_open=True)},
    "p695": {"sdc": one_of(*P695_FIELDS["sdc"]), "record_set": one_of(*P695_FIELDS["record_set"]),
             **{key: number(0.0, text=f"{key} of ASCE 7 Table 12.8-2 (> 0): T = Cu Ct h^x, h in ft", lo_open=True)
                for key in ("Ct", "x")},
             "reasons": Rule(lambda v: isinstance(v, list) and len(v) == 3 and all(isinstance(r, str) and r.strip()
                                                                                   for r in v),
                             "three texts: why the design requirements, the test data and the model earn their "
                             "ratings (FEMA P-695 3.4, 3.5, 5.7)"),
             "ratings": Rule(lambda v: isinstance(v, list) and len(v) == 3 and all(r in ("A", "B", "C", "D")
                                                                                    for r in v),
                             P695_FIELDS["ratings"] + ' (e.g. ["B", "B", "C"])')},
    "losses": {"components": Rule(lambda v: isinstance(v, str), LOSS_FIELDS["components"]),
               **{key: number(0.0, text=LOSS_FIELDS[key], lo_open=True)
                  for key in ("floor_area", "replacement_cost", "replacement_days")},
               "realizations": integer(1, LOSS_FIELDS["realizations"]),
               "repair_days": ascending(POSITIVE, 1, LOSS_FIELDS["repair_days"]),
               "demand_dispersion": number(0.0, 2.0, LOSS_FIELDS["demand_dispersion"], hi_open=True),
               "total_loss": number(0.0, 1.0, LOSS_FIELDS["total_loss"], lo_open=True)},
    # the suite's types; which keys go together and their values: ground_motion.suite
    "suite": {"set": TEXT, "normalized": BOOL, "components": TEXT,
              "records": Rule(lambda v: isinstance(v, list) and v != [] and all(_integer(x) for x in v),
                              "a list of the set's record IDs (integers)"),
              "folder": TEXT, "generator": TEXT, "count": integer(1, "an integer >= 1"),
              "seed": integer(0, "an integer >= 0"), "start": TEXT, "envelope": TABLE,
              **{key: NUMBER for key in ("duration", "dt", "omega_g", "zeta_g", "omega_f", "zeta_f", "S0", "pga")}},
}
#: [uncertainty]: the headline ratios' intervals beyond record resampling (assessment.uncertainty)
UNCERTAINTY = {"hazard": "beta_h: one sigma of the hazard curve's intensities in ln units (the curve's intensities "
                         "scaled by exp(+-beta_h)), in (0, 2)",
               "case": "a table [uncertainty.NAME] of one model source: fields = [FMU fields of the building or the "
                       "configurations], factor (> 0, not 1: the one-sigma multiplier of the fields' values), sides "
                       "(2: x factor and / factor, the default; 1: x factor only)"}
#: fields that must be there when their table is
REQUIRED = {"intensity": ("levels",), "ida": ("first", "step"),
            "losses": ("components", "floor_area", "replacement_cost", "replacement_days")}
#: the tables that need a building (storeys >= 1) run through its FMU: its collapse and storey demands
BUILDING_ONLY = {table: f"a building (storeys >= 1) run through its FMU (engine fmu): {what}" for table, what in (
    ("ida", "each run stops at the building's collapse"), ("p695", "the margin needs the building's pushover and "
                                                                  "collapses"),
    ("losses", "the losses need each storey's and floor's demands"))}
DRIFT_LIMIT = number(0.0, 1.0, "a peak inter-storey drift-ratio limit in (0, 1) (1 % is 0.01)", True, True)

#: a building's per-storey fields (a number for every storey or a list, storey 1 first) and the
#: FMU variables they fill (scene.fmu_values; storey_height: the study's name of storey[k].h)
PER_STOREY = {"floor_m": "floor[{}].m", "storey_k": "storey[{}].k", "storey_Fy": "storey[{}].Fy",
              "storey_b": "storey[{}].b", "storey_height": "storey[{}].h",
              **{f"storey_{name}": f"storey[{{}}].{name}" for name in IMK_DEFAULTS}}
#: FMU parameters a study does not take, and why
NOT_IN_A_STUDY = {
    **{name: "every run starts from rest, driven by its record alone" for name in
       ("theta_0", "theta_dot_0", "alpha_0", "alpha_dot_0", "F0", "Omega", "phi")},
    "storey_h": "the storey heights are building.storey_height",
    **{f"storey[{k}].h": "the storey heights are building.storey_height" for k in range(1, MAX_STOREYS + 1)},
}
FIDELITY = Rule(lambda v: v in LEVELS or (_integer(v) and 0 <= v < len(LEVELS)),
                "one of " + ", ".join(f'"{name}"' for name in LEVELS) + " (or its index 0..3)")


def model_fields(storeys):
    """{field: Rule} of [building] for a building of `storeys` storeys (0: the pendulum primary):
    the FMU's parameters, the per-storey fields and storeys; [configurations.NAME] takes the same
    but storeys and storey_height."""
    n = storeys
    out = {"storeys": integer(0, f"an integer in 0..{MAX_STOREYS} (0: the pendulum primary)")}
    for name, kind, *_ in tables(n)[0]:
        out[name] = NUMBER if kind.__name__ == "Real" else Rule(_integer, "an integer")
    out["fidelity"] = FIDELITY
    for alias in PER_STOREY if n else ("storey_height",):
        size = max(n, 1)
        item = POSITIVE if alias == "storey_height" else NUMBER
        out[alias] = Rule(lambda v, item=item, size=size: item.ok(v) or (
            isinstance(v, list) and len(v) == size and all(item.ok(x) for x in v)),
            f"{item.text}, or a list of {size} (one per storey, storey 1 first)")
    for name in NOT_IN_A_STUDY:
        out.pop(name, None)
    return out


def _unknown(known, n=None):
    """The rule of an unknown field: the known ones (per floor and storey k = 1..n)."""
    names = [k for k in known if "[" not in k]
    floors = sorted({k.split("[")[0] + "[k]." + k.split(".")[-1] for k in known if "[" in k})
    text = "the fields are " + ", ".join(names)
    if floors:
        text += ", " + ", ".join(floors) + f" (k = 1..{n})"
    return text


def read(path, what="study file"):
    """(TOML data, text) of a study file; FileNotFoundError without it, StudyError when it is not TOML."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{what} {path} does not exist")
    text = path.read_text()
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as err:
        raise StudyError(str(path), "file", "TOML", f"it must be valid TOML ({err})") from None


def check_tables(refuse, data, sections, required, what="a study file"):
    """Refuse a table not in `sections`, a value that is not a table, or a `required` table missing
    or empty ({table: what it holds})."""
    for key, value in data.items():
        if key not in sections:
            refuse(key, value, f"the tables of {what} are {', '.join(sections)}")
        if not isinstance(value, dict):
            refuse(key, value, f"a table ([{key}])")
    for key, rule in required.items():
        if key not in data:
            refuse(key, MISSING, f"{what} needs its [{key}] table: {rule}")


def check(data, source):
    """Refuse (StudyError) the first field of the study file's TOML data that is unknown, missing or
    breaks its rule."""
    def refuse(name, value, rule):
        raise StudyError(source, name, value, rule)

    check_tables(refuse, data, SECTIONS, REQUIRED_SECTIONS)
    building = data["building"]
    storeys = building.get("storeys", MISSING)
    if not (_integer(storeys) and 0 <= storeys <= MAX_STOREYS):
        refuse("building.storeys", storeys, f"an integer in 0..{MAX_STOREYS} (0: the pendulum primary, its "
               "displacement x the one storey's drift)")
    fields = model_fields(storeys)
    _check_model(refuse, "building", building, fields, storeys)
    _check_forms(refuse, "building", building, building, storeys)
    confs = data["configurations"]
    if not confs:
        refuse("configurations", confs, REQUIRED_SECTIONS["configurations"])
    for name, params in confs.items():
        if not isinstance(params, dict):
            refuse(f"configurations.{name}", params, "a table [configurations.NAME] of FMU parameters")
        for key in ("storeys", "storey_height"):
            if key in params:
                refuse(f"configurations.{name}.{key}", params[key], "the building's: give it in [building]")
        if "tmd" in params:
            _check_tmd(refuse, name, params, {**building, **params})
        _check_model(refuse, f"configurations.{name}", {k: v for k, v in params.items() if k != "tmd"}, fields,
                     storeys)
        _check_forms(refuse, f"configurations.{name}", params, {**building, **params}, storeys)
    for table, known in FIELDS.items():
        values = data.get(table, {})
        for key, value in values.items():
            rule = DRIFT_LIMIT if known is None else known.get(key)
            if rule is None:
                refuse(f"{table}.{key}", value, _unknown(known))
            if not rule.ok(value):
                refuse(f"{table}.{key}", value, rule.text)
        for key in REQUIRED.get(table, ()) if values or table in REQUIRED_SECTIONS else ():
            if key not in values:
                refuse(f"{table}.{key}", MISSING, f"[{table}] needs {key}: {known[key].text}")
    _check_hazard(refuse, data["hazard"])
    for table in BUILDING_ONLY:
        if data.get(table) and not storeys:
            refuse(table, data[table], BUILDING_ONLY[table])
    measure = (data.get("intensity") or {}).get("measure", "Sa")
    p695 = data.get("p695") or {}
    if ("Ct" in p695 or "x" in p695) and not ("Ct" in p695 and "x" in p695 and data.get("ida")):
        refuse("p695", p695, "Ct and x together, with [ida]: the margin at T = Cu Ct h^x rescales the records' IDA "
               "collapse intensities to Sa(T)")
    ida = data.get("ida") or {}
    if ida.get("stripes") == "interpolate" and data.get("losses"):
        refuse("ida.stripes", "interpolate", "\"run\" with [losses]: the losses need each stripe's residual drifts, "
               "which are never interpolated (a run at the stripe gives them; the IDA's runs at a stripe are taken as "
               "they are)")
    if "loo_limit" in ida and ida.get("stripes") != "interpolate":
        refuse("ida.loo_limit", ida["loo_limit"], "only with stripes = \"interpolate\" (it bounds the error of "
               "reading demands off the IDA curves)")
    if "uncertainty" in data:
        _check_uncertainty(refuse, data["uncertainty"], data, fields)
    if "p695" in data and measure != "Sa":
        refuse("intensity.measure", measure, "\"Sa\" with [p695]: FEMA P-695's margin compares S_CT with S_MT, "
               "both Sa(T)")


def _check_model(refuse, table, params, fields, storeys):
    for key, value in params.items():
        if key in NOT_IN_A_STUDY:
            refuse(f"{table}.{key}", value, NOT_IN_A_STUDY[key])
        if not storeys and key in PER_STOREY and key != "storey_height":
            refuse(f"{table}.{key}", value, "a building's (storeys >= 1): the pendulum primary has none")
        if storeys and key in PENDULUM_ONLY:
            refuse(f"{table}.{key}", value, "a parameter of the pendulum primary (storeys = 0) only: a building has "
                   "floors and storeys")
        if key not in fields:
            refuse(f"{table}.{key}", value, _unknown(fields, storeys) + " (the parameters of "
                   + (f"DampedShearBuilding{storeys}.fmu" if storeys else "PendulumImpactDamper.fmu") + ")")
        if not fields[key].ok(value):
            refuse(f"{table}.{key}", value, fields[key].text)


#: a configuration's `tmd`: a classical tuned mass damper of its mu (pidamper.tuning)
TMD = ("den-hartog", "warburton")


def _check_tmd(refuse, name, params, merged):
    """tmd = a rule of pidamper.tuning with mu > 0, no FR, zeta_p or d of its own, fidelity >= damped."""
    table = f"configurations.{name}"
    if params["tmd"] not in TMD:
        refuse(f"{table}.tmd", params["tmd"], "one of " + ", ".join(f'"{r}"' for r in TMD) + " (a tuned mass damper "
               "of the configuration's mu: Den Hartog's for a harmonic force, Warburton's for white-noise ground "
               "motion)")
    for key in ("FR", "zeta_p", "d"):
        if key in params:
            refuse(f"{table}.{key}", params[key], f"not with tmd = \"{params['tmd']}\": the rule gives it")
    if not (_number(params.get("mu")) and params["mu"] > 0):
        refuse(f"{table}.mu", params.get("mu", MISSING), "a mass ratio > 0 with tmd (the damper's mass over the "
               "building's)")
    if merged.get("fidelity", 0) in (0, "linear"):
        refuse(f"{table}.tmd", params["tmd"], "a fidelity of \"damped\" or above (the TMD's dashpot zeta_p acts "
               "from there)")


def _check_forms(refuse, table, params, merged, storeys):
    """A per-storey field and the FMU variables it fills, given both (here or in [building]): refused."""
    for alias, pattern in PER_STOREY.items():
        named = [pattern.format(k) for k in range(1, storeys + 1) if pattern.format(k) in merged]
        if alias in merged and named:
            key = alias if alias in params else named[0]
            refuse(f"{table}.{key}", params[key], f"{alias} and {', '.join(named)} are both given (in [building] "
                   "or here): give one of them")


def _check_hazard(refuse, hazard):
    """One form of hazard: a curve or points with their source, or k0 and k (a source may cite any);
    what only a curve has (imt, period, extrapolate) only with a curve."""
    forms = [form for form in ("curve", "points", "k0") if form in hazard]
    if len(forms) > 1 or ("k" in hazard and forms != ["k0"]):
        refuse("hazard", hazard, "one of: curve = a site hazard curve's file (CSV or USGS JSON), k0 and k (the power "
               "law k0 IM^-k), points = [[IM, rate], [IM, rate]] with their source")
    for key in ("imt", "period", "extrapolate"):
        if key in hazard and forms != ["curve"]:
            refuse(f"hazard.{key}", hazard[key], "only with hazard.curve (a power law is its own extrapolation)")
    if forms == ["k0"] and "k" not in hazard:
        refuse("hazard.k", MISSING, "the power law k0 IM^-k needs k0 and k")
    if forms in (["points"], ["curve"]) and "source" not in hazard:
        refuse("hazard.source", MISSING, FIELDS["hazard"]["source"].text)
    if not forms:
        refuse("hazard", hazard, REQUIRED_SECTIONS["hazard"])


def _check_uncertainty(refuse, spec, data, fields):
    """[uncertainty]: hazard = beta_h and cases [uncertainty.NAME] (UNCERTAINTY), with [losses]."""
    if not data.get("losses"):
        refuse("uncertainty", spec, "only with [losses]: it widens the intervals of the EAL, repair-time and "
               "collapse ratios")
    if not spec:
        refuse("uncertainty", spec, f"hazard = ... and/or {UNCERTAINTY['case']}")
    merged = {**data["building"], **{k: v for params in data["configurations"].values() for k, v in params.items()}}
    for name, value in spec.items():
        if name == "hazard":
            if not (_number(value) and 0 < value < 2):
                refuse("uncertainty.hazard", value, UNCERTAINTY["hazard"])
            continue
        if not isinstance(value, dict):
            refuse(f"uncertainty.{name}", value, f"hazard = beta_h or {UNCERTAINTY['case']}")
        for key in value:
            if key not in ("fields", "factor", "sides"):
                refuse(f"uncertainty.{name}.{key}", value[key], "the fields are fields, factor, sides")
        names = value.get("fields", MISSING)
        if not (isinstance(names, list) and names and all(isinstance(f, str) for f in names)):
            refuse(f"uncertainty.{name}.fields", names, "a list of FMU fields of the building or the configurations")
        for f in names:
            if f not in merged or not (_number(merged[f]) or isinstance(merged[f], list)):
                refuse(f"uncertainty.{name}.fields", f, "a numeric field given in [building] or a configuration ("
                       f"given: {', '.join(k for k, v in merged.items() if _number(v) or isinstance(v, list))})")
        factor = value.get("factor", MISSING)
        if not (_number(factor) and factor > 0 and factor != 1):
            refuse(f"uncertainty.{name}.factor", factor, "a number > 0, not 1: the fields' one-sigma multiplier")
        if value.get("sides", 2) not in (1, 2) or isinstance(value.get("sides"), bool):
            refuse(f"uncertainty.{name}.sides", value["sides"], "1 (x factor) or 2 (x and / factor)")
