"""The materials' page (issue 25): restitution from the impact (Equation 18 and the laws it comes
from) and the impact forces and pressures.  Writes docs/contact/README.md and its figures (this
module holds the page's prose: one source).

    python -m pidamper.benchmarks.contact [--out docs/contact]

Runs the physics core the FMUs ship (pidamper_physics.Damper: the FMU steps it bit for bit, and the
core hears every impact, where the FMU records 16 per step) on the shipped scenes resonance,
steel-on-steel, steel-on-aluminium and free-decay; the cost row times the FMU under fmpy.
"""
import argparse
import math
import time
from pathlib import Path

import numpy as np

from pidamper_physics import Damper, Params
from pidamper_physics.impact import CONSTANT, JOHNSON, LAWS, PRINTED, SHORT_CONTACT, THORNTON, check_contact

from .. import CoreStepper, run
from ..machine import describe
from ..measures import damping_ratio
from ..running.fmu import find_fmu
from ..scenes.scene import load

PAIRS = ("steel-on-steel", "steel-on-aluminium")
MATERIAL_KEYS = ("S_y", "E1", "nu1", "E2", "nu2", "R", "e_max")
SPEEDS = np.logspace(-4, 0.5, 200)  # approach speeds [m/s] of the e(v) figure


def materials(scene):
    """The scene's materials (its parameters' MATERIAL_KEYS)."""
    return {k: scene.parameters[k] for k in MATERIAL_KEYS}


def reduced_mass(values):
    """m* of the pendulum system's impact: M mu / (1 + mu)."""
    M, mu = values.get("M", 1.0), values["mu"]
    return M * mu / (1.0 + mu)


def law_curves(pair, m):
    """{law: e(v) on SPEEDS} of a pair for reduced mass m [kg]."""
    out = {}
    for law in (PRINTED, JOHNSON, THORNTON):
        contact = check_contact(restitution=law, **materials(load(pair)))
        out[law] = np.array([contact.restitution(v, m, 0.0) for v in SPEEDS])
    return out


def impacts_of(values, stop_time):
    """Every impact of a core run: rows (t, |v_rel|, e, peak force, peak pressure, duration, plastic),
    the largest |theta| over its last 5 periods, and the core."""
    core = Damper(Params(**{k: v for k, v in values.items() if k in Params.NAMES}),
                  values.get("theta_0", 0.0), values.get("theta_dot_0", 0.0))
    rows = []
    core.on_impact = lambda t, side, before, after, loss: rows.append((t, abs(before), *core.contacts.hit))
    w2 = core.p.w2
    times = np.linspace(stop_time - 10 * math.pi / w2, stop_time, 2001)
    core.advance(times[0])
    tail = np.array(core.dense(times))
    return np.array(rows, dtype=float), float(np.abs(tail[:, 0]).max() / core.p.L2), core


def scene_runs():
    """The resonance runs: constant e = 0.2 against each law, per pair (materials as the pair's)."""
    base = load("resonance")
    stop = base.stop_time
    out = {}
    for pair in PAIRS:
        scene = load(pair)
        f = scene.forcing  # the scene's harmonic, as the core's built-in force (the FMU has it too)
        drive = {"F0": f["F0"], "Omega": f["Omega_ratio"] * scene.w2, "phi": f["phi"]}
        for law in (CONSTANT, PRINTED, JOHNSON, THORNTON):
            values = {**scene.start_values, **drive, "restitution": law, "e": 0.2}
            out[pair, law] = impacts_of(values, stop)
    return out, stop


def free_decay_damping():
    """The paper's damping ratio (log decrement, 'exact' average of five cycles) of the free-decay
    scene with the constant e = 0.2 and with each law (a 100 g steel sphere, R = 14.5 mm)."""
    scene = load("free-decay")
    period = 2 * math.pi / scene.w2
    R = (3 * 0.1 / (4 * math.pi * 7850)) ** (1 / 3)
    out = {}
    for pair in PAIRS:
        for law in (CONSTANT, PRINTED, JOHNSON, THORNTON):
            values = {**scene.start_values, **materials(load(pair)), "R": R, "restitution": law}
            out[pair, law] = damping_ratio(CoreStepper(values), period)[0]["exact"]
    return out, R


