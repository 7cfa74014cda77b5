"""OpenSees converging to our Rayleigh damping models (issue 37, item 4): the 3-storey yielding
building with P-Delta under 3 s of held random ground motion, ours (exact, event-driven) against
OpenSees's `rayleigh` (zeroLength storeys with -doRayleigh 1; Newmark average acceleration, Newton)
at falling steps; prints the roof's largest difference over its peak per model and step.

    python -m pidamper.benchmarks.damping_peer
"""
import importlib.metadata

import numpy as np

from pidamper.running import isolated
from pidamper_physics.yielding import building_motion

MASSES, STIFFNESSES, YIELD_FORCES, RATIOS, HEIGHTS = [1e5] * 3, [8e7] * 3, [6e5, 5e5, 3e5], [0.02] * 3, [3.0] * 3
ZETA, INTERVAL, STEPS = 0.05, 0.01, 300
MODELS = {1: "rayleigh-initial", 2: "rayleigh-tangent"}


def record(seed=5, sigma=3.0):
    """The held ground acceleration samples [m/s2], one per INTERVAL, STEPS + 1 of them."""
    return np.random.default_rng(seed).normal(0.0, sigma, STEPS + 1)


def ours_roof(damping, samples):
    """Our roof displacement [m] at every INTERVAL instant (t = 0 first)."""
    motion = building_motion(MASSES, STIFFNESSES, HEIGHTS, ZETA, YIELD_FORCES, RATIOS, p_delta=1, damping=damping)
    roof = [0.0]
    for i in range(STEPS):
        motion.advance((i + 1) * INTERVAL, [0.0] * 3, samples[i])
        roof.append(motion.x[2])
    return np.array(roof)


def roof_errors(damping, steps, samples=None):
    """OpenSees's roof against ours, the largest difference over our peak, at each analysis step."""
    samples = record() if samples is None else samples
    roof = ours_roof(damping, samples)
    out = []
    for dt in steps:
        theirs = np.array(isolated.call("pidamper.oracles.opensees:roof_history", MASSES, STIFFNESSES, YIELD_FORCES,
                                        RATIOS, HEIGHTS, ZETA, True, list(map(float, samples)), INTERVAL, dt,
                                        STEPS * INTERVAL, MODELS[damping], hard_exit=True))
        out.append(float(np.abs(theirs - roof).max() / np.abs(roof).max()))
    return out


def main():
    steps = (2e-3, 5e-4, 1.25e-4)
    print(f"openseespy {importlib.metadata.version('openseespy')}; roof difference over its peak")
    print("| model | " + " | ".join(f"dt = {dt:g} s" for dt in steps) + " |")
    print("|---|" + "---:|" * len(steps))
    for damping, name in MODELS.items():
        print(f"| {name} | " + " | ".join(f"{e:.2g}" for e in roof_errors(damping, steps)) + " |")


if __name__ == "__main__":
    main()
