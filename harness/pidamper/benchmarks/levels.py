"""Speed against error across the fidelity levels (`pidamper bench --levels`).

The reference is the nonlinear level (the double pendulum at any angle, with the scene's
dashpots); each cheaper level runs the same scene with what it can model:
linear (the paper: fixed pivots, no dashpots), damped (+ dashpots), coupled (+ the particle
hung from the moving primary, small angles).  The family: FR 2, mu 0.1, e 0.5, zeta_s 0.02,
zeta_p 0.02, the primary started at amplitude A (theta_dot_0 = A w2) with the particle at
rest, the clearance scaled with it (d = 0.15 A m, so every amplitude sees impacts), over
3 primary periods sampled every 0.01 s.  Measures: the largest deviation of theta from the
nonlinear level relative to its peak, and the relative error of the energy taken by impacts
and dashpots.  Cost: CPU per 0.01 s step of the physics core, its CPU per impact (what the run
costs beyond the same run with the stops out of reach, per impact), and CPU per step
of the FMU under fmpy.simulate_fmu (the step loop only: from the first to the last
step_finished callback, so unpacking and instantiating the FMU are left out; it includes
fmpy's input and recording of the run's outputs).
"""
import csv
import math
import time
from pathlib import Path

import numpy as np

from pidamper_physics import Damper, Params
from pidamper_physics.params import LEVELS

from ..running.fmu import find_fmu
from ..running.simulation import run as run_fmu
from ..machine import describe

W2 = math.sqrt(9.81)
AMPLITUDES = (0.01, 0.03, 0.1, 0.2, 0.4, 0.7, 1.0)
H = 0.01
PERIODS = 3


def scene(level, amplitude, stops=True):
    """(parameters, initial angular velocities) of the family's member at `amplitude` [rad];
    stops=False moves the stops out of reach (the same motion without impacts)."""
    index = LEVELS.index(level)
    zeta = 0.02 if index > 0 else 0.0
    params = {"FR": 2.0, "mu": 0.1, "e": 0.5, "d": 0.15 * amplitude if stops else 100.0, "fidelity": index,
              "zeta_s": zeta, "zeta_p": zeta}
    td = amplitude * W2
    return params, {"theta_dot_0": td, "alpha_dot_0": -td * params["FR"] ** 2 if index >= 2 else 0.0}  # L2/L1 = FR^2


def _damper(level, amplitude, stops=True):
    params, start = scene(level, amplitude, stops)
    return Damper(Params(**params), theta_dot0=start["theta_dot_0"], alpha_dot0=start["alpha_dot_0"])


def fmu_step_cost(level, amplitude, fmu):
    """CPU seconds per communication step of the FMU under fmpy, the step loop only."""
    params, start = scene(level, amplitude)
    stamps = []
    result = run_fmu({**params, **start}, stop_time=PERIODS * 2 * math.pi / W2, output_interval=H, fmu=fmu,
                     step_finished=lambda t, recorder: stamps.append(time.process_time()) or True)
    return (stamps[-1] - stamps[0]) / (len(stamps) - 1), int(result.data["impacts"][-1])


def run(level, amplitude, stops=True):
    """theta samples, energy lost, impacts, CPU seconds, steps of one run."""
    dm = _damper(level, amplitude, stops)
    steps = int(round(PERIODS * 2 * math.pi / W2 / H))
    theta = np.empty(steps + 1)
    theta[0] = dm.angles()[0]
    started = time.process_time()
    for k in range(1, steps + 1):
        dm.advance(k * H)
        theta[k] = dm.angles()[0]
    cpu = time.process_time() - started
    return theta, dm.dissipated + dm.viscous, dm.impacts, cpu, steps


def measure(amplitudes=AMPLITUDES, repeats=3, fmu=None):
    fmu = find_fmu(fmu)
    rows = []
    for a in amplitudes:
        ref_theta, ref_lost, *_ = run("nonlinear", a)
        for level in LEVELS:
            best = free = None
            for _ in range(repeats):
                theta, lost, impacts, cpu, steps = run(level, a)
                best = cpu if best is None else min(best, cpu)
                cpu_free = run(level, a, stops=False)[3]
                free = cpu_free if free is None else min(free, cpu_free)
            costs = [fmu_step_cost(level, a, fmu) for _ in range(repeats)]
            if any(n != impacts for _, n in costs):
                raise RuntimeError(f"{level} at {a} rad: the FMU made {costs[0][1]} impacts, the core {impacts}")
            rows.append({"level": level, "amplitude_rad": a,
                         "theta_error": float(np.max(np.abs(theta - ref_theta)) / np.max(np.abs(ref_theta))),
                         "energy_lost_error": abs(lost - ref_lost) / ref_lost if ref_lost else 0.0,
                         "impacts": impacts, "us_per_step": 1e6 * best / steps,
                         "us_per_impact": 1e6 * (best - free) / impacts if impacts else float("nan"),
                         "fmpy_us_per_step": 1e6 * min(c for c, _ in costs)})
    return rows


def write(rows, out, repeats=3):
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "levels.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    _plot(rows, out / "levels-error.png")
    lines = ["# Model error of each fidelity level against `nonlinear`, and its cost", "",
             f"Machine: {describe('fmpy')}. Command: `pidamper bench --levels --repeats {repeats}` (module `pidamper.benchmarks.levels`; "
             "the scene family is described in its docstring).", "",
             "CPU columns: best of the repeats, process time; core = the physics alone "
             "(`Damper.advance`), fmpy = the FMU's step loop under `fmpy.simulate_fmu` with its outputs "
             "recorded (unpacking and instantiation left out). Per impact: the run's CPU beyond the same run "
             "with the stops out of reach, per impact; at `nonlinear` the run without stops also takes other "
             "integrator steps (larger swings, more steps), so there the difference is not the impacts' alone "
             "and can come out negative.", "",
             "| level | amplitude [rad] | theta error | energy-lost error | impacts | core us / step | "
             "core us per impact (over the run without stops) | fmpy us / step |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['level']} | {r['amplitude_rad']:g} | {r['theta_error']:.2g} | "
                     f"{r['energy_lost_error']:.2g} | {r['impacts']} | {r['us_per_step']:.1f} | "
                     f"{r['us_per_impact']:.0f} | {r['fmpy_us_per_step']:.1f} |")
    lines += ["", "![error against amplitude](levels-error.png)", ""]
    (out / "README.md").write_text("\n".join(lines))


def _plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for level in LEVELS[:-1]:
        sel = [r for r in rows if r["level"] == level]
        ax.loglog([r["amplitude_rad"] for r in sel], [max(r["theta_error"], 1e-16) for r in sel], "o-", label=level)
    ax.set_xlabel("primary amplitude A [rad] (clearance 0.15 A m)")
    ax.set_ylabel("max |theta - theta_nonlinear| / max |theta_nonlinear|")
    ax.set_title("Model error against the nonlinear level, 3 periods")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
