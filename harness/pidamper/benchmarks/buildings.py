"""The damper on a shear building: accuracy against independent oracles, cost, and the scenes with and
without the damper.  Writes docs/buildings/README.md (this module holds its prose: one source).

    python -m pidamper.benchmarks.buildings [--out docs/buildings]
"""
import argparse
import math
import time
from pathlib import Path

import numpy as np
import scipy.linalg

from pidamper_physics import Damper, Params
from pidamper_physics.building import ShearBuilding

from ..scenes import scene as scene_mod
from ..oracles.building_reference import simulate
from ..machine import describe
from ..measures import building_peaks
from ..running.simulation import run

MASSES = [1.0e5, 1.2e5, 0.9e5, 1.1e5, 1.0e5, 0.8e5, 1.3e5, 1.0e5, 0.9e5, 1.2e5]
STIFF = [2.0e8, 1.6e8, 1.2e8, 1.8e8, 1.5e8, 1.1e8, 1.9e8, 1.4e8, 1.3e8, 1.7e8]


def expm_error(n, zeta, t_end=10.0):
    """Largest error of the bare building's floors (relative to their largest value) over 200 output
    times against exp(A t) of its state matrix, held F on the top floor and held a_g."""
    p = Params(storeys=n, floor_m=MASSES[:n], storey_k=STIFF[:n], mu=0.0, d=100.0, fidelity=1 if zeta else 0,
               zeta_s=zeta)
    rng = np.random.default_rng(n)
    x0, v0 = rng.normal(0, 0.01, n), rng.normal(0, 0.1, n)
    core = Damper(p, floors0=(list(x0), list(v0)))
    F, ag = 2.0e5, 0.8
    b = ShearBuilding(MASSES[:n], STIFF[:n], zeta)
    Mi = np.diag(1.0 / np.array(MASSES[:n]))
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ np.array(b.K), -Mi @ np.array(b.C)]])
    load = np.zeros(2 * n)
    load[n:] = -ag
    load[2 * n - 1] += F / MASSES[n - 1]
    z0 = np.concatenate([x0, v0])
    worst = 0.0
    for t in np.linspace(t_end / 200, t_end, 200):
        core.advance(t, F, ag)
        E = scipy.linalg.expm(A * t)
        want = E @ z0 + np.linalg.solve(A, (E - np.eye(2 * n)) @ load)
        xs, vs = core.floors()
        worst = max(worst, np.abs(np.array(xs + vs) - want).max() / np.abs(want).max())
    return worst


def oracle_errors(n=3, t_end=3.0, h=0.01):
    """(floor error / peak, particle error / d, impacts above 1 mm/s: ours, theirs, largest time
    difference [s]) against the solve_ivp event-driven reference, harmonic a_g at w_1 held per step."""
    v = dict(mu=0.05, FR=1.0, d=0.004, e=0.5, zeta_s=0.02, zeta_p=0.01)
    p = Params(storeys=n, floor_m=MASSES[:n], storey_k=STIFF[:n], fidelity=1, **v)
    w = p.building.w_1
    times = np.arange(1, int(round(t_end / h)) + 1) * h
    ref = simulate(MASSES[:n], STIFF[:n], v["zeta_s"], v["mu"], v["FR"], v["d"], v["e"], v["zeta_p"], times[-1],
                   a_g=lambda t: 2.0 * math.sin(w * h * math.floor(t / h + 1e-9)), sample_times=times)
    core = Damper(p)
    impacts = []
    core.on_impact = lambda t, side, before, after, loss: impacts.append((t, before))
    rows = []
    for t in times:
        core.advance(t, 0.0, 2.0 * math.sin(w * (t - h)))
        rows.append(core.floors()[0] + [core.y - core.x])
    rows = np.array(rows)
    ours = [t for t, w_ in impacts if abs(w_) > 1e-3]
    theirs = [t for t, _, w_, _, _ in ref["impacts"] if abs(w_) > 1e-3]
    dt = np.abs(np.array(ours) - np.array(theirs)).max() if len(ours) == len(theirs) else math.nan
    return (np.abs(rows[:, :n] - ref["x"]).max() / np.abs(ref["x"]).max(),
            np.abs(rows[:, n] - ref["r"]).max() / v["d"], len(ours), len(theirs), dt, core.impacts)


def coupled_mapping(t_end=20.0, h=0.01):
    """Largest state difference [m, m/s, relative to 1 + |v|] between the coupled level and the
    1-storey building it maps to, and the impacts."""
    g, M, mu, L2, FR, d, e, zs, zp = 9.81, 2.0, 0.1, 1.3, 1.0, 0.01, 0.4, 0.02, 0.05
    a = Damper(Params(g=g, M=M, mu=mu, L2=L2, FR=FR, d=d, e=e, fidelity=2, zeta_s=zs, zeta_p=zp), theta_dot0=0.5)
    s = math.sqrt(1.0 + mu)
    b = Damper(Params(g=g, mu=mu, FR=FR / s, d=d, e=e, fidelity=2, zeta_s=zs / s, zeta_p=zp, storeys=1,
                      floor_m=[M], storey_k=[M * (1.0 + mu) * g / L2]), floors0=([0.0], [0.5 * L2]))
    worst = 0.0
    for k in range(1, int(round(t_end / h)) + 1):
        t = k * h
        f, ag = 0.3 * math.sin(2.0 * t), 0.2 * math.cos(3.1 * t)
        a.advance(t, f, ag)
        b.advance(t, f, ag)
        worst = max(worst, max(abs(p - q) for p, q in zip((a.x, a.v, a.y, a.u), (b.x, b.v, b.y, b.u))) / (1 + abs(a.v)))
    return worst, a.impacts, b.impacts


