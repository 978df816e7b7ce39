"""The one way uniforms are set: by name, with numpy matrices written column-major.

A name that the program's shader files declare but its #define variant compiled away is skipped.
In strict mode (CITYSHADE_STRICT_UNIFORMS=1, which the test suite sets) a name that the program's
files do not declare is an error, so a misspelt uniform, or a value meant for another program,
fails instead of doing nothing. Values that several programs share go into a uniform block
(gl.FRAME_BLOCK, gl.SHADING_BLOCK), never into one dictionary handed to each."""

from __future__ import annotations

import os

import numpy as np

from ..errors import ShaderError
from ._programs import declared_uniforms, program_path

STRICT_ENV = "CITYSHADE_STRICT_UNIFORMS"


def strict() -> bool:
    return os.environ.get(STRICT_ENV, "") not in ("", "0")


def set_uniforms(program, **values):
    for name, value in values.items():
        if name not in program:
            if strict() and name not in declared_uniforms(program):
                raise ShaderError(f"{program_path(program)} declares no uniform {name!r}")
            continue
        if isinstance(value, np.ndarray):
            if value.shape == (4, 4):
                program[name].write(value.T.astype("f4").tobytes())  # GLSL matrices are column-major
            else:
                program[name].value = tuple(float(v) for v in value.ravel())
        else:
            program[name].value = value
