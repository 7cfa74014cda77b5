"""The smallest pythonfmu co-simulation FMU with the damper's recorded width: four outputs y1..y4 = u.

Its cost per step under a host is the floor for any pythonfmu FMU on that host.
"""
from pythonfmu import Fmi2Causality, Fmi2Slave, Real

OUTPUTS = ("y1", "y2", "y3", "y4")


class TrivialPythonFmu(Fmi2Slave):
    """y1 = y2 = y3 = y4 = u."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.u = 0.0
        self.register_variable(Real("u", causality=Fmi2Causality.input))
        for name in OUTPUTS:
            setattr(self, name, 0.0)
            self.register_variable(Real(name, causality=Fmi2Causality.output))

    def do_step(self, current_time, step_size):
        self.y1 = self.y2 = self.y3 = self.y4 = self.u
        return True