def core_cost(name):
    """us per 0.005 s step of Damper.advance over a scene's ground motion, and the impacts."""
    sc = scene_mod.load(name)
    values = sc.start_values
    p = Params.from_variables(values)
    signal = sc.make_forcing()
    h = sc.output_interval
    n = int(round(sc.stop_time / h))
    ag = signal.value(np.arange(n + 1) * h)
    best = math.inf
    for _ in range(3):
        core = Damper(p)
        core.bound_work()
        t0 = time.process_time()
        for k in range(1, n + 1):
            core.advance(k * h, 0.0, ag[k - 1])
        best = min(best, time.process_time() - t0)
    return best / n * 1e6, core.impacts


def scene_figures(name):
    """Peaks of one scene run through the FMU with fmpy (every building output recorded)."""
    sc = scene_mod.load(name)
    values = sc.start_values
    n = values["storeys"]
    res = run(values, sc.make_forcing(), stop_time=sc.stop_time, output_interval=sc.output_interval)
    d = res.data
    peaks = building_peaks(d, n)  # the FMU's exact running maxima
    return {"top": np.abs(d[f"floor[{n}].x"]).max(), "drift": peaks["drift_ratio"].max(),
            "shear": np.abs(d["base_shear"]).max(), "acc": peaks["a_abs"][-1], "impacts": int(d["impacts"][-1]),
            "cpu": res.cpu_time / (len(d) - 1) * 1e6}


def _effect(figures):
    """'changes the 3-storey's peak top-floor displacement by +x % and the 10-storey's by +y %'."""
    change = [100.0 * (figures[f"building-{n}"]["top"] / figures[f"building-{n}-bare"]["top"] - 1.0) for n in (3, 10)]
    return (f"changes the 3-storey's peak top-floor displacement by {change[0]:+.0f} % and the 10-storey's by "
            f"{change[1]:+.0f} %")


def report():
    lines = [HEADER.format(machine=describe()), "## Accuracy against independent oracles", "",
             "| check | measured |", "|---|---:|"]
    for n, zeta in ((3, 0.0), (3, 0.05), (10, 0.0), (10, 0.05)):
        lines.append(f"| bare {n}-storey building, zeta_s = {zeta:g}: floors vs `scipy.linalg.expm` (200 times to "
                     f"10 s, held F and a_g), largest error / peak | {expm_error(n, zeta):.1e} |")
    fx, fr, ours, theirs, dt, total = oracle_errors()
    lines += [f"| 3-storey with the particle, a_g = 2 sin(w_1 t) held per 0.01 s step, 3 s ({total} impacts): "
              f"floors vs the solve_ivp event-driven reference (rtol 1e-12), largest error / peak | {fx:.1e} |",
              f"| same: particle relative to its floor, largest error / d | {fr:.1e} |",
              f"| same: impacts above 1 mm/s, ours / the reference's | {ours} / {theirs} |",
              f"| same: largest difference of those impacts' times [s] | {dt:.1e} |"]
    worst, ia, ib = coupled_mapping()
    lines += [f"| 1-storey building vs the `coupled` level it maps to, 20 s ({ia} / {ib} impacts): largest state "
              f"difference / (1 + \\|v\\|) | {worst:.1e} |", "", COST_TEXT,
              "| scene | storeys | core us/step | impacts | FMU under fmpy, every output, us/step |",
              "|---|---:|---:|---:|---:|"]
    figures = {}
    for name in ("building-3", "building-3-bare", "building-10", "building-10-bare"):
        cost, impacts = core_cost(name)
        figures[name] = fig = scene_figures(name)
        lines.append(f"| {name} | {scene_mod.load(name).parameters['storeys']} | {cost:.0f} | {impacts} | "
                     f"{fig['cpu']:.0f} |")
    lines += ["", SCENES_TEXT.format(effect=_effect(figures)), "| scene | peak top-floor x [m] | peak drift ratio | peak base shear [MN] | "
              "peak top-floor absolute acceleration [m/s2] | impacts |", "|---|---:|---:|---:|---:|---:|"]
    for name, fig in figures.items():
        lines.append(f"| {name} | {fig['top']:.4f} | {fig['drift']:.2e} | {fig['shear'] / 1e6:.3f} | "
                     f"{fig['acc']:.2f} | {fig['impacts']} |")
    lines += ["", FOOTER]
    return "\n".join(lines) + "\n"


