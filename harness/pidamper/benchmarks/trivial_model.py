"""The smallest pythonfmu co-simulation FMU: one Real input, two Real outputs copied from it and
one Integer output counting the steps.

Its cost per step under a host is the floor for any pythonfmu FMU recording the same
outputs on that host (fmpy reads Real and Integer outputs with one FMI call each).
"""
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real

REALS = ("y1", "y2")


class TrivialPythonFmu(Fmi2Slave):
    """y1 = y2 = u, n = steps taken."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.u = 0.0
        self.n = 0
        self.register_variable(Real("u", causality=Fmi2Causality.input))
        for name in REALS:
            setattr(self, name, 0.0)
            self.register_variable(Real(name, causality=Fmi2Causality.output))
        self.register_variable(Integer("n", causality=Fmi2Causality.output, variability=Fmi2Variability.discrete))

    def do_step(self, current_time, step_size):
        self.y1 = self.y2 = self.u
        self.n += 1
        return True
