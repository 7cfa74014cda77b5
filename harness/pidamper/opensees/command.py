"""pidamper cosim --opensees MODEL.py: the damper unit on a node of the engineer's OpenSees model.

    pidamper cosim --opensees model.py --node N --dof D --ground-motion FILE --step H --stop-time T
                   [-p NAME=VALUE ...] [--csv-out FILE] [--out DIR] [--substeps 4] [--direction 1]

Several units: repeat --node and --dof (one unit per pair, the same -p for all).  The CSV has one
row per step: time, the node's relative displacement x, velocity v, absolute acceleration a_abs
and the unit's outputs by their FMU names (prefixed unit[i]. with several units); the run is logged
to OUT/NAME.mcap and OUT/NAME.rrd.  Every argument is checked before OpenSees starts, the node,
dof and direction once the model is built and before any analysis; a model file that fails or
exits, or OpenSees ending the process (exits.py), is an error (exit status 2), the logs read back.
"""
import argparse
import csv
from pathlib import Path

import fmpy

from ..running.fmu import find_fmu
from . import checks, console, exits
from .checks import CouplingError
from .coupling import UNIT_OUTPUTS, Attachment, Coupling, OpenSeesFailure
from .log import CosimLog, NODE_FIELDS
from .model import build_model, ground_samples, held_note

PROG = "pidamper cosim --opensees"
UNIT_MODEL = "PendulumImpactDamperUnit"


def parser():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n")[0])
    p.add_argument("--opensees", required=True, metavar="MODEL.py", help="Python file building the structure")
    p.add_argument("--node", type=int, action="append", required=True, help="attachment node tag (repeatable)")
    p.add_argument("--dof", type=int, action="append", help="its degree of freedom, 1-based (default 1; repeatable)")
    p.add_argument("--ground-motion", metavar="FILE",
                   help="record (.AT2 or .csv time,a_g; its last value held after its end); none: free vibration")
    p.add_argument("--scale", type=float, default=1.0, help="factor on the record (default 1)")
    p.add_argument("--direction", type=int, default=1,
                   help="degree of freedom the ground moves, one every node has (default 1)")
    p.add_argument("--step", type=float, required=True, help="communication step [s], at most the stop time")
    p.add_argument("--stop-time", type=float, required=True, help="horizon [s], a whole number of steps")
    p.add_argument("--substeps", type=int, default=4, help="OpenSees steps per communication step (default 4)")
    p.add_argument("-p", "--param", action="append", default=[], metavar="NAME=VALUE",
                   help="a unit parameter (m, L1, d, e, zeta_p, M_s, restitution, the materials ...: "
                        "a name the unit does not have lists them)")
    p.add_argument("--csv-out", metavar="FILE", help="write one row per step")
    p.add_argument("--out", default="out", help="folder of the MCAP and .rrd logs (default out/)")
    p.add_argument("--name", default="opensees", help="log file name (default opensees)")
    p.add_argument("--no-log", action="store_true", help="write no MCAP or .rrd")
    p.add_argument("--fmu", help="PendulumImpactDamperUnit.fmu to use (default: the current build)")
    return p


def columns(units):
    names = ("x", "v", "a_abs") + UNIT_OUTPUTS
    return ["time"] + (list(names) if units == 1 else [f"unit[{i + 1}].{n}" for i in range(units) for n in names])


def write_csv(path, result):
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as handle:
        out = csv.writer(handle)
        out.writerow(columns(len(result.nodes)))
        for k, t in enumerate(result.time):
            row = [repr(float(t))]
            for node, unit in zip(result.nodes, result.units):
                row += [repr(float(v)) for v in node[k]] + [repr(float(v)) for v in unit[k]]
            out.writerow(row)


def main(argv=None):
    args = parser().parse_args(argv)
    with console.tracked():
        try:
            return run(args)
        except (CouplingError, OpenSeesFailure, ValueError, FileNotFoundError, ImportError) as err:
            console.say(f"{PROG}: error: {err}", error=True)
            return 2


