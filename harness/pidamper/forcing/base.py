"""What a run receives (`Forcing`): the FMU's built-in harmonic, or a signal the host samples at the
start of each communication step and holds over it, on input F [N] or a_g [m/s2]."""
from dataclasses import dataclass, field

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
