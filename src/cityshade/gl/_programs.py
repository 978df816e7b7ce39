"""GLSL programs from .glsl files in cityshade/shaders, with #include, #define variants and caching.

A program is one file whose stages are selected with `#if defined VERTEX_SHADER` /
`GEOMETRY_SHADER` / `FRAGMENT_SHADER` / `COMPUTE_SHADER`. `#include "common/x.glsl"` pastes
a file (once per stage) and `#line` directives keep every line traceable to its file, so a
compile error names the file and line it came from. `generated/NAME.glsl` includes are text made
from Python definitions (gl/_generated.py); those in PRELUDE (the frame block, the shared
constants, the binding points) go into every stage of every program. A linked program in which
two active resources share a binding point is refused (gl/_bindings.py).
"""

from __future__ import annotations

import re
from importlib import resources

import moderngl

from ..errors import ShaderError
from ._bindings import check_bindings

GLSL_VERSION = 430  # every program is GLSL 4.30 core; the loader writes the #version line
STAGES = {
    "vertex_shader": "VERTEX_SHADER",
    "geometry_shader": "GEOMETRY_SHADER",
    "fragment_shader": "FRAGMENT_SHADER",
}
_INCLUDE = re.compile(r'^\s*#include\s+"([^"]+)"\s*$')
_UNIFORM = re.compile(r"^\s*uniform\s+\w+\s+([^;{]+);", re.M)  # uniform TYPE a, b[3];
_SAMPLER = re.compile(r"^\s*uniform\s+\w*sampler\w*\s+([^;{]+);", re.M)
# Mesa: "0:12(5): error: ..."; NVIDIA: "0(12) : error ..."
_MESA_LOC = re.compile(r"(\d+):(\d+)\((\d+)\)")
_NV_LOC = re.compile(r"(\d+)\((\d+)\)")


GENERATED: dict[str, str] = {}  # "generated/NAME.glsl" -> text made from Python definitions
PRELUDE: list[str] = []  # generated includes that every program gets, in every stage


def shader_source(path: str) -> str:
    """The text of a shader file, path relative to cityshade/shaders (or a generated include)."""
    if path in GENERATED:
        return GENERATED[path]
    try:
        return resources.files("cityshade").joinpath("shaders", path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise ShaderError(f"shader file not found: shaders/{path}") from None


class _Assembler:
    """Expands includes into one source string, numbering each file for #line."""

    def __init__(self):
        self.files: list[str] = []

    def file_index(self, path: str) -> int:
        if path not in self.files:
            self.files.append(path)
        return self.files.index(path)

    def expand(self, path: str, seen: set[str]) -> str:
        if path in seen:
            return ""
        seen.add(path)
        index = self.file_index(path)
        out = [f"#line 1 {index}"]
        for number, line in enumerate(shader_source(path).splitlines(), start=1):
            match = _INCLUDE.match(line)
            if match:
                out.append(self.expand(match.group(1), seen))
                out.append(f"#line {number + 1} {index}")
            else:
                out.append(line)
        return "\n".join(out)

    def locate(self, message: str) -> str:
        """Rewrites 'file-index:line(col)' locations in a driver log into 'shaders/file:line:col'."""

        def mesa(m: re.Match) -> str:
            idx, line, col = (int(g) for g in m.groups())
            name = self.files[idx] if idx < len(self.files) else f"<source {idx}>"
            return f"shaders/{name}:{line}:{col}"

        text, count = _MESA_LOC.subn(mesa, message)
        if count:
            return text

        def nv(m: re.Match) -> str:
            idx, line = (int(g) for g in m.groups())
            name = self.files[idx] if idx < len(self.files) else f"<source {idx}>"
            return f"shaders/{name}:{line}"

        return _NV_LOC.sub(nv, message)


def _define_block(stage: str, defines: dict[str, object]) -> str:
    lines = [f"#version {GLSL_VERSION} core", f"#define {stage}"]
    for name, value in sorted(defines.items()):
        if value is False or value is None:
            continue
        lines.append(f"#define {name}" if value is True else f"#define {name} {value}")
    lines += [GENERATED[path] for path in PRELUDE]
    return "\n".join(lines) + "\n"


class ProgramCache:
    """Compiled programs keyed by (file, defines); feature variants are defines, never copies."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self._programs: dict[tuple, moderngl.Program | moderngl.ComputeShader] = {}

    def get(self, path: str, defines: dict[str, object] | None = None, varyings: tuple[str, ...] = ()):
        defines = dict(defines or {})
        key = (path, tuple(sorted((k, str(v)) for k, v in defines.items())), varyings)
        program = self._programs.get(key)
        if program is None:
            program = self._build(path, defines, varyings)
            self._programs[key] = program
        return program

    def built(self) -> list[tuple[str, moderngl.Program | moderngl.ComputeShader]]:
        """(file, program) for every program built so far."""
        return [(key[0], program) for key, program in self._programs.items()]

    def _build(self, path: str, defines: dict[str, object], varyings: tuple[str, ...]):
        assembler = _Assembler()
        body = assembler.expand(path, set())
        try:
            if "COMPUTE_SHADER" in body:
                program = self.ctx.compute_shader(_define_block("COMPUTE_SHADER", defines) + body)
            else:
                stages = {
                    arg: _define_block(token, defines) + body
                    for arg, token in STAGES.items()
                    if f"defined {token}" in body or f"defined({token})" in body
                }
                program = self.ctx.program(**stages, varyings=varyings)
        except moderngl.Error as exc:
            raise ShaderError(f"{path}: {assembler.locate(str(exc)).strip()}") from None
        check_bindings(program, f"shaders/{path}")
        if isinstance(program, moderngl.ComputeShader):
            return program
        # what the files declare, for gl.set_uniforms and gl.bind_textures in strict mode
        program.extra = {
            "path": f"shaders/{path}",
            "uniforms": _names(_UNIFORM, body),
            "samplers": _names(_SAMPLER, body),
        }
        return program


def program_path(program) -> str:
    """The shader file of a cached program, for messages."""
    return program.extra.get("path", "the program") if isinstance(program.extra, dict) else "the program"


def declared_uniforms(program) -> frozenset[str]:
    """The uniforms (samplers included) that the shader files of a cached program declare, active
    or compiled away by its #define variant; for a program made elsewhere, its active members."""
    extra = program.extra if isinstance(program.extra, dict) else {}
    return extra["uniforms"] if "uniforms" in extra else frozenset(program)


def declared_samplers(program) -> frozenset[str]:
    """The samplers the shader files of a cached program declare (active or compiled away)."""
    extra = program.extra if isinstance(program.extra, dict) else {}
    return extra["samplers"] if "samplers" in extra else frozenset(program)


def _names(pattern: re.Pattern, text: str) -> frozenset[str]:
    """The names declared by each `uniform TYPE a, b[3];` that `pattern` matches in `text`."""
    return frozenset(
        name.split("[")[0].strip() for match in pattern.finditer(text) for name in match.group(1).split(",")
    )
