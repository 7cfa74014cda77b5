"""The documentation/ folder of the FMUs other than PendulumImpactDamper (PendulumImpactDamperUnit,
DampedShearBuilding<N>, ShearBuilding<N>): an index.html with the model's description and its
variable tables, read from the adapter module."""
import ast
import html
from pathlib import Path

from .models import family
from .documentation import git_revision
from .variables import html_tables

#: the physics module whose doc describes each family's model
PHYSICS_DOC = {"PendulumImpactDamperUnit": "unit.py", "ShearBuilding": "shear_motion.py",
               "DampedShearBuilding": "building_level.py"}


def _module_doc(path):
    return ast.get_docstring(ast.parse(Path(path).read_text())) or ""


def write(folder, model, adapter_path, version):
    """Fill `folder` with index.html for `model`, whose adapter module is `adapter_path`."""
    import importlib

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    physics = PHYSICS_DOC[family(model)[0]]
    physics_doc = _module_doc(Path(importlib.import_module("pidamper_physics").__file__).with_name(physics))

    text = f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>{model}</title></head><body>
<h1>{model} {html.escape(version)}</h1>
<p>FMI 2.0 co-simulation, built by build_fmu from the pidamper physics package; source revision
{html.escape(git_revision())}. Inputs are held constant over each communication step
(canInterpolateInputs = false). The model runs in Python (see PendulumImpactDamper's documentation for
how a host provides it); refused values answer fmi2Error with a message naming the value.</p>
<h2>Adapter</h2><pre>{html.escape(_module_doc(adapter_path))}</pre>
<h2>Model</h2><pre>{html.escape(physics_doc)}</pre>
{html_tables(model)}
</body></html>
"""
    (folder / "index.html").write_text(text)
    return folder
