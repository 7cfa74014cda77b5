"""The documentation/ folder of a component FMU (PendulumImpactDamperUnit, ShearBuilding): an
index.html with the model's description and its variable tables, read from the adapter module."""
import ast
import html
from pathlib import Path

from .documentation import git_revision


def _module_doc(path):
    return ast.get_docstring(ast.parse(Path(path).read_text())) or ""


def write(folder, model, adapter_path, version):
    """Fill `folder` with index.html for `model`, whose adapter module is `adapter_path`."""
    import importlib

    from .builder import COMPONENTS

    module = importlib.import_module(f"pidamper_fmu.{COMPONENTS[model]}")
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    physics = {"PendulumImpactDamperUnit": "unit.py", "ShearBuilding": "shear_motion.py"}[model]
    physics_doc = _module_doc(Path(importlib.import_module("pidamper_physics").__file__).with_name(physics))

    def row(*cells):
        return "<tr>" + "".join(f"<td>{html.escape('' if c is None else str(c))}</td>" for c in cells) + "</tr>"

    params = "\n".join(row(name, unit, repr(start), f"[{'' if lo is None else lo}, {'' if hi is None else hi}]",
                           ("tunable; " if tunable else "") + desc)
                       for name, _, start, unit, lo, hi, desc, tunable in module.PARAMETERS)
    inputs = "\n".join(row(name, unit, repr(start), desc) for name, start, unit, desc in module.INPUTS)
    computed = "\n".join(row(name, unit, "output" if out else "local", " ".join(feed), desc)
                         for name, _, unit, desc, out, feed in module.COMPUTED)
    text = f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{model}</title></head><body>
<h1>{model} {html.escape(version)}</h1>
<p>FMI 2.0 co-simulation, built by build_fmu from the pidamper physics package; source revision
{html.escape(git_revision())}. Inputs are held constant over each communication step
(canInterpolateInputs = false). The model runs in Python (see PendulumImpactDamper's documentation for
how a host provides it); refused values answer fmi2Error with a message naming the value.</p>
<h2>Adapter</h2><pre>{html.escape(_module_doc(adapter_path))}</pre>
<h2>Model</h2><pre>{html.escape(physics_doc)}</pre>
<h2>Parameters</h2>
<table border="1"><tr><th>name</th><th>unit</th><th>start</th><th>range</th><th>description</th></tr>
{params}</table>
<h2>Inputs</h2>
<table border="1"><tr><th>name</th><th>unit</th><th>start</th><th>description</th></tr>
{inputs}</table>
<h2>Outputs and local variables</h2>
<table border="1"><tr><th>name</th><th>unit</th><th>causality</th><th>direct feedthrough from</th>
<th>description</th></tr>
{computed}</table>
</body></html>
"""
    (folder / "index.html").write_text(text)
    return folder
