"""Hard cases run through the FMU: invariants hold, nothing penetrates, stalls or crashes.

    pidamper stress [--quick] [--case NAME ...]

Each case drives the FMU with fmpy (simulate_fmu, or a hand-written FMU2Slave loop where
fmpy itself is the limit: it merges steps closer than a relative 1e-9 and records every
output in memory) and returns (passed, detail). tests/test_stress.py runs the same cases
under a time limit; this command prints them as a table.
"""
import argparse
import math
import resource
import time

import numpy as np

from ..running.fmu import find_fmu
from ..running.stepper import FmuStepper

W2 = math.sqrt(9.81)
PERIOD = 2 * math.pi / W2
FREE = {"mu": 0.1, "FR": 5.0, "d": 0.1, "e": 0.2, "theta_dot_0": 0.7 * W2}


class Probe(FmuStepper):
    """An FmuStepper that also reads the state and bookkeeping outputs."""

    NAMES = ("x", "y", "z", "energy", "energy_dissipated", "work_in")

    def state(self):
        vals = self.fmu.getReal(self.vr(*self.NAMES))
        return dict(zip(self.NAMES, vals))


def _balance(s, e0):
    """|E(0) + W_in - E(t) - dissipated| relative to the energy scale."""
    scale = max(abs(e0), abs(s["energy"]), abs(s["work_in"]), abs(s["energy_dissipated"]), 1e-300)
    return abs(e0 + s["work_in"] - s["energy"] - s["energy_dissipated"]) / scale


def _march(fmu, values, times, force=None, check_gap=True, d=None):
    """Step the FMU through `times`; return the worst penetration of a stop relative to the size of
    the motion (positions are rounded to that scale), the worst balance error, the last state and
    the impact count."""
    d = d if d is not None else values.get("d", 0.1)
    with Probe(fmu, values) as probe:
        e0 = probe.state()["energy"]
        pen = bal = 0.0
        for k, t in enumerate(times):
            if force is not None:
                probe.set("F", force(k, probe.t))
            probe.advance(t)
            s = probe.state()
            if check_gap:
                pen = max(pen, (abs(s["z"]) - d) / max(d, abs(s["x"]), abs(s["y"])))
            bal = max(bal, _balance(s, e0))
        return pen, bal, s, probe.get("impacts")


def _verdict(ok, detail):
    return bool(ok), detail


# ---- the cases ----------------------------------------------------------------------------

def resonance_no_contact(fmu, quick=False):
    """Exact resonance over 10^4 periods without contact: secular growth against the closed form."""
    F0, n = 0.01, 1000 if quick else 10_000
    values = {"mu": 0.1, "d": 1e6, "F0": F0, "Omega": W2, "phi": 0.0, "theta_dot_0": 0.0}
    worst = scale = 0.0
    with Probe(fmu, values) as probe:
        for k in range(1, n + 1):
            t = k * PERIOD
            probe.advance(t)
            x = probe.state()["x"]
            ref = F0 / (2 * W2 * W2) * (math.sin(W2 * t) - W2 * t * math.cos(W2 * t))
            worst, scale = max(worst, abs(x - ref)), max(scale, abs(ref))
    err = worst / scale
    return _verdict(err < 1e-9, f"{n} periods, steps of one period: max |x - closed form| = {err:.1e} of max|x| "
                                f"({scale:.3g} m)")


