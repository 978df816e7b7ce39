"""Textures bound by sampler name: each program numbers its own active samplers 0..n-1 (in name
order, array elements consecutively), found by introspection, so no table of units is shared
between programs and no two samplers of a program share a unit.

OpenGL 4.3 guarantees 16 texture units per stage; a program with more active samplers than that is
refused. In strict mode (CITYSHADE_STRICT_UNIFORMS=1, set by the test suite) a name that the
program's shader files do not declare as a sampler is an error; a declared sampler that a #define
variant compiled away is skipped."""

from __future__ import annotations

import moderngl

from ..errors import ShaderError
from ._programs import declared_samplers, program_path
from ._uniforms import strict

MAX_SAMPLERS = 16  # texture units per stage that OpenGL 4.3 guarantees

# GL_SAMPLER_* / GL_INT_SAMPLER_* / GL_UNSIGNED_INT_SAMPLER_* type enums (plain, shadow, array,
# cube, buffer, rectangle, multisample)
_SAMPLER_TYPES = frozenset(
    [
        *range(0x8B5D, 0x8B65),
        *range(0x8DC0, 0x8DC6),
        *range(0x8DC9, 0x8DD9),
        *range(0x900C, 0x9010),
        *range(0x9108, 0x910E),
    ]
)


def sampler_units(program: moderngl.Program) -> dict[str, int]:
    """The first unit of each active sampler of `program` (made once per program)."""
    extra = program.extra if isinstance(program.extra, dict) else {}
    if "units" not in extra:
        units, unit = {}, 0
        for name in sorted(name for name in program if _is_sampler(program[name])):
            units[name] = unit
            unit += max(program[name].array_length, 1)
        if unit > MAX_SAMPLERS:
            where = extra.get("path", "a program")
            raise ShaderError(
                f"{where} has {unit} active samplers ({', '.join(units)}); OpenGL guarantees "
                f"{MAX_SAMPLERS} per stage: put textures of one kind into a texture array"
            )
        for name, first in units.items():
            length = max(program[name].array_length, 1)
            program[name].value = first if length == 1 else list(range(first, first + length))
        extra["units"] = units
        program.extra = extra
    return extra["units"]


def bind_textures(program: moderngl.Program, textures: dict):
    """Binds each texture (or list of textures, for a sampler array) to the units `program` gave
    the sampler of that name, and points the sampler at them."""
    units = sampler_units(program)
    for name, texture in textures.items():
        if name not in units:
            if strict() and name not in declared_samplers(program):
                raise ShaderError(f"{program_path(program)} declares no sampler {name!r}")
            continue
        group = texture if isinstance(texture, (list, tuple)) else [texture]
        for offset, tex in enumerate(group[: max(program[name].array_length, 1)]):
            tex.use(units[name] + offset)


def _is_sampler(member) -> bool:
    return isinstance(member, moderngl.Uniform) and member.gl_type in _SAMPLER_TYPES
