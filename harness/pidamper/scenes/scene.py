"""Scenes: small TOML files that say everything a run needs.

    pidamper run free-decay              # a shipped scene, by name
    pidamper run my-scene.toml          # a scene file
    pidamper run resonance --periods 40  # any option of `pidamper run` overrides its field

Fields (every one optional but [forcing].kind):

    description = "..."
    [parameters]  FMU parameters and initial state, e.g. mu = 0.02, theta_dot_0 = 0.0; a building's
                  per-storey ones as a number (every storey) or a list of `storeys` numbers
                  (storey_Fy = [6e5, 5e5, 3e5]), or one storey's FMU variable ("storey[1].Fy" = 1e6)
    [forcing]     kind = "none" | "harmonic" | "sweep" | "csv" | "kanai-tajimi", and its arguments:
                  harmonic: F0 [N], Omega [rad/s] or Omega_ratio (of w2), phi [rad], sampled (bool)
                  sweep: F0, Omega_start / Omega_end [rad/s] or Omega_start_ratio / Omega_end_ratio
                  csv: file (time,F or time,a_g; relative to the scene file)
                  kanai-tajimi: pga [m/s2], omega_g [rad/s], zeta_g, seed, dt [s], rise [s], strong [s]
    [run]         stop_time [s] or periods (of the primary), output_interval [s], fidelity ("linear", "damped", "coupled" or "nonlinear")
    [outputs]     record = [...]: the FMU outputs kept in the result table and CSV
    [log]         mcap, rrd (bool); mcap_topics = [...]; rerun_views = [...]

A scene that does not follow this is refused with the field, its value and what is allowed.
"""
import difflib
import importlib.resources
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

from pidamper_physics.imk_storeys import IMK_DEFAULTS
from pidamper_physics.impact import MATERIAL_NAMES
from pidamper_physics.params import LEVELS, MAX_STOREYS

from .. import forcing as forcing_mod
from ..forcing.ground_motion import FEMA_P695_SETS
from ..errors import FieldError
from ..runlog.mcap_log import TOPICS as MCAP_TOPICS
from ..runlog.rerun_log import VIEWS as RERUN_VIEWS
from ..running.simulation import OUTPUTS, building_outputs, resonance

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

PARAMETERS = ("g", "M", "mu", "L2", "FR", "d", "d_angle", "e", "contact_form", "F0", "Omega", "phi",
              "theta_0", "theta_dot_0", "alpha_0", "alpha_dot_0", "angle_limit", "zeta_s", "zeta_p",
              "storeys", "damper_floor", "floor_m", "storey_k", "storey_h", "storey_Fy", "storey_b", "p_delta",
              "collapse_drift", "damping", "storey_law") + MATERIAL_NAMES + tuple(f"storey_{name}" for name in IMK_DEFAULTS)
#: a building's per-storey parameters: a number (every storey) or a list (storey 1 first), and the
#: FMU variables they fill (storey_<IMKBilin name>: storey[k].<IMKBilin name>, with storey_law = 1)
PER_STOREY = {"floor_m": "floor[{}].m", "storey_k": "storey[{}].k", "storey_h": "storey[{}].h",
              "storey_Fy": "storey[{}].Fy", "storey_b": "storey[{}].b",
              **{f"storey_{name}": f"storey[{{}}].{name}" for name in IMK_DEFAULTS}}
#: one storey's FMU variable (floor[k].m, storey[k].k, ...): it overrides the per-storey parameter
STOREY_VARIABLE = re.compile(r"(floor|storey)\[(\d+)\]\.(\w+)")
STOREY_VARIABLES = tuple(pattern.format("k") for pattern in PER_STOREY.values())
INTEGERS = ("storeys", "damper_floor", "contact_form", "p_delta", "restitution", "damping", "storey_law")
FIDELITY = LEVELS  # linear, damped, coupled, nonlinear: FMU parameter fidelity = the index
SECTIONS = ("description", "name", "parameters", "forcing", "run", "outputs", "log")
FORCING_ARGS = {
    "none": (),
    "harmonic": ("F0", "Omega", "Omega_ratio", "phi", "sampled"),
    "sweep": ("F0", "Omega_start", "Omega_end", "Omega_start_ratio", "Omega_end_ratio"),
    "csv": ("file",),
    "kanai-tajimi": ("pga", "omega_g", "zeta_g", "seed", "dt", "rise", "strong"),
    "fema-p695": ("set", "record", "component", "scale"),
}
RUN_KEYS = ("stop_time", "periods", "output_interval", "fidelity")
LOG_KEYS = ("mcap", "rrd", "mcap_topics", "rerun_views")


