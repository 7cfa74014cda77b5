"""python -m build_fmu [--out DIR] [--model NAME]: build PendulumImpactDamper.fmu and the component
FMUs PendulumImpactDamperUnit.fmu and ShearBuilding.fmu (default dist/; --model: that one only)."""
import argparse

from .builder import COMPONENTS, MODEL_NAME, build, build_all, build_component


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m build_fmu", description=__doc__)
    parser.add_argument("--out", default="dist", help="output folder (default: dist)")
    parser.add_argument("--model", choices=(MODEL_NAME,) + tuple(COMPONENTS), help="build this FMU only")
    args = parser.parse_args(argv)
    if args.model is None:
        paths = build_all(args.out)
    elif args.model == MODEL_NAME:
        paths = [build(args.out)]
    else:
        paths = [build_component(args.model, args.out)]
    for path in paths:
        print(path)


if __name__ == "__main__":
    main()