def resonance_with_damper(fmu, quick=False):
    """Exact resonance with the damper: the amplitude stays bounded over 10^4 periods."""
    n = 500 if quick else 10_000
    values = {"mu": 0.02, "d": 0.1, "e": 0.2, "F0": 0.0981, "Omega": W2, "theta_dot_0": 0.0}
    times = [k * PERIOD / 4 for k in range(1, 4 * n + 1)]
    peaks = []
    with Probe(fmu, values) as probe:
        e0 = probe.state()["energy"]
        bal = 0.0
        for k, t in enumerate(times):
            probe.advance(t)
            s = probe.state()
            peaks.append(abs(s["x"]))
            bal = max(bal, _balance(s, e0))
        impacts = probe.get("impacts")
    first, last = max(peaks[: len(peaks) // 10]), max(peaks[-len(peaks) // 10:])
    undamped = 0.0981 / (2 * W2) * n * PERIOD
    ok = last < 3 * first and last < 0.05 * undamped and bal < 1e-9
    return _verdict(ok, f"{n} periods: max|x| first tenth {first:.3g} m, last tenth {last:.3g} m "
                        f"(undamped would reach {undamped:.3g} m), {impacts} impacts, balance {bal:.1e}")


def near_resonance(fmu, quick=False):
    """Omega within 1e-12 of w2: the solution equals the resonance closed form up to the detuning."""
    F0 = 0.01
    values = {"mu": 0.1, "d": 1e6, "F0": F0, "Omega": W2 * (1 + 1e-12), "theta_dot_0": 0.0}
    worst = scale = 0.0
    with Probe(fmu, values) as probe:
        for k in range(1, 201):
            t = k * PERIOD * 0.5
            probe.advance(t)
            x = probe.state()["x"]
            ref = F0 / (2 * W2 * W2) * (math.sin(W2 * t) - W2 * t * math.cos(W2 * t))
            worst, scale = max(worst, abs(x - ref)), max(scale, abs(ref))
    # the exact detuned solution differs from resonance by about (detuning * w t) of the amplitude
    allowed = 1e-12 * W2 * 100 * PERIOD + 1e-12
    return _verdict(worst / scale < allowed, f"Omega = w2 (1 + 1e-12): max |x - resonance form| = "
                                             f"{worst / scale:.1e} of max|x| (detuning effect {allowed:.1e})")


def grazing(fmu, quick=False):
    """Contacts at approach speed 1e-12 m/s (found and applied) and exactly 0 (not an impact)."""
    d = 0.1
    R = 1e-12 / W2
    values = {"mu": 0.1, "FR": 5.0, "d": d, "e": 0.5, "theta_0": d - R, "theta_dot_0": 0.0}
    with Probe(fmu, values) as probe:
        probe.set("F", W2 * W2 * d)  # equilibrium at the stop: reaches it at 1e-12 m/s, zero acceleration
        probe.advance(10.0)
        hit = probe.get("impacts")
        first_v = probe.get("impact[1].v_rel_before")
    touch = {"mu": 0.1, "FR": 5.0, "d": d, "e": 0.5, "theta_0": d, "theta_dot_0": 0.0}
    with Probe(fmu, touch) as probe:
        probe.advance(5 * PERIOD + 0.123)
        touches = probe.get("impacts")
    ok = hit >= 1 and abs(first_v + 1e-12) < 1e-15 and touches == 0
    return _verdict(ok, f"1e-12 m/s contact inside one 10 s step: {hit} impacts (first v_rel {first_v:.3e} m/s); "
                        f"exact zero-speed touches over 5 periods: {touches} impacts")


def chatter_and_sticking(fmu, quick=False):
    """Complete chatter and long sticking for e in {0, 1e-3, 0.2}: a held primary pressing the particle."""
    out, ok = [], True
    for e in (0.0, 1e-3, 0.2):
        X0, V0 = 0.15, 0.3
        values = {"mu": 1e-6, "FR": 5.0, "d": 0.1, "e": e, "theta_0": X0, "alpha_0": (X0 - 0.1) * 25.0,
                  "alpha_dot_0": V0 * 25.0, "theta_dot_0": 0.0}
        with Probe(fmu, values) as probe:
            probe.set("F", W2 * W2 * X0)
            t0 = time.process_time()
            for k in range(1, 101):
                probe.advance(k * 0.5)  # 50 s, almost all of it riding the stop
            contact, impacts = probe.get("contact"), probe.get("impacts")
            s = probe.state()
            cpu = time.process_time() - t0
        pen = (abs(s["z"]) - 0.1) / 0.1
        ok &= contact == 1 and pen <= 1e-14
        out.append(f"e={e:g}: {impacts} impacts then riding (contact {contact}), penetration {pen:.0e}, {cpu:.2f} s")
    return _verdict(ok, "; ".join(out))


def elastic_long(fmu, quick=False):
    """e = 1 over 10^5 impacts: energy conserved (the motion is chaotic; only the invariant is checked)."""
    target = 4000
    with Probe(fmu, {**FREE, "e": 1.0}) as probe:
        e0 = probe.state()["energy"]
        t = 0.0
        while probe.get("impacts") < target:
            t += 10 * PERIOD
            probe.advance(t)
        s = probe.state()
        n = probe.get("impacts")
    drift = abs(s["energy"] - e0) / e0
    return _verdict(drift < 1e-9 and s["energy_dissipated"] == 0.0,
                    f"{n} impacts in {t:.0f} s: relative energy drift {drift:.1e}, dissipated {s['energy_dissipated']}")


def parameter_extremes(fmu, quick=False):
    """d from 1e-9 m to 10 x amplitude, mu from 1e-6 to 10, FR from 0.2 to 1000 (FR < 1 and = 1 too)."""
    amp = 0.7
    sets = [("d", v) for v in (1e-9, 1e-6, 1e-3, 0.1, 10 * amp)] + \
           [("mu", v) for v in (1e-6, 1e-3, 1.0, 10.0)] + \
           [("FR", v) for v in (0.2, 0.9, 1.0, 1.1, 20.0, 1000.0)]
    if quick:
        sets = sets[::3]
    out, ok = [], True
    for name, value in sets:
        values = {**FREE, name: value}
        times = [k * PERIOD / 20 for k in range(1, 3 * 20 + 1)]
        t0 = time.process_time()
        pen, bal, s, impacts = _march(fmu, values, times, d=values["d"])
        cpu = time.process_time() - t0
        good = pen <= 1e-14 and bal <= 1e-9
        ok &= good
        out.append(f"{name}={value:g}: {impacts} imp, pen {max(pen, 0):.0e}, bal {bal:.0e}, {cpu:.2f}s"
                   + ("" if good else " FAIL"))
    return _verdict(ok, "; ".join(out))


def step_sizes(fmu, quick=False):
    """Communication steps from 1e-9 s to 10^3 periods, and 4000 impacts inside one step (a step
    that needs more than damper.MAX_PIECES pieces is refused: tests/test_edges.py)."""
    with Probe(fmu, FREE) as a, Probe(fmu, FREE) as b:
        a.advance(1.0)
        b.advance(1.0)
        for k in range(1000):
            a.do_step(a.t, 1e-9)
        b.advance(a.t)
        tiny = abs(a.read()[0] - b.read()[0])
    with Probe(fmu, FREE) as p:
        p.advance(1000 * PERIOD)  # one step of 10^3 periods
        long_step = p.get("impacts_in_step")
    target = 4000
    span, n_big = 0.0, 0
    while n_big < target:  # a single step long enough for the target count, from the rate seen so far
        span = 200 * PERIOD if not n_big else 1.1 * span * target / n_big
        with Probe(fmu, {**FREE, "e": 1.0, "FR": 20.0}) as p:
            t0 = time.process_time()
            p.advance(span)
            cpu = time.process_time() - t0
            n_big = p.get("impacts_in_step")
            s = p.state()
    ok = tiny < 1e-13 and n_big >= target and abs(s["z"]) <= 0.1 * (1 + 1e-14)
    return _verdict(ok, f"1000 steps of 1e-9 s vs one step: |dtheta| = {tiny:.1e}; one step of 10^3 periods: "
                        f"{long_step} impacts; one step of {span / PERIOD:.0f} periods (FR 20, e = 1): {n_big} "
                        f"impacts in {cpu:.1f} s")


def rough_forces(fmu, quick=False):
    """A force that jumps at every step, and a force of 1e9 N."""
    rng = np.random.default_rng(7)
    jumps = rng.normal(0.0, 2.0, 4000)
    times = [k * 0.005 for k in range(1, 4001)]
    pen, bal, _, impacts = _march(fmu, {**FREE}, times, force=lambda k, t: float(jumps[k]))
    pen2, bal2, s2, impacts2 = _march(fmu, {**FREE}, times[:400], force=lambda k, t: 1e9)
    ok = pen <= 1e-14 and bal <= 1e-9 and pen2 <= 1e-14 and bal2 <= 1e-9 and math.isfinite(s2["energy"])
    return _verdict(ok, f"jumping force: {impacts} impacts, penetration {max(pen, 0):.0e}, balance {bal:.0e}; "
                        f"1e9 N: {impacts2} impacts, balance {bal2:.0e}, energy {s2['energy']:.3g} J")


def long_run_memory(fmu, quick=False):
    """10^6 communication steps with flat memory (peak RSS reported)."""
    n = 100_000 if quick else 1_000_000
    h = PERIOD / 200
    with Probe(fmu, FREE) as p:
        rss = []
        t0 = time.process_time()
        for k in range(1, n + 1):
            p.do_step(p.t, h)
            if k % (n // 10) == 0:
                rss.append(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
        cpu = time.process_time() - t0
    growth = rss[-1] - rss[0]
    return _verdict(growth < 20, f"{n} steps in {cpu:.1f} s CPU ({cpu / n * 1e6:.1f} us/step, FMU2Slave loop): "
                                 f"peak RSS {rss[0]:.0f} MB after a tenth, {rss[-1]:.0f} MB at the end")


def bad_input(fmu, quick=False):
    """NaN/inf input, NaN/negative/zero parameters, e > 1, a step back, a fixed parameter after init.
    Each provokes fmi2Fatal, so each runs in a child process (pidamper.running.isolated): this host
    process survives and goes on using the FMU."""
    from ..running import isolated

    found = []
    for name, value in (("M", float("nan")), ("L2", -1.0), ("d", 0.0), ("e", 1.2), ("g", float("inf"))):
        text = isolated.call("pidamper.benchmarks.fatal_checks:bad_parameter", str(fmu), name, value)
        found.append("ok" if text and f"{name} = " in text else f"{name}={value}: {text}")
    for value in (float("nan"), float("inf")):
        result = isolated.call("pidamper.benchmarks.fatal_checks:bad_input", str(fmu), value)
        found.append("ok" if result["error"] and "F = " in result["error"] else f"F={value}: {result}")
    for action in ("back", "mismatch", "fixed"):
        refused = isolated.call("pidamper.benchmarks.fatal_checks:host_misuse", str(fmu), action)
        found.append("ok" if refused else f"{action}: accepted")
    with Probe(fmu, FREE) as p:  # and this process still runs the FMU
        p.advance(1.0)
        alive = p.get("impacts") > 0
    ok = all(f == "ok" for f in found) and alive
    return _verdict(ok, f"{found.count('ok')} of {len(found)} refused with a message naming the value; "
                        "the host process survived and still runs the FMU" + ("" if ok else f": {found}"))


def sensitive_twins(fmu, quick=False):
    """Near-grazing and e = 1 are sensitive: a twin perturbed by 1e-12 agrees in statistics."""
    out, ok = [], True
    for label, values, periods in (("near-grazing", {"mu": 0.1, "FR": 2.0, "d": 0.1, "e": 0.9,
                                                     "theta_dot_0": 0.1 * (1 + 1e-6) * W2}, 40),
                                   ("e = 1", {**FREE, "e": 1.0}, 40)):
        stats = []
        for eps in (0.0, 1e-12):
            v = {**values, "theta_dot_0": values["theta_dot_0"] * (1 + eps)}
            times = [k * PERIOD / 50 for k in range(1, periods * 50 + 1)]
            with Probe(fmu, v) as p:
                peaks, energy = [], []
                for k, t in enumerate(times):
                    p.advance(t)
                    peaks.append(abs(p.read()[0]))
                    energy.append(p.state()["energy_dissipated"])
                n = p.get("impacts")
            window = np.array(peaks).reshape(periods, 50).max(axis=1)
            stats.append((window, n, np.array(energy)[49::50]))
        (w1, n1, e1), (w2, n2, e2) = stats
        peak_diff = np.max(np.abs(w1 - w2)) / np.max(w1)
        diss = np.max(np.abs(e1 - e2)) / max(np.max(np.abs(e1)), 1e-300) if np.max(np.abs(e1)) > 0 else 0.0
        good = peak_diff < 0.25 and abs(n1 - n2) <= max(5, 0.25 * n1)
        ok &= good
        out.append(f"{label}: window-peak difference {peak_diff:.1e}, impacts {n1} vs {n2}, "
                   f"dissipated-per-period difference {diss:.1e}")
    return _verdict(ok, "; ".join(out))


CASES = {f.__name__: f for f in (resonance_no_contact, resonance_with_damper, near_resonance, grazing,
                                chatter_and_sticking, elastic_long, parameter_extremes, step_sizes, rough_forces,
                                long_run_memory, bad_input, sensitive_twins)}


def main(argv=None):
    parser = argparse.ArgumentParser(prog="pidamper stress", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--case", action="append", choices=sorted(CASES), help="run only these (repeatable)")
    parser.add_argument("--quick", action="store_true", help="smaller sizes (the CI subset)")
    args = parser.parse_args(argv)
    fmu = find_fmu()
    failed = 0
    print(f"{'case':24s} {'result':6s} {'CPU s':>7s}  detail")
    for name, case in CASES.items():
        if args.case and name not in args.case:
            continue
        t0 = time.process_time()
        try:
            ok, detail = case(fmu, args.quick)
        except Exception as err:  # noqa: BLE001  an exception is a failed case, shown as such
            ok, detail = False, f"{type(err).__name__}: {err}"
        failed += not ok
        print(f"{name:24s} {'pass' if ok else 'FAIL':6s} {time.process_time() - t0:7.2f}  {detail}", flush=True)
    return 1 if failed else 0