class SceneError(FieldError):
    """A scene field with a value that is not allowed."""


@dataclass
class Scene:
    name: str
    source: str
    description: str = ""
    parameters: dict = field(default_factory=dict)
    forcing: dict = field(default_factory=lambda: {"kind": "none"})
    run: dict = field(default_factory=dict)
    outputs: tuple = OUTPUTS
    log: dict = field(default_factory=dict)
    folder: Path = Path(".")

    # ---- what a run needs ----------------------------------------------------------------

    def summary(self):
        """What a run's log keeps of its scene."""
        return {"name": self.name, "source": self.source, "description": self.description}

    @property
    def start_values(self):
        """FMU start values: the parameters (a building's floor_m and storey_k spread over the
        floor[k].m and storey[k].k variables) and the fidelity level's index."""
        level = self.run.get("fidelity", "linear")
        return {**fmu_values(self.parameters), "fidelity": FIDELITY.index(level)}

    @property
    def w2(self):
        return resonance(self.start_values)

    @property
    def stop_time(self):
        if "stop_time" in self.run:
            return float(self.run["stop_time"])
        return float(self.run.get("periods", 10)) * 2 * math.pi / self.w2

    @property
    def output_interval(self):
        return float(self.run.get("output_interval", 0.01))

    def make_forcing(self):
        f = self.forcing
        kind = f["kind"]
        w2 = self.w2
        if kind == "none":
            return forcing_mod.none()
        if kind == "harmonic":
            omega = f.get("Omega", f.get("Omega_ratio", 1.0) * w2)
            return forcing_mod.harmonic(f.get("F0", 0.01 * 9.81), omega, f.get("phi", 0.0), f.get("sampled", False))
        if kind == "sweep":
            start = f.get("Omega_start", f.get("Omega_start_ratio", 0.5) * w2)
            end = f.get("Omega_end", f.get("Omega_end_ratio", 1.5) * w2)
            return forcing_mod.sweep(f.get("F0", 0.01 * 9.81), start, end, self.stop_time)
        if kind == "csv":
            path = self.folder / f["file"]
            if not path.is_file():
                raise SceneError(self.source, "forcing.file", f["file"],
                                 f"it must name an existing file (looked for {path.resolve()})")
            return forcing_mod.from_csv(path)
        if kind == "fema-p695":
            return forcing_mod.fema_p695(**{k: f[k] for k in FORCING_ARGS[kind] if k in f})
        args = {k: f[k] for k in FORCING_ARGS["kanai-tajimi"] if k in f}
        return forcing_mod.kanai_tajimi(self.stop_time, **args)


def fmu_values(parameters):
    """FMU start values of scene or study parameters: floor_m, storey_k, storey_h, storey_Fy and
    storey_b (a number for every storey, or a list, storey 1 first) spread over floor[k].m,
    storey[k].k, storey[k].h, storey[k].Fy and storey[k].b; a storey's own variable given by its
    FMU name (storey[1].Fy) overrides the spread value."""
    values = {k: v for k, v in parameters.items() if k not in PER_STOREY}
    for key, pattern in PER_STOREY.items():
        given = parameters.get(key)
        if given is not None:
            listed = given if isinstance(given, list) else [given] * MAX_STOREYS
            values.update({pattern.format(k): float(v) for k, v in enumerate(listed, start=1)})
    values.update({k: float(v) for k, v in parameters.items() if storey_variable(k)})
    return values


