"""pidamper cosim: run the coupled system with the chosen masters and compare with the reference."""
import math

import numpy as np

from .components import component_fmus
from .masters import LABELS, MODES, gauss_seidel, libcosim_jacobi
from .reference import error, reference
from .scenario import scenario_from
from .system_files import export_system


def add_arguments(parser):
    parser.add_argument("--step", type=float, action="append",
                        help="communication step [s] (repeatable; default 0.001); must divide the horizon")
    parser.add_argument("--stop-time", type=float, help="horizon [s] (default 5)")
    parser.add_argument("--master", action="append", choices=tuple(LABELS),
                        help="which masters to run (repeatable; default: mean, impulse, impulse-extrapolated: fmpy "
                             "Gauss-Seidel; libcosim, libcosim-impulse: libcosim's Jacobi)")
    parser.add_argument("--fmu-dir", help="folder with ShearBuilding<N>.fmu (N: the scenario's storeys) and "
                                          "PendulumImpactDamperUnit.fmu (default: dist/, built when missing or stale)")
    parser.add_argument("--export", metavar="DIR", help="also write the SSP files and the OSP system structures "
                                                        "(and a copy of the FMUs) into DIR")
    parser.add_argument("--no-reference", action="store_true", help="do not compute the monolithic reference")
    parser.add_argument("-p", "--param", action="append", default=[], metavar="NAME=VALUE",
                        help="scenario field, e.g. -p e=0.8 -p pulse=3 (fields of pidamper.cosim.Scenario; -p sets its fields)")


def cli_main(argv=None, more_help=""):
    """pidamper cosim [options]: run the coupled system (see add_arguments); exit status.  more_help:
    printed after this help by -h (the cli passes the --opensees form's own help)."""
    import argparse
    import sys

    parser = argparse.ArgumentParser(
        prog="pidamper cosim",
        description="Co-simulate PendulumImpactDamperUnit.fmu on ShearBuilding<N>.fmu (Gauss-Seidel with fmpy, or "
                    "libcosim's Jacobi) and compare with the exact monolithic model; --export writes the SSP files "
                    "and OSP system structures.  With --opensees MODEL.py: the unit on a node of your OpenSees "
                    "model" + (" (its options below)." if more_help else "."))
    add_arguments(parser)
    if more_help and any(a in ("-h", "--help") for a in (sys.argv[1:] if argv is None else argv)):
        print(parser.format_help() + "\n" + more_help, end="")
        return 0
    args = parser.parse_args(argv)
    try:
        return main(args)
    except (ValueError, FileNotFoundError, RuntimeError) as err:
        print(f"pidamper cosim: error: {err}", file=sys.stderr)
        return 2


def main(args):
    scn = scenario_from(args.param, args.stop_time)
    fmus = component_fmus(args.fmu_dir, scn.storeys)
    if args.export:
        for path in export_system(args.export, scn, fmus):
            print(f"wrote {path}")
    steps = args.step or [0.001]
    masters = args.master or list(MODES)
    grid = max(steps)
    ref, source = (None, None)
    if not args.no_reference:
        times = np.arange(1, int(round(scn.stop_time / grid)) + 1) * grid
        ref, source = reference(scn, times)
        print(f"reference: {source}")
    print(f"{'master':46s} {'step [s]':>10s} {'impacts':>8s} {'wall [s]':>9s} {'max|x_top| [m]':>15s} "
          f"{'error':>10s}")
    for h in steps:
        for master in masters:
            if master in ("libcosim", "libcosim-impulse"):
                run = libcosim_jacobi(scn, h, master == "libcosim-impulse", fmus)
            else:
                run = gauss_seidel(scn, h, master, fmus)
            err = error(run, scn, grid, ref) if ref is not None else math.nan
            print(f"{run.master:46s} {h:10.3g} {run.impacts:8d} {run.wall:9.3f} {np.max(np.abs(run.x[:, -1])):15.6g} "
                  f"{err:10.3e}")
            for text in run.notes:
                print(f"  FMU: {text}")
    return 0
