"""Build dist/PendulumImpactDamper.fmu (and the component FMUs PendulumImpactDamperUnit.fmu,
ShearBuilding.fmu) from fmu_src/ with pythonfmu.

The physics package travels inside the FMU as ``pidamper_physics_<hash>`` and the
model script as ``PendulumImpactDamper_<hash>``, where <hash> is a digest of the
shipped sources: a process that already imported the source tree, or ran an
older build, can never make the FMU silently run other code (pythonfmu imports
the model by module name and Python caches modules per process).
"""
from .builder import COMPONENTS, build, build_all, build_component, expected_guid, source_hash, sources

__all__ = ["COMPONENTS", "build", "build_all", "build_component", "expected_guid", "source_hash", "sources"]