def storey_variable(name):
    """(the per-storey parameter, k) of a storey's FMU variable name (storey[2].Fy: ('storey_Fy', 2)),
    or None."""
    found = STOREY_VARIABLE.fullmatch(name)
    if found is None:
        return None
    for key, pattern in PER_STOREY.items():
        if pattern.format(found.group(2)) == name and not found.group(2).startswith("0"):
            return key, int(found.group(2))
    return None


def check_parameters(params, source, prefix="parameters."):
    """Refuse a parameter the FMU does not have, or a value it cannot take, naming it and the rule
    (an unknown name with the closest valid ones); `prefix` + name is the field named."""
    storeys = params.get("storeys", 0)
    if type(storeys) is not int or not 0 <= storeys <= MAX_STOREYS:
        raise SceneError(source, f"{prefix}storeys", storeys,
                         f"an integer in 0..{MAX_STOREYS} (0: the pendulum system, N: a building of N storeys)")
    no_building = "a building's parameter: give storeys >= 1 with it (storeys = 0, the pendulum system, has none)"
    for key, value in params.items():
        field_ = f"{prefix}{key}"
        own = storey_variable(key)
        if own is not None:
            _number(source, field_, value)
            if not storeys:
                raise SceneError(source, field_, value, no_building)
            if not 1 <= own[1] <= storeys:
                raise SceneError(source, field_, value,
                                 f"the building's storeys are 1..{storeys} (storeys = {storeys})")
            continue
        if key not in PARAMETERS:
            raise SceneError(source, field_, value, _unknown(key, storeys))
        if key in PER_STOREY:
            if not storeys:
                raise SceneError(source, field_, value, no_building)
            if isinstance(value, list):
                if len(value) != storeys:
                    raise SceneError(source, field_, value, f"a number (every storey) or a list of storeys = "
                                     f"{storeys} numbers (storey 1 first), not {len(value)}")
                for k, item in enumerate(value, start=1):
                    _number(source, f"{field_}[{k}]", item)
                continue
        _number(source, field_, value)
        if key in INTEGERS and not isinstance(value, int):
            raise SceneError(source, field_, value, "an integer")


def _unknown(name, storeys):
    """What an unknown parameter name is told: the closest valid names, then all of them."""
    own = [pattern.format(k) for pattern in PER_STOREY.values() for k in range(1, storeys + 1)]
    names = PARAMETERS + tuple(own)
    lowered = {n.lower(): n for n in names}
    close = [lowered[n] for n in difflib.get_close_matches(name.lower(), list(lowered), n=4, cutoff=0.6)]
    tail = name.lower().rpartition(".")[2].rpartition("_")[2]  # Fy: storey_Fy, storey[k].Fy
    close += [n for n in names if n not in close and tail and re.split(r"[._]", n.lower())[-1] == tail]
    hint = f"did you mean {', '.join(close[:4])}? " if close else ""
    if name == "fidelity":
        hint = "the level is run.fidelity (pidamper run --fidelity). "
    storey_names = (f"; a building's storey k = 1..{storeys} by its FMU name: {', '.join(STOREY_VARIABLES)}"
                    if storeys else "")
    return f"{hint}FMU parameters are {', '.join(PARAMETERS)}{storey_names}"


