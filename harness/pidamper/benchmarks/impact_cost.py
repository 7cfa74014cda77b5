"""CPU cost per impact of the physics core, on impact-dense runs (no output steps in between).

    python -m pidamper.benchmarks.impact_cost [--repeats 5]
"""
import argparse
import math
import platform
import time

from pidamper_physics import Damper, Params

W2 = math.sqrt(9.81)
CASES = (
    ("e = 1, FR 5, d 0.1 (chaotic, no sticking)", {"e": 1.0}, 200.0),
    ("e = 0.8, FR 5, d 0.02 (chatter)", {"e": 0.8, "d": 0.02}, 60.0),
    ("e = 1, FR 20, d 0.1", {"e": 1.0, "FR": 20.0}, 60.0),
)


def cost_per_impact(values, t_end, repeats):
    """(minimum CPU seconds per impact, impacts) of the core advancing to t_end from A0 = 0.7 rad."""
    best, impacts = math.inf, 0
    for _ in range(repeats):
        core = Damper(Params(**values), theta_dot0=0.7 * W2)
        t0 = time.process_time()
        core.advance(t_end)
        best = min(best, time.process_time() - t0)
        impacts = core.impacts
    return best / impacts, impacts


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    print(f"Python {platform.python_version()} on {platform.machine()}, min of {args.repeats} runs, process CPU time")
    print(f"{'case':45s} {'impacts':>8s} {'us/impact':>10s}")
    for name, values, t_end in CASES:
        cost, impacts = cost_per_impact(values, t_end, args.repeats)
        print(f"{name:45s} {impacts:8d} {cost * 1e6:10.1f}")


if __name__ == "__main__":
    main()