def prepared(args):
    """What needs no model, before OpenSees starts: the arguments checked (checks.py), the unit
    FMU's description read, the record sampled.  (dofs, unit values, M_s or None, the FMU's path,
    ground samples and record, both None without --ground-motion)."""
    dofs = checks.arguments(args)
    fmu = Path(args.fmu) if args.fmu else find_fmu(model=UNIT_MODEL)
    try:
        md = fmpy.read_model_description(str(fmu))
    except Exception as err:
        raise CouplingError(f"--fmu = {str(fmu)!r} is not allowed: not a readable FMU ({err})") from None
    if md.modelName != UNIT_MODEL:
        raise CouplingError(f"--fmu = {str(fmu)!r} is not allowed: a {UNIT_MODEL} FMU (it is {md.modelName})")
    values, M_s = checks.unit_parameters(args.param, md)
    ground = record = None
    if args.ground_motion:
        ground, record = ground_samples(args.ground_motion, args.step, args.stop_time, args.scale)
    return dofs, values, M_s, str(fmu), ground, record


def run(args):
    dofs, values, M_s, fmu, ground, record = prepared(args)
    note = None if record is None else held_note(record, ground, args.step, args.stop_time)
    if note:
        console.say(f"{PROG}: note: {note}", error=True)
    attachments = [Attachment(node, dof, dict(values), M_s) for node, dof in zip(args.node, dofs)]
    state = {"doing": f"while running the model file {args.opensees}", "coupling": None, "sink": None}
    with exits.guarded(lambda status: ended(status, state, args)):
        ops = build_model(args.opensees)
        checks.on_model(ops, attachments, args.direction, flag="--")
        state["doing"] = "while reading the model's mass and damping (its first analysis steps, from rest)"
        coupling = state["coupling"] = Coupling(attachments, args.step, ground=ground, direction=args.direction,
                                                substeps=args.substeps, fmu=fmu)
        sink = None
        if not args.no_log:
            Path(args.out).mkdir(parents=True, exist_ok=True)
            info = {"model": str(args.opensees), "nodes": args.node, "dofs": dofs, "unit": values,
                    "M_s": coupling.M_s, "step": args.step, "stop_time": args.stop_time, "substeps": args.substeps,
                    "ground_motion": None if record is None else {"file": str(args.ground_motion), "dt": record.dt,
                                                                  "npts": record.npts, "scale": args.scale}}
            sink = state["sink"] = CosimLog(info, len(attachments), Path(args.out) / f"{args.name}.mcap",
                                            Path(args.out) / f"{args.name}.rrd")
        state["doing"] = "in the co-simulation"
        try:
            result = coupling.run(args.stop_time, sink=sink)
        except OpenSeesFailure:
            if args.csv_out:
                console.say(f"(no CSV: the run failed; the logs in {args.out}/ read back up to the failure)",
                            error=True)
            raise
        finally:
            coupling.close()
            if sink is not None:
                sink.close()
    report(args, dofs, result, sink)
    return 0


def ended(status, state, args):
    """What is said and kept when the process exits inside the run (exits.guarded): the completed
    steps handed to the logs, the logs closed, the phase named."""
    coupling, sink, where = state["coupling"], state["sink"], state["doing"]
    running = coupling is not None and coupling.stopped is not None
    if running:
        n = int(round(args.stop_time / args.step))
        where = f"in the co-simulation after {coupling.done} of {n} steps (t = {coupling.done * args.step:g} s)"
    text = f"OpenSees ended the process (exit status {status}) {where}: see OpenSees's output above"
    if sink is not None:
        sink.drop_rerun()
    if running:
        coupling.stopped(text, coupling.done * args.step)
    if sink is not None:
        sink.close()
        text += f"; {Path(args.out) / args.name}.mcap reads back up to there, the .rrd to its last block"
    console.say(f"{PROG}: error: {text}" + (" (no CSV)" if args.csv_out else ""), error=True)


def report(args, dofs, result, sink):
    """The run's summary, its CSV, where it was logged."""
    for text in result.warnings:
        console.say(f"warning from the unit: {text}", error=True)
    for i, (node, unit) in enumerate(zip(result.nodes, result.units)):
        console.say(f"unit {i + 1} on node {args.node[i]}, dof {dofs[i]} (M_s {result.M_s[i]:.6g} kg): "
                    f"max |x| {abs(node[:, 0]).max():.6g} m, max |a_abs| {abs(node[:, 2]).max():.6g} m/s2, "
                    f"impacts {int(unit[-1, UNIT_OUTPUTS.index('impacts')])}")
    console.say(f"{len(result.time) - 1} steps of {args.step:g} s to t = {result.time[-1]:.6g} s; "
                f"CPU {result.cpu:.3f} s")
    if args.csv_out:
        write_csv(args.csv_out, result)
        console.say(f"wrote {args.csv_out}")
    if sink is not None:
        console.say(f"logged to {Path(args.out) / args.name}.mcap and .rrd")


__all__ = ["main", "parser", "columns", "NODE_FIELDS"]
