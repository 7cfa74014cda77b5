"""What machine a measurement ran on: the line every measured page states."""
import os
import platform
from importlib.metadata import PackageNotFoundError, version


def cpu_model():
    """The CPU's model name (Linux: /proc/cpuinfo), else what platform knows of it."""
    try:
        with open("/proc/cpuinfo") as handle:
            return next(line.split(":", 1)[1].strip() for line in handle if line.startswith("model name"))
    except (OSError, StopIteration):
        return platform.processor() or "unknown CPU"


def describe(*packages):
    """'2-core x86_64 <CPU>, Python 3.11.7, fmpy 0.3.32, ...' with the versions of `packages`."""
    versions = []
    for name in packages:
        try:
            versions.append(f", {name} {version(name)}")
        except PackageNotFoundError:
            versions.append(f", {name} (not installed)")
    return (f"{os.cpu_count()}-core {platform.machine()} {cpu_model()}, Python {platform.python_version()}"
            + "".join(versions))
