"""The package as a user installs it: the wheel, built from this tree, in a fresh virtual environment
(its dependencies borrowed from the test environment, so no registry is needed)."""
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

IMPORT_EVERYTHING = r'''
import importlib, pkgutil, sys
names = []
for top in ("pidamper", "pidamper_physics", "pidamper_fmu", "build_fmu"):
    package = importlib.import_module(top)
    assert package.__file__.startswith(sys.prefix), package.__file__  # the installed copy, not the tree
    names.append(top)
    for info in pkgutil.walk_packages(package.__path__, top + "."):
        if info.ispkg:
            importlib.import_module(info.name)
            names.append(info.name)
print(" ".join(sorted(names)))
'''


def _run(cmd, **kwargs):
    done = subprocess.run(cmd, capture_output=True, text=True, **kwargs)
    assert done.returncode == 0, (cmd, done.stdout[-2000:], done.stderr[-2000:])
    return done.stdout


def test_wheel_installs_and_runs_from_a_clean_environment(tmp_path):
    """Package discovery ships every subpackage and its data: from the installed wheel alone,
    `pidamper --help` runs, every subpackage imports (the shipped scenes among them) and
    `python -m build_fmu --storeys 2` builds the pendulum system, the unit and both 2-storey buildings."""
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path / "wheel"), str(ROOT)])
    wheel, = (tmp_path / "wheel").glob("pidamper-*.whl")
    env_dir = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", str(env_dir)])
    python = env_dir / "bin" / "python"
    site = Path(_run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"]).strip())
    (site / "borrowed_dependencies.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    _run([str(python), "-m", "pip", "install", "-q", "--no-deps", "--no-index", str(wheel)])
    work = tmp_path / "elsewhere"  # no source tree on the path
    work.mkdir()
    assert "usage: pidamper" in _run([str(env_dir / "bin" / "pidamper"), "--help"], cwd=work)
    names = _run([str(python), "-c", IMPORT_EVERYTHING], cwd=work).split()
    assert {"pidamper.scenes", "pidamper.oracles", "pidamper.benchmarks", "pidamper.runlog", "pidamper_physics", "pidamper_fmu",
            "build_fmu"} <= set(names)
    scenes = _run([str(python), "-c", "from pidamper import scenes; print(' '.join(scenes.shipped()))"], cwd=work)
    assert "resonance" in scenes.split() and len(scenes.split()) >= 10
    out = tmp_path / "fmus"
    _run([str(python), "-m", "build_fmu", "--out", str(out), "--storeys", "2"], cwd=work)
    assert sorted(p.name for p in out.glob("*.fmu")) == ["DampedShearBuilding2.fmu", "PendulumImpactDamper.fmu",
                                                          "PendulumImpactDamperUnit.fmu", "ShearBuilding2.fmu"]
