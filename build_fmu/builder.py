"""Assemble the model script and the renamed physics package, then call pythonfmu."""
import hashlib
import importlib.util
import re
import shutil
import tempfile
import uuid
from pathlib import Path

MODEL_NAME = "PendulumImpactDamper"
PHYSICS = "pidamper_physics"
_REPO_SRC = Path(__file__).resolve().parent.parent / "fmu_src"


def sources():
    """(model script, physics package dir): the repository's fmu_src/ or the installed packages."""
    if (_REPO_SRC / PHYSICS / "__init__.py").is_file():
        return _REPO_SRC / "pidamper_fmu" / "slave.py", _REPO_SRC / PHYSICS
    physics = Path(importlib.util.find_spec(PHYSICS).origin).parent
    slave = Path(importlib.util.find_spec("pidamper_fmu").origin).parent / "slave.py"
    return slave, physics


def _physics_files(physics_dir):
    return sorted(p for p in physics_dir.rglob("*.py") if "__pycache__" not in p.parts)


def source_hash():
    """12 hex digits of SHA-256 over the shipped sources and the pythonfmu version."""
    import pythonfmu

    slave, physics = sources()
    digest = hashlib.sha256(pythonfmu.__version__.encode())
    for path in [slave] + _physics_files(physics):
        rel = path.name if path == slave else path.relative_to(physics).as_posix()
        digest.update(rel.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:12]


def expected_guid(tag=None):
    """GUID the FMU built from the current sources carries (slave.py derives it the same way)."""
    return str(uuid.uuid5(uuid.NAMESPACE_URL, "pidamper/PendulumImpactDamper/" + (tag or source_hash())))


def build(out_dir="dist", documentation=None):
    """Build <out_dir>/PendulumImpactDamper.fmu and return its path."""
    from pythonfmu.builder import FmuBuilder

    slave, physics = sources()
    tag = source_hash()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="pidamper_build_") as tmp:
        tmp = Path(tmp)
        package = tmp / f"{PHYSICS}_{tag}"
        shutil.copytree(physics, package, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
        text = slave.read_text()
        text, n_imports = re.subn(rf"\b{PHYSICS}\b", f"{PHYSICS}_{tag}", text)
        text, n_hash = re.subn(r'^SOURCE_HASH = "development".*$', f'SOURCE_HASH = "{tag}"', text, flags=re.M)
        if n_imports == 0 or n_hash != 1:
            raise RuntimeError(f"{slave}: expected imports of {PHYSICS} and one SOURCE_HASH line")
        script = tmp / f"{MODEL_NAME}_{tag}.py"
        script.write_text(text)
        fmu = FmuBuilder.build_FMU(
            script, dest=out_dir / f"{MODEL_NAME}.fmu", project_files=[package],
            documentation_folder=documentation,
            needsExecutionTool=False, canHandleVariableCommunicationStepSize=True,
            canGetAndSetFMUstate=True, canSerializeFMUstate=True)
    return Path(fmu)