def fmu_cost(runs=5):
    """(median CPU s per simulated s of the resonance scene's FMU under fmpy: without materials,
    with them and the constant e, with Eq. 18)."""
    scene = load("steel-on-steel")
    path = find_fmu()
    rows = []
    for extra in ({"R": 0.0, "restitution": 0}, {"restitution": 0}, {}):
        values = {**scene.start_values, **extra}
        times = []
        for _ in range(runs):
            t0 = time.process_time()
            run(values, scene.make_forcing(), stop_time=scene.stop_time, output_interval=0.01, fmu=path)
            times.append(time.process_time() - t0)
        rows.append(float(np.median(times)) / scene.stop_time)
    return rows


# ---- the page ------------------------------------------------------------------------------------

def figure_e(path, m):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    styles = {PRINTED: "-", JOHNSON: "--", THORNTON: ":"}
    for pair, colour in zip(PAIRS, ("tab:blue", "tab:orange")):
        for law, e in law_curves(pair, m).items():
            ax.semilogx(SPEEDS, e, styles[law], color=colour, label=f"{pair}, {LAWS[law]}")
    ax.axhline(0.2, color="grey", lw=0.8, label="constant e = 0.2 (resonance scene)")
    ax.set_xlabel("approach speed v [m/s]")
    ax.set_ylabel("e (at most e_max = 0.95)")
    ax.set_title(f"restitution against impact speed, m* = {m * 1e3:.1f} g, R = 8.4 mm")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def figure_forces(path, runs):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    for ax, pair in zip(axes, PAIRS):
        forces = [runs[pair, law][0][:, 3] for law in (CONSTANT, PRINTED, THORNTON)]
        top = max(f.max() for f in forces)
        low = min(f[f > 0].min() for f in forces)
        bins = np.logspace(math.log10(low) - 0.1, math.log10(top) + 0.1, 40)
        for f, law in zip(forces, (CONSTANT, PRINTED, THORNTON)):
            label = "constant e = 0.2" if law == CONSTANT else LAWS[law]
            ax.hist(f[f > 0], bins=bins, histtype="step", label=f"{label} ({len(f)} impacts)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("peak contact force per impact [N]")
        ax.set_title(pair, fontsize=9)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("impacts")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _stats(rows):
    e, force, pressure, duration, plastic = rows[:, 2], rows[:, 3], rows[:, 4], rows[:, 5], rows[:, 6]
    return (len(rows), np.percentile(e, 5), np.percentile(e, 95), plastic.mean(), np.percentile(force, 50),
            np.percentile(force, 99), force.max(), pressure.max(), duration.max())


def write(out, runs, stop, damping, R_decay, cost, t_wall):
    m = reduced_mass(load("steel-on-steel").start_values)
    shift = max(abs(runs[pair, law][1] / runs[pair, CONSTANT][1] - 1.0) for pair in PAIRS
                for law in (PRINTED, JOHNSON, THORNTON))
    lines = [
        "# Restitution from the materials, and the impact forces",
        "",
        f"Generated by `python -m pidamper.benchmarks.contact` on {describe('numpy', 'fmpy')} in {t_wall:.0f} s.",
        "The impacts are the physics core's (`Damper`, which every particle FMU steps bit for bit): it hears",
        "every impact, where an FMU records 16 per communication step.",
        "",
        "## The laws (parameter `restitution`)",
        "",
        "The particle FMUs (`PendulumImpactDamper`, `DampedShearBuilding<N>`, `PendulumImpactDamperUnit`) take",
        "the materials of the particle and its stop: `S_y` (dynamic yield strength of the softer body),",
        "`E1`, `nu1` (particle), `E2`, `nu2` (stop), `R` (radius of the particle's contact surface on a flat",
        "stop) and `e_max` (default 0.95).  At each impact `e = min(e_max, law(v, m*))` with `v` the normal",
        "approach speed and `m*` the impact's reduced mass (the particle against its primary, floor or",
        "`M_s`).  `restitution = 0` keeps the constant `e` (the default: today's runs, bit for bit).",
        "",
        "- **1, Equation 18 as printed**: `e = 3.1 S_y^(5/8) E*^(-1/2) v^(-1/4) rho^(-1/8)` with the paper's",
        "  `E* = E / (1 - nu^2)` (one material; for two we use the harmonic mean of the two plane-strain",
        "  moduli, `2 / ((1 - nu1^2)/E1 + (1 - nu2^2)/E2)`, which is the paper's for equal materials) and",
        "  `rho = 3 m* / (4 pi R^3)`: the density of the sphere the law was derived for (a solid sphere of",
        "  the particle's material on a heavy stop gives the material's density; a pendulum bob of another",
        "  shape has its contact radius `R` and its mass).",
        "- **2, Johnson (1985, Contact Mechanics, 11.5)**, the source of the print's exponents: fully",
        "  plastic loading at the dynamic yield pressure `p_d`, elastic (Hertz) unloading:",
        "  `e^2 = (3 pi^(5/4) 4^(3/4) / 10) (p_d / E*) (m* v^2 / (2 p_d R^3))^(-1/4)`, with Hertz's",
        "  two-body `1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2` and `p_d = 3 S_y` (the mean pressure of a fully",
        "  plastic indentation).  For a solid sphere this is `e = 1.72 (p_d/E*)^(1/2) (rho v^2/p_d)^(-1/8)`.",
        "- **3, Thornton (1997)**: Hertz until the peak pressure reaches `p_y = 1.6 S_y` (first yield,",
        "  Johnson 6.2), then the pressure is held there while the contact grows",
        "  (`F = F_y + pi p_y R (delta - delta_y)`), and the unloading is Hertzian from a flattened radius",
        "  `R_p`; its `e` is 1 below the yield speed and about `1.185 (V_y/v)^(1/4)` far above it.",
        "",
        "**The print against its source.**  The print has Johnson's exponents but differs in more than the",
        "constant: (i) its `E*` is one material's `E / (1 - nu^2)`, twice Hertz's two-body modulus of equal",
        "materials (Johnson's); (ii) it has the yield strength `S_y` where Johnson has the dynamic yield",
        "pressure `p_d` (about 3 `S_y`); (iii) its constant 3.1 is Johnson's 1.72 with both converted",
        "(`1.72 sqrt(2) (p_d/S_y)^(5/8)` = 3.1 for `p_d` = 1.48 `S_y`; with `p_d = 3 S_y` it would be 4.8).",
        "So the print gives a lower `e` than Johnson's law (0.51 against 0.79 for a 10 mm steel sphere at",
        "0.5 m/s on steel) and is `restitution = 1`; Johnson's own law is `restitution = 2`.  Both exceed 1",
        "at low speed, where the impact is elastic: `e_max` binds there, and keeps chatter ending in",
        "sticking.",
        "",
        "## Each impact's force, pressure and duration",
        "",
        "One contact law for every restitution law (so a constant-`e` run and a material run report",
        "comparable forces): Hertz (`F = (4/3) E* sqrt(R) delta^(3/2)`) while the peak pressure",
        "`p0 = (6 F E*^2 / (pi^3 R^2))^(1/3)` stays below `1.6 S_y`, with the contact time",
        "`T_c = 2.868 (m*^2 / (R E*^2 v))^(1/5)`; above it Thornton's elastic-plastic law, the impact",
        "flagged plastic, its peak pressure the limit `1.6 S_y` (the contact area grows instead) and its",
        "duration the elastic loading, the plastic stroke and the elastic unloading in closed form.  The",
        "FMU outputs `impact_force_peak` and `contact_pressure_peak` (largest over the step, 0 without",
        "impact) and `impacts_plastic` (count); each recorded impact has `e`, `force_peak`,",
        "`pressure_peak`, `duration` and `plastic`, in the FMU, the MCAP (`/damper/impacts`) and Rerun",
        "(the events log and a peak-force plot).  A contact longer than "
        f"{SHORT_CONTACT:.0%} of the primary's period (the",
        "unit: of its particle's) is warned about once through the FMI logger: the instantaneous impact",
        "then misplaces the impulse.  Checked (tests/test_contact.py) against `solve_ivp` integrating",
        "`m* delta'' = -F(delta)` (rtol 1e-12) over velocity sweeps: peak force, duration and rebound to",
        "1e-6, elastic and elastic-plastic.",
        "",
        "Mild steel yields at very low speed: a 20 g steel sphere (R = 8.4 mm) on mild steel (S_y 300 MPa)",
        f"starts to yield at {check_contact(3, **materials(load('steel-on-steel'))).yield_speed(m) * 1e3:.2f} mm/s, "
        f"on aluminium 5083-O at "
        f"{check_contact(3, **materials(load('steel-on-aluminium'))).yield_speed(m) * 1e3:.2f} mm/s: nearly every impact",
        "of the damper is plastic (local denting of the stop, the wear the paper asks about).",
        "",
        "![e against v](e-vs-v.png)",
        "",
        "## The resonance scene with the materials",
        "",
        f"The paper's forced case (`resonance`: mu = 0.02, FR = 5, d = 0.1 m, {stop:.1f} s from rest) with",
        "the constant `e = 0.2` it uses and with each law, for a 20 g steel sphere (R = 8.4 mm) on a steel",
        "and on an aluminium stop (the scenes `steel-on-steel`, `steel-on-aluminium`: `pidamper run",
        "steel-on-steel`).  Steady |theta|: the largest over the last 5 periods.",
        "",
        "| pair | law | impacts | e (5-95 %) | plastic | median force [N] | 99th pct [N] | largest [N] | "
        "largest pressure [MPa] | longest contact [ms] | steady max abs(theta) [rad] |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for pair in PAIRS:
        for law in (CONSTANT, PRINTED, JOHNSON, THORNTON):
            rows, steady, _ = runs[pair, law]
            n, e5, e95, share, f50, f99, fmax, pmax, tmax = _stats(rows)
            name = "constant e = 0.2" if law == CONSTANT else LAWS[law]
            lines.append(f"| {pair} | {name} | {n} | {e5:.2f}-{e95:.2f} | {share:.0%} | {f50:.3g} | {f99:.3g} | {fmax:.3g} | "
                         f"{pmax / 1e6:.0f} | {tmax * 1e3:.3f} | {steady:.4f} |")
    lines += [
        "",
        "With the materials the impacts are far more elastic than the constant `e = 0.2` the paper",
        "assumed (the `e` column; the constant-e rows' 0 is the plastic impact that ends each chatter),",
        "so the particle rattles: Eq. 18 and Thornton's law give ten times as many impacts, most of them",
        "tiny (chatter at `e_max` before the particle sticks), and the largest forces rise with the",
        f"rebounds.  The steady amplitude moves by at most {shift:.0%} (the damper works by momentum",
        "exchange as much as by dissipation, as the paper found for `e`).  The core runs the scene's",
        "harmonic as its built-in force; `pidamper run` feeds the same harmonic through the FMU's input,",
        "so its counts differ by a few impacts (the motion is that sensitive).",
        "The peak pressure of a plastic impact is the limit `1.6 S_y` by construction: what grows with the",
        "speed is the dent (the contact radius) and the force.",
        "",
        "![peak forces](forces.png)",
        "",
        "## The damping ratio",
        "",
        "The paper's measure: the average damping ratio from the log decrement of five cycles of free",
        f"vibration (the scene `free-decay`: mu = 0.1, FR = 5, d = 0.1 m, a 100 g steel sphere, R = {R_decay * 1e3:.1f} mm).",
        "",
        "| pair | constant e = 0.2 | " + " | ".join(LAWS[law] for law in (PRINTED, JOHNSON, THORNTON)) + " |",
        "|---|---:|---:|---:|---:|",
    ]
    for pair in PAIRS:
        lines.append(f"| {pair} | " + " | ".join(f"{damping[pair, law]:.4f}" for law in
                                                  (CONSTANT, PRINTED, JOHNSON, THORNTON)) + " |")
    lines += [
        "",
        "## Cost",
        "",
        "CPU per simulated second of the `steel-on-steel` scene's FMU under fmpy (`pidamper.run`), median of",
        f"5 runs: without materials (`R = 0`) {cost[0]:.3f} s/s; with them and the constant `e` (the same",
        f"motion, every impact's contact computed) {cost[1]:.3f} s/s; with Eq. 18 {cost[2]:.3f} s/s (more",
        "impacts: the motion differs).",
        "",
    ]
    (out / "README.md").write_text("\n".join(lines))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="docs/contact", help="folder of the page (default docs/contact)")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    runs, stop = scene_runs()
    damping, R_decay = free_decay_damping()
    cost = fmu_cost()
    figure_e(out / "e-vs-v.png", reduced_mass(load("steel-on-steel").start_values))
    figure_forces(out / "forces.png", runs)
    write(out, runs, stop, damping, R_decay, cost, time.perf_counter() - t0)
    print(f"wrote {out / 'README.md'}")


if __name__ == "__main__":
    main()
