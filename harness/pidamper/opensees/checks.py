"""The one place the OpenSees co-simulation's arguments are checked: a refusal is a CouplingError
`<name> = <value> is not allowed: <rule>`, the name as the caller spells it (`--step` on the
command line, `step` in Python).  `arguments` (the command line's), `horizon`, `count`, `factor`
and `unit_parameters` need no model: the command runs them before OpenSees starts.  `on_model`
reads the built model (its node tags and degrees of freedom) and runs before any analysis."""
import math
from pathlib import Path

#: the unit's parameter the coupling sets itself (the impulses go to OpenSees as velocity jumps)
COUPLING_SETS = ("impulse_aware",)


class CouplingError(ValueError):
    """A value the coupling cannot honour (a node, a degree of freedom, a mass, a step), named."""


def _real(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def positive(name, value, unit="s"):
    """value, a finite number > 0 [unit]."""
    if not (_real(value) and math.isfinite(value) and value > 0.0):
        raise CouplingError(f"{name} = {value!r} is not allowed: a finite number > 0 {unit}")
    return value


def horizon(stop_time, h, names=("stop_time", "step")):
    """The number of steps h [s] in stop_time [s]: both finite and > 0, h at most stop_time, and
    stop_time a whole number of them (to 1e-9)."""
    positive(names[0], stop_time)
    positive(names[1], h)
    if h > stop_time:
        raise CouplingError(f"{names[1]} = {h!r} is not allowed: at most the stop time ({stop_time!r} s)")
    n = int(round(stop_time / h))
    if abs(n * h - stop_time) > 1e-9 * stop_time:
        raise CouplingError(f"{names[0]} = {stop_time!r} is not allowed: a whole number of steps of {h!r} s "
                            f"(it is {stop_time / h:.6g} steps)")
    return n


def count(name, value, least=1):
    """value, an integer >= least."""
    if type(value) is not int or value < least:
        raise CouplingError(f"{name} = {value!r} is not allowed: an integer >= {least}")
    return value


def factor(name, value):
    """value, a finite number."""
    if not (_real(value) and math.isfinite(value)):
        raise CouplingError(f"{name} = {value!r} is not allowed: a finite factor")
    return value


def unit_parameters(pairs, md):
    """({name: value}, M_s or None) from `-p NAME=VALUE` items against the unit FMU's model
    description `md` (fmpy): a parameter it declares (not one the coupling sets), a finite number,
    an integer within its declared range where the FMU takes an integer.  The FMU checks the rest
    (ranges of reals, relations between parameters) and names what it refuses."""
    declared = {v.name: v for v in md.modelVariables if v.causality == "parameter"}
    values = {}
    for item in pairs:
        name, sep, text = (part.strip() for part in item.partition("="))
        try:
            value = float(text)
        except ValueError:
            value = None
        if not sep or not name or value is None or not math.isfinite(value):
            raise CouplingError(f"-p {item!r} is not allowed: NAME=VALUE with a finite number")
        var = declared.get(name)
        if var is None:
            raise CouplingError(f"{name} = {value!r} is not allowed: -p takes a parameter of the unit "
                                f"({md.modelName}): {', '.join(n for n in declared if n not in COUPLING_SETS)}")
        if name in COUPLING_SETS:
            raise CouplingError(f"{name} = {text} is not allowed: the coupling sets it (1: the unit reports its "
                                "impulses, OpenSees applies them as velocity jumps)")
        if var.type == "Integer":
            low, high = int(var.min), int(var.max)
            if not (value.is_integer() and low <= value <= high):
                shown = int(value) if value.is_integer() else value
                raise CouplingError(f"{name} = {shown!r} is not allowed: an integer, one of "
                                    f"{', '.join(str(k) for k in range(low, high + 1))} ({var.description})")
            value = int(value)
        values[name] = value
    M_s = values.pop("M_s", None)
    if M_s is not None:
        positive("M_s", M_s, "kg (without -p M_s: the apparent mass of the attachment)")
    return values, M_s


def on_model(ops, attachments, direction, flag=""):
    """The attachments' nodes and degrees of freedom, and the ground's `direction`, against the
    built model: a node it has, a degree of freedom 1..ndf of that node, a direction every node has
    (UniformExcitation moves that degree of freedom of every node).  Names are flag + node, dof,
    direction."""
    tags = list(ops.getNodeTags())
    ndf = {tag: len(ops.nodeDisp(tag)) for tag in tags}
    for a in attachments:
        if a.node not in ndf:
            raise CouplingError(f"{flag}node = {a.node!r} is not allowed: the model has no such node "
                                f"({len(tags)} nodes, tags {min(tags)}..{max(tags)})" if tags else
                                f"{flag}node = {a.node!r} is not allowed: the model has no nodes")
        if type(a.dof) is not int or not 1 <= a.dof <= ndf[a.node]:
            raise CouplingError(f"{flag}dof = {a.dof!r} is not allowed: node {a.node} has degrees of freedom "
                                f"1..{ndf[a.node]}")
    common = min(ndf.values(), default=0)
    if type(direction) is not int or not 1 <= direction <= common:
        raise CouplingError(f"{flag}direction = {direction!r} is not allowed: a degree of freedom every node of the "
                            f"model has, 1..{common}")


def writable(flag, path, folder=False):
    """path a file (a folder if `folder`) that can be made: not the other kind, no file among its
    folders (those missing are made when it is written)."""
    path = Path(path)
    there = next((p for p in (path, *path.resolve().parents) if p.exists()), None)
    kind, other = ("folder", "file") if folder else ("file", "folder")
    if there == path and there.is_dir() != folder:
        raise CouplingError(f"{flag} = {str(path)!r} is not allowed: a {kind} (it is a {other})")
    if there is not None and there != path and not there.is_dir():
        raise CouplingError(f"{flag} = {str(path)!r} is not allowed: a {kind} in a folder ({there} is a file)")


def arguments(args):
    """The command line's arguments that need neither the model nor the unit FMU (command.parser);
    returns the dofs, one per --node."""
    horizon(args.stop_time, args.step, ("--stop-time", "--step"))
    count("--substeps", args.substeps)
    factor("--scale", args.scale)
    dofs = args.dof or [1] * len(args.node)
    if len(dofs) != len(args.node):
        raise CouplingError(f"--dof given {len(dofs)} times is not allowed: once per --node ({len(args.node)})")
    for dof in dofs:
        count("--dof", dof)
    if not Path(args.opensees).is_file():
        raise CouplingError(f"--opensees = {args.opensees!r} is not allowed: no such file (a Python file that builds "
                            "the structure with openseespy)")
    if args.csv_out:
        writable("--csv-out", args.csv_out)
    if not args.no_log:
        writable("--out", args.out, folder=True)
    return dofs
