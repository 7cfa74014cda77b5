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
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


@dataclass(frozen=True)
class Forcing:
    """kind and args describe the signal (for logs); see the generator functions."""

    kind: str
    args: dict = field(default_factory=dict)
    start_values: dict = field(default_factory=dict)  # FMU parameters it sets (built-in harmonic)
    signal: object = None  # callable on numpy arrays of time, or None
    table: object = None  # (time, value) arrays of a recorded signal, or None
    target: str = "F"  # the FMU input it drives: "F" [N] or "a_g" [m/s2]

    def value(self, t):
        """The signal [N or m/s2] at time(s) t (0 without an external signal)."""
        if self.table is not None:
            times, values = self.table
            return np.interp(t, times, values)
        if self.signal is None:
            return np.zeros_like(np.asarray(t, dtype=float))
        return self.signal(np.asarray(t, dtype=float))

    def input_array(self, times):
        """fmpy input (structured array time, F, a_g; the input not driven is 0) sampled on the
        communication grid, or None."""
        if self.signal is None and self.table is None:
            return None
        times = np.asarray(times, dtype=float)
        signal = np.zeros(len(times), dtype=[("time", np.float64), ("F", np.float64), ("a_g", np.float64)])
        signal["time"] = times
        signal[self.target] = self.value(times)
        return signal


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
    """A synthetic accelerogram a_g(t) [m/s2]: white noise (fixed seed) through the Kanai-Tajimi
    filter (ground frequency omega_g [rad/s], damping zeta_g), shaped by a Jennings envelope (rise
    `rise` s, strong motion until `strong` s, then exponential decay) and scaled to peak `pga`."""
    from scipy import signal as sps

    args = {"duration": float(duration), "dt": float(dt), "pga": float(pga), "omega_g": float(omega_g),
            "zeta_g": float(zeta_g), "seed": int(seed), "rise": float(rise)}
    _check_finite(args)
    for name in ("duration", "dt", "omega_g", "zeta_g", "pga"):
        if args[name] <= 0:
            raise ValueError(f"{name} = {args[name]!r} is not allowed: it must be > 0")
    strong = 0.5 * duration if strong is None else float(strong)
    t = np.arange(0.0, duration + 0.5 * dt, dt)
    noise = np.random.default_rng(seed).standard_normal(len(t)) / math.sqrt(dt)
    kt = sps.lti([2 * zeta_g * omega_g, omega_g ** 2], [1.0, 2 * zeta_g * omega_g, omega_g ** 2])
    _, filtered, _ = sps.lsim(kt, noise, t)
    envelope = np.where(t < rise, (t / rise) ** 2, np.where(t < strong, 1.0, np.exp(-0.5 * (t - strong))))
    accel = filtered * envelope
    accel *= pga / np.max(np.abs(accel))
    args["strong"] = strong
    return Forcing("kanai-tajimi", args, table=(t, accel), target="a_g")


def _check_finite(args):
    for name, value in args.items():
        if not math.isfinite(value):
            raise ValueError(f"{name} = {value!r} is not allowed: it must be finite")
