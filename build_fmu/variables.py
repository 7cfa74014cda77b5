"""The variables of the FMUs as tables: the one source of each FMU's documentation/index.html and of
the site's page docs/guide/fmu-variables.md (the building FMUs shown for two storeys).

    python -m build_fmu.variables docs/guide/fmu-variables.md
"""
import html
import importlib
import sys
from pathlib import Path

from .models import MODEL_NAME, family

#: the models of the site's page: a building family is shown for two storeys
MODELS = ("PendulumImpactDamper", "PendulumImpactDamperUnit", "DampedShearBuilding2", "ShearBuilding2")
_ADAPTERS = {"PendulumImpactDamper": "slave", "PendulumImpactDamperUnit": "unit_slave",
             "DampedShearBuilding": "damped_building_slave", "ShearBuilding": "building_slave"}
_HEADERS = {"Parameters": ("name", "unit", "start", "range", "description"),
            "Inputs": ("name", "unit", "description"),
            "Outputs": ("name", "unit", "direct feedthrough from", "description"),
            "Local variables": ("name", "unit", "direct feedthrough from", "description")}


def _range(lo, hi):
    return f"[{'' if lo is None else lo}, {'' if hi is None else hi}]"


def tables(model):
    """[(title, header, rows)] of `model`'s parameters, inputs, outputs and local variables."""
    kind, _ = family(model)
    module = importlib.import_module(f"pidamper_fmu.{_ADAPTERS[kind]}")
    cls = getattr(module, model)
    if kind in (MODEL_NAME, "DampedShearBuilding"):  # particle_tables' layout
        tables_module = importlib.import_module("pidamper_fmu.particle_tables")
        local = {name for name, *_ in tables_module.DERIVED}
        params = [(n, u or "", repr(start), _range(lo, hi), d) for n, _, start, u, lo, hi, d in cls.PARAMETERS]
        inputs = [(n, u, d) for n, u, d in tables_module.INPUTS]
        computed = [(n, u, ("F a_g" if feed else ""), d, n not in local) for n, _, u, d, feed in cls.COMPUTED]
    else:
        params = [(n, u or "", repr(start), _range(lo, hi), d) for n, _, start, u, lo, hi, d, _ in cls.PARAMETERS]
        inputs = [(n, u, d) for n, _, u, d in cls.INPUTS]
        computed = [(n, u, " ".join(feed), d, out) for n, _, u, d, out, feed in cls.COMPUTED]
    return [("Parameters", _HEADERS["Parameters"], params), ("Inputs", _HEADERS["Inputs"], inputs),
            ("Outputs", _HEADERS["Outputs"], [(n, u or "", f, d) for n, u, f, d, out in computed if out]),
            ("Local variables", _HEADERS["Local variables"],
             [(n, u or "", f, d) for n, u, f, d, out in computed if not out])]


def html_tables(model):
    """The tables as HTML sections (for the FMU's documentation/index.html)."""
    parts = []
    for title, header, rows in tables(model):
        if not rows:
            continue
        head = "".join(f"<th>{h}</th>" for h in header)
        body = "\n".join("<tr>" + "".join(f"<td>{html.escape(str(c))}</td>" for c in row) + "</tr>" for row in rows)
        parts.append(f'<h2>{title}</h2>\n<table border="1"><tr>{head}</tr>\n{body}</table>')
    return "\n".join(parts)


def _cell(value):
    return str(value).replace("|", "\\|")


def markdown():
    """The site's page of every FMU's variables."""
    lines = ["# FMU variables", "",
             "Every variable of the FMUs `python -m build_fmu --storeys N` builds, from the same tables as each "
             "FMU's own `documentation/index.html` (written by `python -m build_fmu.variables "
             "docs/guide/fmu-variables.md`; a test checks this page against them). The building FMUs "
             "`DampedShearBuilding<N>` and `ShearBuilding<N>` are shown for N = 2: each has exactly N floors' and "
             "storeys' variables of these names. Inputs are held over each communication step; names are a "
             "contract.", ""]
    for model in MODELS:
        lines += [f"## {model}", ""]
        for title, header, rows in tables(model):
            if not rows:
                continue
            lines += [f"### {title} ({model})", "", "| " + " | ".join(header) + " |",
                      "|" + "---|" * len(header)]
            lines += ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
            lines.append("")
    return "\n".join(lines)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    Path(argv[0]).write_text(markdown())
    print(argv[0])
    return 0


if __name__ == "__main__":
    sys.exit(main())
