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


# The moderngl.Context methods that create GL objects: only cityshade.gl calls them.
GL_OBJECT_MAKERS = frozenset(
    "buffer texture texture_array texture_cube texture3d depth_texture vertex_array simple_vertex_array "
    "framebuffer simple_framebuffer renderbuffer depth_renderbuffer program compute_shader sampler query "
    "scope".split()
)


def _ctx_calls(path: Path):
    """(line, method) of every call of a method on something called ctx (ctx, self.ctx, f.ctx)."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
            owner = node.func.value
            if (owner.id if isinstance(owner, ast.Name) else getattr(owner, "attr", "")) == "ctx":
                yield node.lineno, node.func.attr


def gl_object_calls(src: Path = SRC) -> list[str]:
    """The calls of a GL object maker outside cityshade/gl."""
    paths = [p for p in sorted(src.rglob("*.py")) if p.relative_to(src).parts[0] != "gl"]
    return [
        f"{path.relative_to(src.parent)}:{line}: ctx.{method}"
        for path in paths
        for line, method in _ctx_calls(path)
        if method in GL_OBJECT_MAKERS
    ]


def test_only_gl_creates_gl_objects():
    found = gl_object_calls()
    assert not found, "GL objects made outside cityshade.gl (use its toolkit):\n" + "\n".join(found)


def test_the_check_sees_a_gl_object_made_outside_gl(tmp_path):
    fake = tmp_path / "cityshade"
    (fake / "trees").mkdir(parents=True)
    (fake / "gl").mkdir()
    (fake / "trees" / "x.py").write_text(
        "vbo = ctx.buffer(b'')\nself.ctx.vertex_array(p, [])\nf.ctx.copy_framebuffer(a, b)\nbuffer(0)\n"
    )
    (fake / "gl" / "y.py").write_text("ctx.texture((1, 1), 4)\n")
    assert gl_object_calls(fake) == ["cityshade/trees/x.py:1: ctx.buffer", "cityshade/trees/x.py:2: ctx.vertex_array"]
