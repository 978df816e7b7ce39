"""The one way uniforms are set: by name, with numpy matrices written column-major.

A name the linked program lacks is skipped: the frame hands its shared values to every program and
a #define variant may compile a uniform away. In strict mode (CITYSHADE_STRICT_UNIFORMS=1, which
the test suite sets) a name that no shader file declares at all is an error, so a misspelt uniform
fails instead of doing nothing."""

from __future__ import annotations

import os

import numpy as np

from ..errors import ShaderError
from ._programs import declared_uniforms

STRICT_ENV = "CITYSHADE_STRICT_UNIFORMS"


def strict() -> bool:
    return os.environ.get(STRICT_ENV, "") not in ("", "0")


def set_uniforms(program, **values):
    for name, value in values.items():
        if name not in program:
            if strict() and name not in declared_uniforms():
                raise ShaderError(f"no shader declares a uniform {name!r}")
            continue
        if isinstance(value, np.ndarray):
            if value.shape == (4, 4):
                program[name].write(value.T.astype("f4").tobytes())  # GLSL matrices are column-major
            else:
                program[name].value = tuple(float(v) for v in value.ravel())
        else:
            program[name].value = value
