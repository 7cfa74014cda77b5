"""python -m build_fmu [--out DIR] [--storeys N [N ...]] [--model NAME [NAME ...]]: build
PendulumImpactDamper.fmu and PendulumImpactDamperUnit.fmu, and for each N of --storeys (1..10)
DampedShearBuilding<N>.fmu and ShearBuilding<N>.fmu (default folder dist/; --model: those only)."""
import argparse

from .builder import build, build_all
from .models import MAX_STOREYS, check_storeys, family


def _storeys(text):
    try:
        return check_storeys(int(text))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not allowed: an integer in 1..{MAX_STOREYS}") from None


def _model(text):
    try:
        family(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None
    return text


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m build_fmu", description=__doc__)
    parser.add_argument("--out", default="dist", help="output folder (default: dist)")
    parser.add_argument("--storeys", type=_storeys, nargs="+", default=[], metavar="N",
                        help=f"also build DampedShearBuilding<N>.fmu and ShearBuilding<N>.fmu (N in 1..{MAX_STOREYS})")
    parser.add_argument("--model", type=_model, nargs="+", metavar="NAME",
                        help="build these FMUs only (PendulumImpactDamper, PendulumImpactDamperUnit, "
                             "DampedShearBuilding<N>, ShearBuilding<N>)")
    args = parser.parse_args(argv)
    paths = [build(args.out, model) for model in args.model] if args.model else build_all(args.out, args.storeys)
    for path in paths:
        print(path)


if __name__ == "__main__":
    main()