HEADER = """# The damper on a shear building

`DampedShearBuilding<N>.fmu` (N = 1..10; `storeys = N` in scenes and studies) puts the particle on a
linear shear building: floor masses `floor[k].m` [kg], storey stiffnesses `storey[k].k` [N/m] (storey
k joins floor k-1 to floor k), storey heights `storey[k].h` [m], every mode damped at `zeta_s`
(classical modal damping, from `fidelity` 1 on). The particle
(mass `m = mu` times the building's mass, pendulum frequency `w1 = FR w_1`, `w_1` the bare
building's first natural frequency, `L1 = g / w1^2`) hangs from floor `damper_floor` (0 = the top
floor) and pulls it with `m w1^2 r`, `r = y - x_j`; stops at `r = -+d`. With `x` the floor
displacements relative to the ground:

    M x'' + C x' + K x = -M 1 a_g + e_j (F + m w1^2 r + c_p r'),    m (y'' + a_g) = -m w1^2 r - c_p r'

An impact exchanges momentum between the particle and floor j alone (Newton, restitution `e`); while
the particle rides a stop, floor j carries it (its mass becomes `m_j + m`; the wire force is internal)
until the stop's force `N = m (x_j'' + a_g + w1^2 r)` reaches zero. Between events the motion is the
closed form of the (N+1)-DOF system's complex modes (N-DOF while riding), found once per parameter
set by a plain-Python eigensolver (`pidamper_physics/eigen.py`: balanced Hessenberg QR, inverse
iteration); impacts, chatter, sticking and release are located exactly inside `fmi2DoStep` as at the
pendulum levels. `fidelity` 0 has no dashpots, 1 and 2 are the same model here (modal damping and the
particle's dashpot `c_p = 2 zeta_p m w1`), 3 (`nonlinear`) is refused.

Outputs: `floor[k].x` (relative to the ground), `floor[k].a` (absolute), `storey[k].drift`,
`storey[k].drift_ratio`, `base_shear` (the building's force on the ground, `sum(K x + C x')`), and
the exact running maxima `storey[k].drift_ratio_max`, `floor[k].v_abs_max`, `floor[k].a_abs_max`
(located inside `fmi2DoStep`, not sampled: [Buildings](../guide/buildings.md)). `x` is
the damper floor's displacement, `y` the particle's; `theta = x / L2` with `L2 = g / w_1^2` (the
pendulum of the building's first frequency) and `alpha = (y - x) / L1` (the wire's angle). The energy
is the floors' kinetic and strain energy plus the particle's; the balance
`E(0) + work_in - E = energy_dissipated + energy_viscous` closes with the building's modal dashpots.
`F` acts on the damper floor; the building starts at rest.
Scenes: `building-3`, `building-10` and their `-bare` twins (`mu = 0`).

A 1-storey building reproduces the `coupled` level: floor mass `M`, storey stiffness
`M (1 + mu) g / L2`, `FR / sqrt(1 + mu)` and `zeta_s / sqrt(1 + mu)` (the coupled primary carries the
particle's weight, so its pendulum's stiffness is `(M + m) g / L2`; `FR` and `zeta_s` refer to the
frequency `sqrt(g / L2)` there and to `w_1 = sqrt((1 + mu) g / L2)` here).

Measured on {machine}. Written by
`python -m pidamper.benchmarks.buildings` (this page is its output); tests: `tests/test_building.py`.
"""

COST_TEXT = """## Cost

Process CPU time of `Damper.advance` per communication step of 0.005 s over each scene's 20 s of
ground motion (best of 3; the running maxima included), and of the whole `fmpy.simulate_fmu` call
per step with every building output recorded.
"""

SCENES_TEXT = """## The scenes, with and without the damper

Synthetic Kanai-Tajimi ground motion (`forcing.kanai_tajimi`: filtered white noise simulated exactly from
rest, Jennings envelope), peak 3 m/s2, seed 1, 20 s; floors 1e5 kg, storeys 2e8 N/m,
zeta_s = 2 %; the damper: mu = 5 % of the building's mass, FR = 0.95, e = 0.5, d = 5 mm (3 storeys)
or 40 mm (10 storeys). Drift ratio: drift / 3.0 m storey height; peak drift ratio and peak
acceleration are the FMU's exact running maxima. One record says little about a
device (the assessment runs suites of records): on this one the damper {effect}. Its impacts jump the top floor's
velocity, which excites every mode of the building: the floor's acceleration right after an impact
is of the order of the highest natural frequency times that jump, hence the peak accelerations.
"""

FOOTER = """## Logs

A building run's MCAP has the topic `/building/floors` (arrays `x`, `a`, `drift` and `base_shear`
per communication point; Foxglove plots `/building/floors.x[0]` and so on), its `.rrd` the view
`floors` (`plots/floors/floor_k`), and the replay of the MCAP carries them; the CSV has every
building output by name.

## Not here

Large angles and the nonlinear level on a building."""


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m pidamper.benchmarks.buildings", description=__doc__)
    parser.add_argument("--out", default="docs/buildings", help="folder of README.md (default docs/buildings)")
    args = parser.parse_args(argv)
    text = report()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "README.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
