"""The damper unit on the engineer's own OpenSeesPy model (issue 26): `Coupling` steps the model and
PendulumImpactDamperUnit FMUs on its nodes (coupling.py), `build_model` runs a model file
(model.py), `pidamper cosim --opensees` is the command (command.py); its arguments are checked in
checks.py, OpenSees ending the process is caught in exits.py, its lines kept apart in console.py."""
from .coupling import Attachment, CosimResult, Coupling, CouplingError, OpenSeesFailure, UNIT_OUTPUTS

__all__ = ["Attachment", "CosimResult", "Coupling", "CouplingError", "OpenSeesFailure", "UNIT_OUTPUTS"]
