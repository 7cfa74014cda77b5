"""Where the FMU's sources are: the repository's fmu_src/, or the installed packages of an installed
pidamper.  builder and native both import this module; it imports neither."""
import importlib.util
from pathlib import Path

PHYSICS = "pidamper_physics"
ADAPTER = "pidamper_fmu"
_REPO_SRC = Path(__file__).resolve().parent.parent / "fmu_src"


def sources():
    """(model script, physics package dir): the repository's fmu_src/ or the installed packages."""
    if (_REPO_SRC / PHYSICS / "__init__.py").is_file():
        return _REPO_SRC / ADAPTER / "slave.py", _REPO_SRC / PHYSICS
    physics = Path(importlib.util.find_spec(PHYSICS).origin).parent
    slave = Path(importlib.util.find_spec(ADAPTER).origin).parent / "slave.py"
    return slave, physics


def native_source():
    """The native layer's C source (fmi2_entry.c), beside the model's adapter."""
    return sources()[0].with_name("fmi2_entry.c")
