"""The documentation: the README is a front door, the FMU variables page is the FMUs' own tables, the
measured pages are where the site expects them, and every code block marked as an example runs.

(The site's strict build, `mkdocs build --strict`, runs in `make test` after the tests: a broken link
or a missing page fails CI there.)"""
import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
EXAMPLE = re.compile(r"^```python\n# example\n(.*?)^```", flags=re.M | re.S)


def examples():
    """(id, code) of every ```python block whose first line is `# example`, in the README and docs/."""
    found = []
    for path in [ROOT / "README.md"] + sorted(DOCS.rglob("*.md")):
        text = path.read_text()
        for match in EXAMPLE.finditer(text):
            line = text[:match.start()].count("\n") + 1
            found.append((f"{path.relative_to(ROOT)}:{line}", match.group(1)))
    return found


def test_the_readme_is_a_front_door():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.encode()) <= 10_000
    for link in re.findall(r"\]\(([^)#]+)", readme):  # every relative link reaches a file
        if not link.startswith("http"):
            assert (ROOT / link).exists(), link


def test_the_fmu_variables_page_is_the_fmus_own_tables():
    from build_fmu.variables import markdown

    assert (DOCS / "guide" / "fmu-variables.md").read_text() == markdown(), \
        "regenerate it: python -m build_fmu.variables docs/guide/fmu-variables.md"


def test_every_page_in_the_nav_exists_and_the_measured_pages_are_at_their_paths():
    class Loader(yaml.SafeLoader):
        pass

    Loader.add_multi_constructor("tag:", lambda loader, suffix, node: None)
    config = yaml.load((ROOT / "mkdocs.yml").read_text(), Loader=Loader)

    def pages(nav):
        for item in nav:
            value = next(iter(item.values())) if isinstance(item, dict) else item
            if isinstance(value, list):
                yield from pages(value)
            else:
                yield value

    listed = set(pages(config["nav"]))
    for page in listed:
        assert (DOCS / page).is_file(), page
    assert {"paper/README.md", "levels/README.md", "bench/step-cost.md", "buildings/README.md",
            "cosim/README.md", "assessment/README.md"} <= listed
    assert not any((DOCS / p).with_name("index.md").exists() for p in listed if p.endswith("README.md"))


def test_there_are_examples():
    ids = [i for i, _ in examples()]
    assert any(i.startswith("README.md") for i in ids) and any(i.startswith("docs/") for i in ids)


@pytest.mark.parametrize("where,code", examples(), ids=[i for i, _ in examples()])
def test_examples_run(where, code, tmp_path, fmu_path):
    script = tmp_path / "example.py"
    script.write_text(code)
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, f"{where}:\n{done.stdout[-1500:]}\n{done.stderr[-3000:]}"
