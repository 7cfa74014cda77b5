"""Where the FMU's sources are: the repository's fmu_src/, or the installed packages."""
import importlib.util
from pathlib import Path

PHYSICS = "pidamper_physics"
_REPO_SRC = Path(__file__).resolve().parent.parent / "fmu_src"


def sources():
    """(model script, physics package dir): the repository's fmu_src/ or the installed packages."""
    if (_REPO_SRC / PHYSICS / "__init__.py").is_file():
        return _REPO_SRC / "pidamper_fmu" / "slave.py", _REPO_SRC / PHYSICS
    physics = Path(importlib.util.find_spec(PHYSICS).origin).parent
    slave = Path(importlib.util.find_spec("pidamper_fmu").origin).parent / "slave.py"
    return slave, physics
