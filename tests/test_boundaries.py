"""Package boundaries: no package imports another package's private (_underscore) modules; it uses
that package's public __init__ instead."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parent.parent / "src" / "cityshade"


def _module_name(path: Path, src: Path) -> list[str]:
    parts = ["cityshade", *path.relative_to(src).with_suffix("").parts]
    return parts[:-1] if parts[-1] == "__init__" else parts


def _imports(path: Path, src: Path):
    """(line, absolute dotted name) of every module an import statement names, or imports from."""
    here = _module_name(path, src)
    package = here if path.name == "__init__.py" else here[:-1]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = ".".join([*base, *(node.module.split(".") if node.module else [])])
            yield node.lineno, module
            for alias in node.names:  # `from ..grammar import _gpu` names a module too
                if alias.name.startswith("_"):
                    yield node.lineno, f"{module}.{alias.name}"


def violations(src: Path = SRC) -> list[str]:
    found = []
    for path in sorted(src.rglob("*.py")):
        owner = _module_name(path, src)[:2]  # cityshade.<package>
        for line, name in _imports(path, src):
            parts = name.split(".")
            if parts[0] != "cityshade" or len(parts) < 3:
                continue
            private = next((i for i, p in enumerate(parts) if p.startswith("_") and i >= 2), None)
            if private is not None and parts[:2] != owner:
                found.append(f"{path.relative_to(src.parent)}:{line}: {name}")
    return found


def test_no_package_imports_another_packages_private_modules():
    found = violations()
    assert not found, "imports of another package's private modules:\n" + "\n".join(found)


def test_the_check_sees_a_private_import(tmp_path):
    fake = tmp_path / "cityshade"
    (fake / "trees").mkdir(parents=True)
    (fake / "trees" / "x.py").write_text(
        "from ..render._frame import Pass\nfrom ..render import Renderer\n"
        "from ._own import ok\nfrom .. import _files\nfrom ..scene import _city\n"
    )
    assert violations(fake) == [
        "cityshade/trees/x.py:1: cityshade.render._frame",
        "cityshade/trees/x.py:5: cityshade.scene._city",
    ]
