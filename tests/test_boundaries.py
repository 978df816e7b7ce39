"""Package boundaries: no package imports another package's private (_underscore) modules; it uses
that package's public __init__ instead. The top-level parts of cityshade are layers: each imports
only from layers below it, and no import circle joins them."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
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
            named = [alias.name for alias in node.names if _names_module(module, alias.name, src)]
            if len(named) < len(node.names):
                yield node.lineno, module
            for name in named:  # `from ..grammar import _gpu`, `from .. import render` name modules
                yield node.lineno, f"{module}.{name}"


def _names_module(module: str, name: str, src: Path) -> bool:
    """Whether `from module import name` imports a module: one in the tree, or any private name."""
    folder = src.joinpath(*module.split(".")[1:])
    private = name.startswith("_") and not name.startswith("__")
    return private or (folder / f"{name}.py").exists() or (folder / name / "__init__.py").exists()


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


# The top-level parts of cityshade, lowest first, and why each sits where it does. A part imports
# only from layers below its own; the parts of one layer do not import each other. "" is the
# package face (cityshade/__init__.py), which every `import cityshade...` runs first.
LAYERS = (
    ("errors",),  # the one error type every part raises
    ("_values", "_files", "_json", "_budget", "_version"),  # plain Python: checks, files, JSON, budgets
    ("gl", "assets", "terrain"),  # the GL toolkit; procedural textures in numpy; the ground's relief from a DEM
    ("scene",),  # the city model: cameras, masses and their meshes
    ("frame",),  # passes, their targets and GL state, the frame's view and settings, culling
    ("grammar",),  # facade grammars and their deferred pass, over the scene
    ("relief",),  # relief maps, some rasterised from grammars
    ("interior", "trees"),  # rooms and windows, cut by grammar and relief openings; trees (impostors cached as reliefs)
    ("shader_constants", "maps"),  # every technique's constants for the shaders; map data to a scene with trees
    ("render",),  # the city's frame: its passes in order, the renderer, the city on the GPU
    ("export", "dataset"),  # cities as files; labelled renders
    ("api",),  # render_image and render_city
    ("",),  # the package face
    ("viewer",),  # the renderer in a window
    ("bench",),  # the papers' experiments, the viewer's among them
    ("commands",),  # the command line over all of it
    ("__main__",),  # python -m cityshade
)


def _part(name: str) -> str | None:
    """The top-level part of cityshade a dotted module name is in ("" for the face), None outside it."""
    parts = name.split(".")
    return (parts[1] if len(parts) > 1 else "") if parts[0] == "cityshade" else None


def part_imports(src: Path = SRC):
    """(file, line, importing part, imported part) of every import, at any depth, between two parts."""
    for path in sorted(src.rglob("*.py")):
        owner = _part(".".join(_module_name(path, src)))
        for line, name in _imports(path, src):
            target = _part(name)
            if target is not None and target != owner:
                yield path.relative_to(src.parent), line, owner, target


def upward_imports(src: Path = SRC, layers=LAYERS) -> list[str]:
    level = {part: i for i, layer in enumerate(layers) for part in layer}
    found = []
    for path, line, owner, target in part_imports(src):
        unplaced = [part for part in (owner, target) if part not in level]
        if unplaced:
            found.append(f"{path}:{line}: {unplaced[0] or 'the face'} has no layer")
        elif level[target] >= level[owner]:
            found.append(f"{path}:{line}: {owner or 'the face'} imports {target or 'the face'}")
    return found


def import_circles(src: Path = SRC) -> list[list[str]]:
    """The sets of parts that import each other round a circle (strongly connected, more than one)."""
    edges: dict[str, set[str]] = {}
    for _, _, owner, target in part_imports(src):
        edges.setdefault(owner, set()).add(target)

    def reach(start: str) -> set[str]:
        seen, todo = set(), [start]
        while todo:
            for nxt in edges.get(todo.pop(), ()):
                if nxt not in seen:
                    seen.add(nxt)
                    todo.append(nxt)
        return seen

    reached = {part: reach(part) for part in edges}
    circles = {frozenset(p for p in reached if p in reached[part] and part in reached[p]) for part in edges}
    return sorted(sorted(c) for c in circles if len(c) > 1)


def test_no_import_runs_upward_through_the_layers():
    found = upward_imports()
    assert not found, "imports that run upward (or sideways) through LAYERS:\n" + "\n".join(found)


def test_the_check_sees_an_upward_import(tmp_path):
    fake = tmp_path / "cityshade"
    for part in ("scene", "maps"):
        (fake / part).mkdir(parents=True)
        (fake / part / "__init__.py").write_text("")
    (fake / "scene" / "x.py").write_text("from ..errors import E\n\n\ndef load():\n    from ..maps import load_map\n")
    (fake / "maps" / "y.py").write_text(
        "from ..scene import City\nfrom .. import __version__, scene\nimport cityshade.new\n"
    )
    layers = (("errors",), ("scene",), ("maps",), ("",))
    assert upward_imports(fake, layers) == [
        "cityshade/maps/y.py:2: maps imports the face",
        "cityshade/maps/y.py:3: new has no layer",
        "cityshade/scene/x.py:5: scene imports maps",
    ]


def test_no_import_circle_joins_top_level_parts():
    assert import_circles() == []


def test_the_check_sees_an_import_circle(tmp_path):
    fake = tmp_path / "cityshade"
    fake.mkdir()
    (fake / "a.py").write_text("from . import b\n")
    (fake / "b.py").write_text("def later():\n    from .c import f\n")
    (fake / "c.py").write_text("import cityshade.a\n")
    (fake / "d.py").write_text("from .a import g\n")
    assert import_circles(fake) == [["a", "b", "c"]]


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


# Libraries that take a second or more to import, or matter only to one command: imported where used.
HEAVY = ("scipy", "ray", "pyarrow", "matplotlib", "osmium")


def heavy_modules_after(statement: str) -> list[str]:
    """The HEAVY libraries loaded by running `statement` in a fresh Python on this tree."""
    code = f"import sys\n{statement}\nprint(' '.join(m for m in {HEAVY!r} if m in sys.modules))"
    env = {**os.environ, "PYTHONPATH": str(SRC.parent)}
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return done.stdout.split()


def test_import_cityshade_loads_no_heavy_library():
    assert heavy_modules_after("import cityshade") == []


def test_the_check_sees_a_heavy_import():
    assert heavy_modules_after("import cityshade, scipy.ndimage") == ["scipy"]


# Tests check a package through its public names and its `testing` module (the numpy twins and the
# parts checked one by one); the few private imports left reach a module to patch or a private class.
TESTS = Path(__file__).resolve().parent
MAX_PRIVATE_TEST_IMPORTS = 20


def private_test_imports(tests: Path = TESTS) -> list[str]:
    """`file:line: module` of each import in the tests that names a private module or name of cityshade."""
    found = []
    for path in sorted(tests.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "cityshade":
                names = [*node.module.split("."), *(alias.name for alias in node.names)]
            elif isinstance(node, ast.Import):
                names = [
                    part
                    for alias in node.names
                    if alias.name.startswith("cityshade.")
                    for part in alias.name.split(".")
                ]
            else:
                continue
            if any(name.startswith("_") and name != "__version__" for name in names):
                found.append(f"{path.relative_to(tests)}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_tests_import_few_private_modules():
    found = private_test_imports()
    assert len(found) <= MAX_PRIVATE_TEST_IMPORTS, f"{len(found)} private imports in tests:\n" + "\n".join(found)


def test_the_check_sees_a_private_import_in_a_test(tmp_path):
    (tmp_path / "test_x.py").write_text(
        "import cityshade.render._frame\nfrom cityshade.scene import _city\nfrom cityshade.grammar._gpu import x\n"
        "from cityshade.grammar.testing import facade_view\nfrom cityshade import render\n"
    )
    assert [line.split(": ")[0] for line in private_test_imports(tmp_path)] == [
        "test_x.py:1",
        "test_x.py:2",
        "test_x.py:3",
    ]
