"""pidamper cosim --opensees MODEL.py: the damper unit on a node of the engineer's OpenSees model.

    pidamper cosim --opensees model.py --node N --dof D --ground-motion FILE --step H --stop-time T
                   [-p NAME=VALUE ...] [--csv-out FILE] [--out DIR] [--substeps 4] [--direction 1]

Several units: repeat --node and --dof (one unit per pair, the same -p for all).  The CSV has one
row per step: time, the node's relative displacement x, velocity v, absolute acceleration a_abs
and the unit's outputs by their FMU names (prefixed unit[i]. with several units); the run is logged
to OUT/NAME.mcap and OUT/NAME.rrd.
"""
import argparse
import csv
import math
import sys
from pathlib import Path

from .coupling import UNIT_OUTPUTS, Attachment, Coupling, CouplingError, OpenSeesFailure
from .log import CosimLog, NODE_FIELDS
from .model import build_model, ground_samples


def parser():
    p = argparse.ArgumentParser(prog="pidamper cosim --opensees", description=__doc__.split("\n")[0])
    p.add_argument("--opensees", required=True, metavar="MODEL.py", help="Python file building the structure")
    p.add_argument("--node", type=int, action="append", required=True, help="attachment node tag (repeatable)")
    p.add_argument("--dof", type=int, action="append", help="its degree of freedom, 1-based (default 1; repeatable)")
    p.add_argument("--ground-motion", metavar="FILE", help="record (.AT2 or .csv time,a_g); none: free vibration")
    p.add_argument("--scale", type=float, default=1.0, help="factor on the record (default 1)")
    p.add_argument("--direction", type=int, default=1, help="degree of freedom the ground moves (default 1)")
    p.add_argument("--step", type=float, required=True, help="communication step [s]")
    p.add_argument("--stop-time", type=float, required=True, help="horizon [s], a whole number of steps")
    p.add_argument("--substeps", type=int, default=4, help="OpenSees steps per communication step (default 4)")
    p.add_argument("-p", "--param", action="append", default=[], metavar="NAME=VALUE",
                   help="a unit parameter (m, L1, d, e, zeta_p, M_s, the materials ...)")
    p.add_argument("--csv-out", metavar="FILE", help="write one row per step")
    p.add_argument("--out", default="out", help="folder of the MCAP and .rrd logs (default out/)")
    p.add_argument("--name", default="opensees", help="log file name (default opensees)")
    p.add_argument("--no-log", action="store_true", help="write no MCAP or .rrd")
    p.add_argument("--fmu", help="PendulumImpactDamperUnit.fmu to use (default: the current build)")
    return p


def unit_parameters(pairs):
    """{name: value} of `-p NAME=VALUE` items; M_s kept apart (the coupling's)."""
    values = {}
    for item in pairs:
        name, sep, text = item.partition("=")
        try:
            value = float(text)
        except ValueError:
            value = None
        if not sep or not name or value is None or not math.isfinite(value):
            raise CouplingError(f"-p {item!r} is not allowed: NAME=VALUE with a finite number")
        values[name.strip()] = int(value) if value.is_integer() and name.strip() in ("restitution",) else value
    return values


def columns(units):
    names = ("x", "v", "a_abs") + UNIT_OUTPUTS
    return ["time"] + (list(names) if units == 1 else [f"unit[{i + 1}].{n}" for i in range(units) for n in names])


def write_csv(path, result):
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
    try:
        return run(args)
    except (CouplingError, OpenSeesFailure, ValueError, FileNotFoundError, ImportError) as err:
        print(f"pidamper cosim --opensees: error: {err}", file=sys.stderr)
        return 2


def run(args):
    dofs = args.dof or [1] * len(args.node)
    if len(dofs) != len(args.node):
        raise CouplingError(f"--dof given {len(dofs)} times is not allowed: once per --node ({len(args.node)})")
    values = unit_parameters(args.param)
    M_s = values.pop("M_s", None)
    build_model(args.opensees)
    ground, record = (None, None)
    if args.ground_motion:
        ground, record = ground_samples(args.ground_motion, args.step, args.stop_time, args.scale)
    attachments = [Attachment(node, dof, dict(values), M_s) for node, dof in zip(args.node, dofs)]
    coupling = Coupling(attachments, args.step, ground=ground, direction=args.direction, substeps=args.substeps,
                        fmu=args.fmu)
    sink = None
    if not args.no_log:
        Path(args.out).mkdir(parents=True, exist_ok=True)
        info = {"model": str(args.opensees), "nodes": args.node, "dofs": dofs, "unit": values, "M_s": coupling.M_s,
                "step": args.step, "stop_time": args.stop_time, "substeps": args.substeps,
                "ground_motion": None if record is None else {"file": str(args.ground_motion), "dt": record.dt,
                                                              "npts": record.npts, "scale": args.scale}}
        sink = CosimLog(info, len(attachments), Path(args.out) / f"{args.name}.mcap", Path(args.out) / f"{args.name}.rrd")
    try:
        result = coupling.run(args.stop_time, sink=sink)
    except OpenSeesFailure:
        if args.csv_out:
            print(f"(no CSV: the run failed; the logs in {args.out}/ read back up to the failure)", file=sys.stderr)
        raise
    finally:
        coupling.close()
        if sink is not None:
            sink.close()
    for text in result.warnings:
        print(f"warning from the unit: {text}", file=sys.stderr)
    for i, (node, unit) in enumerate(zip(result.nodes, result.units)):
        print(f"unit {i + 1} on node {args.node[i]}, dof {dofs[i]} (M_s {result.M_s[i]:.6g} kg): "
              f"max |x| {abs(node[:, 0]).max():.6g} m, max |a_abs| {abs(node[:, 2]).max():.6g} m/s2, "
              f"impacts {int(unit[-1, UNIT_OUTPUTS.index('impacts')])}")
    print(f"{len(result.time) - 1} steps of {args.step:g} s to t = {result.time[-1]:.6g} s; CPU {result.cpu:.3f} s")
    if args.csv_out:
        write_csv(args.csv_out, result)
        print(f"wrote {args.csv_out}")
    if sink is not None:
        print(f"logged to {Path(args.out) / args.name}.mcap and .rrd")
    return 0


__all__ = ["main", "parser", "columns", "NODE_FIELDS"]
