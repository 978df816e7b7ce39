"""Setting uniforms by name, skipping those a shader variant compiled away."""

from __future__ import annotations

import numpy as np


def set_uniforms(program, **values):
    for name, value in values.items():
        if name not in program:
            continue
        if isinstance(value, np.ndarray):
            if value.shape == (4, 4):
                program[name].write(value.T.astype("f4").tobytes())  # GLSL matrices are column-major
            else:
                program[name].value = tuple(float(v) for v in value.ravel())
        else:
            program[name].value = value


# Texture units: fixed, so every program samples the same unit for the same texture.
UNIT_ENV, UNIT_FACADE, UNIT_CEILING, UNIT_FLOOR, UNIT_WALL_X, UNIT_WALL_Z, UNIT_ATLAS, UNIT_SPRITES, UNIT_CURTAIN = range(9)
UNIT_HDR = 10
UNIT_SHADOW = (11, 12, 13)  # the three shadow cascades
UNIT_BARK_COLOR, UNIT_BARK_NORMAL, UNIT_LEAF_COLOR, UNIT_LEAF_DETAIL = range(14, 18)
UNIT_GRAMMAR = 24  # facade grammar: rules, noise, tiles on 24, 25, 26
UNIT_RELIEF = 27  # relief facades: BMF X, Y, S of D, M, A on 27..35
UNIT_GRAMMAR_DEFERRED = 36  # deferred grammar pass: its G-buffer on 36..39, its results on 40, 41
