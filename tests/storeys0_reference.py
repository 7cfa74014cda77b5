"""Rows of the pendulum levels (storeys = 0) that the building work must leave unchanged, bit for bit.

`python tests/storeys0_reference.py OUT.csv` writes them with the physics package on sys.path; the
committed tests/data/storeys0_reference.csv was written by the code before buildings were added
(commit afc9ed0), and tests/test_building.py recomputes the rows and compares every bit."""
import csv
import math
import sys

CASES = {  # level: parameters (the rest default) and the initial primary velocity [rad/s]
    "linear": ({"fidelity": 0}, 0.5),
    "damped": ({"fidelity": 1, "zeta_s": 0.02, "zeta_p": 0.05}, 0.5),
    "coupled": ({"fidelity": 2, "zeta_s": 0.02, "zeta_p": 0.05, "FR": 1.0, "d": 0.02}, 0.3),
    "coupled-harmonic": ({"fidelity": 2, "zeta_s": 0.01, "FR": 2.0, "d": 0.002, "F0": 0.3, "Omega": 3.0}, 0.0),
    "nonlinear": ({"fidelity": 3, "d": 0.01, "FR": 2.0}, 1.0),
}
FIELDS = ("x", "v", "y", "u", "impacts", "energy", "dissipated", "work_in", "viscous")


def rows():
    from pidamper_physics import Damper, Params

    out = []
    for name, (values, theta_dot0) in CASES.items():
        core = Damper(Params(**values), theta_dot0=theta_dot0)
        for k in range(1, 401):
            core.advance(0.01 * k, 0.2 * math.sin(1.3 * k * 0.01), 0.3 * math.cos(2.1 * k * 0.01))
            out.append([name, k] + [getattr(core, f) for f in FIELDS])
    return out


def write(path):
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(("case", "step") + FIELDS)
        for row in rows():
            writer.writerow([repr(v) if isinstance(v, float) else v for v in row])


if __name__ == "__main__":
    write(sys.argv[1])
