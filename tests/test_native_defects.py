"""Defects at the FMU's boundary to its host, each shown by a test that failed before its fix:
build_fmu's builder and native imported each other."""
import ast
from pathlib import Path

import build_fmu


def _local_imports(path, modules):
    """The modules of `modules` that the module at `path` imports (at any depth, inside functions too)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            found.update([node.module.split(".")[0]] if node.module else [a.name for a in node.names])
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("build_fmu."):
            found.add(node.module.split(".")[1])
        elif isinstance(node, ast.Import):
            found.update(a.name.split(".")[1] for a in node.names if a.name.startswith("build_fmu."))
    return found & modules


def test_build_fmu_has_no_import_circle():
    """build_fmu's modules import each other one way only (builder and native imported each other)."""
    package = Path(build_fmu.__file__).parent
    modules = {p.stem for p in package.glob("*.py")} - {"__init__", "__main__"}
    graph = {m: _local_imports(package / f"{m}.py", modules) for m in modules}
    assert graph["builder"] >= {"native"}  # the search sees the imports (this one stays)

    def circle(start, node, path):
        for nxt in sorted(graph[node]):
            if nxt == start:
                return path + [nxt]
            if nxt not in path:
                found = circle(start, nxt, path + [nxt])
                if found:
                    return found
        return None

    circles = [c for c in (circle(m, m, [m]) for m in sorted(modules)) if c]
    assert not circles, " -> ".join(circles[0])
