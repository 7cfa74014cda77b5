"""OpenSees converging to our deteriorating building (issue 37): the 3-storey building of `IMKBilin`
storeys with P-Delta under a held two-cycle pulse that takes storey 1 past capping, ours (exact,
event-driven) against OpenSees (zeroLength `IMKBilin` storeys, `modalDamping`, Newmark average
acceleration, Newton) at falling steps, bare and with the pendulum damper on the roof (ours only: the
speed).  Prints per step OpenSees's roof error over the peak and its CPU per simulated second, and
ours.

    python -m pidamper.benchmarks.imk_peer
"""
import importlib.metadata
import math
import time

import numpy as np

from pidamper.running import isolated
from pidamper_physics import Damper, Params
from pidamper_physics.imk_storeys import imk_tables
from pidamper_physics.yielding import building_motion

MASSES, STIFFNESSES, YIELD_FORCES, HEIGHTS = [1e5] * 3, [8e7] * 3, [6e5, 5.2e5, 3.2e5], [3.0] * 3
SIDE = dict(dp=0.02, dpc=0.3, du=0.5, FmaxFy=1.3, FresFy=0.3)
#: each storey: capping 2 cm past yield at 1.3 Fy, zero force 30 cm beyond, residual 0.3 Fy, Lamda 1 m
ENTRY = {**{f"{k}_{s}": v for k, v in SIDE.items() for s in ("pos", "neg")}, "LamdaS": 1.0, "LamdaC": 1.0,
         "LamdaK": 1.0}
TABLES = imk_tables(STIFFNESSES, YIELD_FORCES, [ENTRY] * 3)
ZETA, INTERVAL, SECONDS, AMPLITUDE = 0.05, 0.01, 6.0, 3.5
STEPS = (5e-3, 2e-3, 1e-3, 1e-4, 1e-5)


def record():
    """The held ground acceleration [m/s2] per INTERVAL: two 1 s sine cycles of AMPLITUDE, then 0."""
    n = int(round(SECONDS / INTERVAL))
    return [AMPLITUDE * math.sin(2.0 * math.pi * i * INTERVAL) if i * INTERVAL < 2.0 else 0.0 for i in range(n + 1)]


def ours_roof(samples):
    """(our roof displacement [m] at every INTERVAL instant, CPU seconds of the run)."""
    start = time.process_time()
    motion = building_motion(MASSES, STIFFNESSES, HEIGHTS, ZETA, None, None, p_delta=1, collapse_drift=0.3, imk=TABLES)
    roof = [0.0]
    for i in range(len(samples) - 1):
        motion.advance((i + 1) * INTERVAL, [0.0] * 3, samples[i])
        roof.append(motion.x[2])
    return np.array(roof), time.process_time() - start


def ours_damped_cpu(samples):
    """CPU seconds of the same run with the damper (5 % of the mass, tuned, 2 cm gap) on the roof."""
    start = time.process_time()
    core = Damper(Params(storeys=3, mu=0.05, FR=0.95, d=0.02, e=0.5, fidelity=1, zeta_s=ZETA, storey_Fy=YIELD_FORCES,
                         p_delta=1, floor_m=MASSES, storey_k=STIFFNESSES, storey_law=1, storey_imk=[ENTRY] * 3,
                         collapse_drift=0.3))
    for i in range(len(samples) - 1):
        core.advance((i + 1) * INTERVAL, 0.0, samples[i])
    return time.process_time() - start


def opensees_roof(samples, dt):
    """(OpenSees's roof at every INTERVAL instant, its CPU seconds) at the analysis step dt."""
    out = isolated.call("pidamper.benchmarks.imk_peer:_timed_opensees", list(map(float, samples)), dt, hard_exit=True)
    return np.array(out[0]), out[1]


def _timed_opensees(samples, dt):
    from pidamper.oracles.opensees import roof_history

    start = time.process_time()
    roof = roof_history(MASSES, STIFFNESSES, YIELD_FORCES, [0.0] * 3, HEIGHTS, ZETA, True, samples, INTERVAL, dt,
                        (len(samples) - 1) * INTERVAL, imk=TABLES)
    return roof, time.process_time() - start


def roof_errors(steps=STEPS):
    """[(dt, OpenSees's roof error over the peak, its CPU s per simulated s)], ours as (roof, CPU)."""
    samples = record()
    roof, cpu = ours_roof(samples)
    seconds = (len(samples) - 1) * INTERVAL
    rows = []
    for dt in steps:
        theirs, their_cpu = opensees_roof(samples, dt)
        rows.append((dt, float(np.abs(theirs - roof).max() / np.abs(roof).max()), their_cpu / seconds))
    return rows, (roof, cpu / seconds)


def main():
    rows, (roof, cpu) = roof_errors()
    samples = record()
    damped = ours_damped_cpu(samples) / ((len(samples) - 1) * INTERVAL)
    print(f"openseespy {importlib.metadata.version('openseespy')}; 3-storey IMKBilin building with P-Delta, "
          f"{AMPLITUDE} m/s2 two-cycle pulse, {SECONDS} s; peak roof {np.abs(roof).max():.4g} m")
    print("| OpenSees dt [s] | roof error / peak | CPU s per simulated s |")
    print("|---:|---:|---:|")
    for dt, err, their in rows:
        print(f"| {dt:g} | {err:.2g} | {their:.3g} |")
    print(f"| ours (exact) | 0 (reference) | {cpu:.3g} |")
    print(f"| ours with the damper on the roof | | {damped:.3g} |")


if __name__ == "__main__":
    main()
