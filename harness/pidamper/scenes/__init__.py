"""Scenes: the shipped scene files (TOML, installed with the package) and their loader (`scene`:
parameters, forcing, horizon, outputs and logging of a run, validated field by field).  It may import
the running room, the inputs and the run logs' option names."""
from .scene import Scene, SceneError, load, parse, shipped

__all__ = ["Scene", "SceneError", "load", "parse", "shipped"]
