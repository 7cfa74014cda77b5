"""Build the pidamper FMUs from fmu_src/ with pythonfmu: PendulumImpactDamper.fmu,
PendulumImpactDamperUnit.fmu and, per storey count N = 1..10, DampedShearBuilding<N>.fmu and
ShearBuilding<N>.fmu.

The physics package travels inside each FMU as ``pidamper_physics_<hash>`` and the model script as
``<model>_<hash>``, where <hash> is a digest of the shipped sources: a process that already
imported the source tree, or ran an older build, can never make the FMU silently run other code
(pythonfmu imports the model by module name and Python caches modules per process).
"""
from .builder import build, build_all, expected_guid, source_hash, sources
from .models import BASE_MODELS, MAX_STOREYS, building_models, check_storeys, family, models

__all__ = ["BASE_MODELS", "MAX_STOREYS", "build", "build_all", "building_models", "check_storeys",
           "expected_guid", "family", "models", "source_hash", "sources"]
