"""The ground motions of a design study: each [excitations.NAME] table gives one or more members,
each a ground acceleration history [m/s2] at its own interval that every design (and the bare
building) is run against.

    kind = "harmonic"  ratios = [w / w_1, ...], amplitude [m/s2], periods (of the forcing; default
                       40): A sin(r w_1 t), one member per ratio, sampled at the design's step
    kind = "sweep"     start, end (w / w_1), amplitude [m/s2], periods (of the building's first
                       period T1; default 60): a linear sweep A sin(phi(t)), phi' from start w_1 to
                       end w_1, sampled at the design's step
    kind = "suite"     the keys of a study's [suite] (set = ..., records, components; folder = ...;
                       generator = "kanai-tajimi" ..., count, seed ...: forcing.ground_motion.suite),
                       each record a member at its own interval, scaled to sa [g] (Sa(T1, 5 %)) or
                       by factor (default 1)
"""
import hashlib
import math
from dataclasses import dataclass

import numpy as np

from ..assessment.study_file import StudyError
from ..forcing import ground_motion, spectra

G = 9.80665  # m/s2: the unit g of sa
KINDS = ("harmonic", "sweep", "suite")
_KEYS = {"harmonic": {"ratios", "amplitude", "periods"}, "sweep": {"start", "end", "amplitude", "periods"},
         "suite": {"sa", "factor"}}


@dataclass(frozen=True)
class Member:
    """One ground motion: its excitation's name, its own name, interval dt [s] and samples [m/s2]."""
    excitation: str
    name: str
    dt: float
    accel: tuple

    @property
    def digest(self):
        """A hash of the samples and the interval (a run's resume key changes with them)."""
        data = np.asarray(self.accel, dtype=np.float64).tobytes() + repr(self.dt).encode()
        return hashlib.sha1(data).hexdigest()[:16]


def members(tables, period, step, folder, source):
    """Every member of the excitation tables, in the file's order; a refusal names the field."""
    out = []
    for name, spec in tables.items():
        if not isinstance(spec, dict):
            raise StudyError(source, f"excitations.{name}", spec, "a table [excitations.NAME] with its kind")
        kind = spec.get("kind")
        if kind not in KINDS:
            raise StudyError(source, f"excitations.{name}.kind", kind, "one of " + ", ".join(f'"{k}"' for k in KINDS))
        rest = {k: v for k, v in spec.items() if k != "kind"}
        out += _MAKERS[kind](name, rest, period, step, folder, source)
    return out


def _positive(source, where, value, text):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0):
        raise StudyError(source, where, value, text)
    return float(value)


def _unknown(source, name, kind, spec):
    for key in spec:
        if key not in _KEYS[kind]:
            raise StudyError(source, f"excitations.{name}.{key}", spec[key], f"a {kind} excitation takes "
                             + ", ".join(sorted(_KEYS[kind])) + (" and a [suite]'s keys" if kind == "suite" else ""))


def _harmonic(name, spec, period, step, folder, source):
    _unknown(source, name, "harmonic", spec)
    ratios = spec.get("ratios", [1.0])
    if not (isinstance(ratios, list) and ratios):
        raise StudyError(source, f"excitations.{name}.ratios", ratios, "a list of frequency ratios w / w_1 (> 0)")
    ratios = [_positive(source, f"excitations.{name}.ratios", r, "a list of frequency ratios w / w_1 (> 0)")
              for r in ratios]
    amplitude = _positive(source, f"excitations.{name}.amplitude", spec.get("amplitude", "(missing)"),
                          "the ground acceleration's amplitude [m/s2] (> 0)")
    periods = _positive(source, f"excitations.{name}.periods", spec.get("periods", 40), "forcing periods (> 0)")
    out = []
    for r in ratios:
        t = step * np.arange(int(round(periods * period / r / step)) + 1)
        accel = amplitude * np.sin(r * 2.0 * math.pi / period * t)
        out.append(Member(name, f"{name} {r:g} w1", step, tuple(accel.tolist())))
    return out


def _sweep(name, spec, period, step, folder, source):
    _unknown(source, name, "sweep", spec)
    start, end = (_positive(source, f"excitations.{name}.{k}", spec.get(k, "(missing)"), "a frequency ratio w / w_1 "
                            "(> 0)") for k in ("start", "end"))
    if start == end:
        raise StudyError(source, f"excitations.{name}.end", end, f"a ratio other than start ({start:g}): a sweep")
    amplitude = _positive(source, f"excitations.{name}.amplitude", spec.get("amplitude", "(missing)"),
                          "the ground acceleration's amplitude [m/s2] (> 0)")
    periods = _positive(source, f"excitations.{name}.periods", spec.get("periods", 60), "first periods (> 0)")
    duration = periods * period
    w1 = 2.0 * math.pi / period
    t = step * np.arange(int(round(duration / step)) + 1)
    phase = w1 * (start * t + 0.5 * (end - start) * t * t / duration)
    return [Member(name, f"{name} {start:g}-{end:g} w1", step, tuple((amplitude * np.sin(phase)).tolist()))]


def _suite(name, spec, period, step, folder, source):
    scaling = {k: spec[k] for k in ("sa", "factor") if k in spec}
    if len(scaling) > 1:
        raise StudyError(source, f"excitations.{name}", spec, "sa or factor, not both")
    for key, value in scaling.items():
        _positive(source, f"excitations.{name}.{key}", value, "a number > 0 (sa in g)")
    try:
        records = ground_motion.suite({k: v for k, v in spec.items() if k not in scaling}, folder)
    except (ValueError, OSError) as err:
        raise StudyError(source, f"excitations.{name}", spec, str(err)) from None
    return scaled(name, records, period, **scaling)


def scaled(name, records, period, sa=None, factor=1.0):
    """Members of `records`, each scaled to Sa(period, 5 %) = sa [g], or by factor."""
    out = []
    for record in records:
        k = sa * G / spectra.sa(record, period, 0.05) if sa is not None else factor
        out.append(Member(name, record.name, float(record.dt), tuple((k * np.asarray(record.accel)).tolist())))
    return out


_MAKERS = {"harmonic": _harmonic, "sweep": _sweep, "suite": _suite}
