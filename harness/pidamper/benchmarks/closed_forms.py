"""Cost of one closed-form evaluation of a one-degree-of-freedom oscillator: the fast path
(oscillator.Oscillator, undamped with the harmonic) against the general complex modal form
(modal.Motion with n = 1) on the same motion, free and forced; the figures quoted in
pidamper_physics/oscillator.py's docstring.

    python -m pidamper.benchmarks.closed_forms [--calls N] [--repeats R]

Process CPU time per state() call, minimum over the repeats; the largest |x| difference of the two
forms on the same motion shows they are the same motion to rounding.
"""
import argparse
import time

from pidamper_physics.modal import Modes, Motion
from pidamper_physics.oscillator import Oscillator

from ..machine import describe


def per_call(function, taus, repeats):
    """Least CPU microseconds per call of function(tau) over `repeats` passes."""
    best = float("inf")
    for _ in range(repeats):
        start = time.process_time()
        for tau in taus:
            function(tau)
        best = min(best, (time.process_time() - start) / len(taus) * 1e6)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m pidamper.benchmarks.closed_forms", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--calls", type=int, default=200000)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    w, x0, v0, c, om, psi = 3.13, 0.01, 0.2, 0.05, 2.9, 0.4
    taus = [1e-3 * (k % 997) for k in range(args.calls)]
    print(f"Machine: {describe()}; {args.calls} calls, least of {args.repeats} passes, process CPU time.\n")
    print("| motion | Oscillator us/call | Motion n=1 us/call | ratio | max abs x difference |")
    print("|---|---:|---:|---:|---:|")
    for label, a in (("free (constant load)", 0.0), ("forced (constant + harmonic)", 0.3)):
        fast = Oscillator(w, x0, v0, c=c, a=a, om=om, psi=psi)
        modal = Motion(Modes([[w * w]], [[0.0]]), [x0, v0], [c], [a] if a else None, om, psi)
        t_fast, t_modal = per_call(fast.state, taus, args.repeats), per_call(modal.state, taus, args.repeats)
        diff = max(abs(fast.state(tau)[0] - modal.state(tau)[0]) for tau in taus[:997])
        print(f"| {label} | {t_fast:.2f} | {t_modal:.2f} | {t_modal / t_fast:.1f} | {diff:.1e} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