def shipped():
    """Names of the scenes installed with the package."""
    folder = importlib.resources.files("pidamper.scenes")
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def load(name_or_path):
    """A scene from a file path, or a shipped scene by name."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        if not path.is_file():
            raise FileNotFoundError(f"scene file {path} does not exist")
        text, source, folder = path.read_text(), str(path), path.parent
    else:
        resource = importlib.resources.files("pidamper.scenes") / f"{name_or_path}.toml"
        if not resource.is_file():
            raise SceneError("pidamper run", "scene", name_or_path,
                             f"a scene file, or one of the shipped scenes: {', '.join(shipped())}")
        text, source, folder = resource.read_text(), f"scene {name_or_path}", Path(".")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise SceneError(source, "file", "TOML", f"it must be valid TOML ({err})") from None
    return parse(data, source, folder, Path(source).stem if source.endswith(".toml") else name_or_path)


def parse(data, source="scene", folder=Path("."), name="scene"):
    """Validate a scene's TOML data; every refusal names the field, its value and what is allowed."""
    for key in data:
        if key not in SECTIONS:
            raise SceneError(source, key, data[key], f"the top-level fields are {', '.join(SECTIONS)}")
    params = _table(data, "parameters", source)
    check_parameters(params, source)
    forcing = _table(data, "forcing", source) or {"kind": "none"}
    kind = forcing.get("kind")
    if kind not in FORCING_ARGS:
        raise SceneError(source, "forcing.kind", kind, f"one of {', '.join(FORCING_ARGS)}")
    for key, value in forcing.items():
        if key == "kind":
            continue
        if key not in FORCING_ARGS[kind]:
            raise SceneError(source, f"forcing.{key}", value,
                             f"forcing of kind {kind!r} takes {', '.join(FORCING_ARGS[kind]) or 'no arguments'}")
        if key == "file":
            if not isinstance(value, str):
                raise SceneError(source, "forcing.file", value, "a file name (string)")
        elif key == "sampled":
            if not isinstance(value, bool):
                raise SceneError(source, "forcing.sampled", value, "true or false")
        elif key == "set":
            if value not in FEMA_P695_SETS:
                raise SceneError(source, "forcing.set", value, f"one of {', '.join(FEMA_P695_SETS)}")
        elif key == "component":
            if value not in ("a", "b"):
                raise SceneError(source, "forcing.component", value, "'a' or 'b' (the record's two horizontal "
                                 "components)")
        else:
            _number(source, f"forcing.{key}", value)
    if kind == "csv" and "file" not in forcing:
        raise SceneError(source, "forcing.file", None,
                         "a csv forcing needs its file (columns time,F or time,a_g; relative to the scene file)")
    run = _table(data, "run", source)
    for key, value in run.items():
        if key not in RUN_KEYS:
            raise SceneError(source, f"run.{key}", value, f"the run fields are {', '.join(RUN_KEYS)}")
        if key == "fidelity":
            if value not in FIDELITY:
                raise SceneError(source, "run.fidelity", value, f"one of {', '.join(FIDELITY)}")
        elif _number(source, f"run.{key}", value) <= 0:
            raise SceneError(source, f"run.{key}", value, "it must be > 0")
    if "stop_time" in run and "periods" in run:
        raise SceneError(source, "run", "stop_time and periods", "give one of them")
    outputs = _table(data, "outputs", source)
    record = tuple(outputs.get("record", OUTPUTS + building_outputs(params)))
    for key in outputs:
        if key != "record":
            raise SceneError(source, f"outputs.{key}", outputs[key], "the outputs field is record")
    available = OUTPUTS + building_outputs(params)
    for name_ in record:
        if name_ not in available:
            raise SceneError(source, "outputs.record", name_, f"FMU outputs are {', '.join(available)}")
    log = _table(data, "log", source)
    for key, value in log.items():
        if key not in LOG_KEYS:
            raise SceneError(source, f"log.{key}", value, f"the log fields are {', '.join(LOG_KEYS)}")
        if key in ("mcap", "rrd") and not isinstance(value, bool):
            raise SceneError(source, f"log.{key}", value, "true or false")
        allowed = MCAP_TOPICS if key == "mcap_topics" else RERUN_VIEWS if key == "rerun_views" else None
        if allowed:
            for item in value:
                if item not in allowed:
                    raise SceneError(source, f"log.{key}", item, f"one of {', '.join(allowed)}")
    description = data.get("description", "")
    return Scene(name=data.get("name", name), source=source, description=description, parameters=params,
                 forcing=forcing, run=run, outputs=record, log=log, folder=folder)


def _table(data, key, source):
    value = data.get(key, {})
    if not isinstance(value, dict):
        raise SceneError(source, key, value, "a table ([" + key + "])")
    return dict(value)


def _number(source, name, value):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SceneError(source, name, value, "a finite number")
    return float(value)
