"""The coupled system's parameters (`Scenario`), a co-simulation's result (`Run`) and the scenario
from command-line fields (`scenario_from`)."""
from dataclasses import dataclass, field, replace

import numpy as np

UNIT = "PendulumImpactDamperUnit"
BUILDING = "ShearBuilding"  # the building's role; its FMU is ShearBuilding<storeys>.fmu (Scenario.building_model)
SYSTEM = "DamperOnBuilding"

@dataclass(frozen=True)
class Scenario:
    """A building with the damper unit on floor `damper_floor` (1..storeys; 0 = the top floor, as in
    the monolithic model's Params), excited by a ground
    acceleration pulse `pulse` [m/s2] over [0, pulse_time) [s], from rest.

    The particle is given as in the monolithic model: m = mu * (building mass), w1 = FR * w_1 (the
    building's first natural frequency), L1 = g / w1^2; M_s = the damper floor's mass.  Defaults:
    the convergence benchmark's case (3 storeys of 1e5 kg and 8e7 N/m: T1 = 0.499 s; 2 % modal
    damping; a 6 t particle at the top, w1 = w_1 / 2, d = 2 cm, e = 0.5; 2 m/s2 for half a
    period): 20 impacts in 5 s, every one well separated (no chatter, no sticking)."""

    storeys: int = 3
    floor_m: tuple = (1e5,) * 10  # per floor / storey, 1 first; entries beyond `storeys` are ignored
    storey_k: tuple = (8e7,) * 10
    zeta_s: float = 0.02
    damper_floor: int = 0
    mu: float = 0.02
    FR: float = 0.5
    g: float = 9.81
    d: float = 0.02
    e: float = 0.5
    zeta_p: float = 0.0
    pulse: float = 2.0
    pulse_time: float = 0.25
    stop_time: float = 5.0

    @property
    def building_model(self):
        """The building's FMU model: ShearBuilding<storeys>."""
        return f"{BUILDING}{self.storeys}"

    @property
    def building(self):
        from pidamper_physics.shear_motion import make_building

        return make_building(list(self.floor_m[:self.storeys]), list(self.storey_k[:self.storeys]), self.zeta_s)

    @property
    def floor(self):
        """Number (1-based) of the damper floor."""
        if not 0 <= self.damper_floor <= self.storeys:
            raise ValueError(f"damper_floor = {self.damper_floor!r} is not allowed: 0 (the top) or 1..storeys")
        return self.damper_floor or self.storeys

    @property
    def j(self):
        """Index (0-based) of the damper floor."""
        return self.floor - 1

    @property
    def m(self):
        return self.mu * sum(self.floor_m[:self.storeys])

    @property
    def M_s(self):
        return self.floor_m[self.j]

    @property
    def w1(self):
        return self.FR * self.building.w_1

    @property
    def L1(self):
        return self.g / self.w1 ** 2

    def building_values(self):
        values = {"zeta_s": self.zeta_s}
        for k in range(self.storeys):
            values[f"floor[{k + 1}].m"] = self.floor_m[k]
            values[f"storey[{k + 1}].k"] = self.storey_k[k]
        return values

    def unit_values(self, impulse_aware=False):
        return {"m": self.m, "M_s": self.M_s, "L1": self.L1, "g": self.g, "d": self.d, "e": self.e,
                "zeta_p": self.zeta_p, "impulse_aware": int(bool(impulse_aware))}

    def ground(self, t, h):
        """a_g held over the step [t, t + h]: the pulse's mean over it (exact where the pulse's end
        is a communication point, and its impulse always kept)."""
        if h <= 0.0:
            return self.pulse if t < self.pulse_time else 0.0
        return self.pulse * max(0.0, min(t + h, self.pulse_time) - t) / h

    def steps(self, h):
        n = int(round(self.stop_time / h))
        if abs(n * h - self.stop_time) > 1e-9 * self.stop_time:
            raise ValueError(f"step {h!r} is not allowed: it must divide stop_time = {self.stop_time!r}")
        return n


@dataclass
class Run:
    """A co-simulation's result on its communication grid."""

    master: str
    h: float
    time: np.ndarray
    x: np.ndarray          # floor displacements [m], one row per communication point, one column per floor
    r: np.ndarray          # the unit's r [m]
    impacts: int
    wall: float            # s, wall time of the stepping loop (instantiation excluded)
    notes: list = field(default_factory=list)

    def at(self, times):
        """Rows of x at `times` (points of the grid)."""
        index = np.rint(np.asarray(times) / self.h).astype(int)
        if np.max(np.abs(index * self.h - np.asarray(times))) > 1e-9 * max(1.0, float(np.max(times))):
            raise ValueError(f"times are not points of the grid of step {self.h}")
        return self.x[index]


def scenario_from(params, stop_time=None):
    scn = Scenario()
    scalars = [k for k in Scenario.__dataclass_fields__ if k not in ("floor_m", "storey_k")]
    fields = {}
    for text in params:
        name, sep, value = text.partition("=")
        if not sep or name not in scalars:
            raise ValueError(f"-p {text!r} is not allowed: NAME=VALUE with NAME a scalar field of Scenario "
                             f"({', '.join(scalars)})")
        kind = type(getattr(scn, name))
        try:
            fields[name] = kind(value)
        except ValueError:
            raise ValueError(f"-p {text!r} is not allowed: {value!r} is not a {kind.__name__}") from None
    if stop_time is not None:
        fields["stop_time"] = stop_time
    return replace(scn, **fields)
