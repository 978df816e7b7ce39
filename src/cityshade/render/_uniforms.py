"""Texture units: fixed, so every program samples the same unit for the same texture."""

UNIT_ENV, UNIT_FACADE, UNIT_CEILING, UNIT_FLOOR, UNIT_WALL_X, UNIT_WALL_Z, UNIT_ATLAS, UNIT_SPRITES, UNIT_CURTAIN = range(9)
UNIT_HDR = 10
UNIT_SHADOW = (11, 12, 13)  # the three shadow cascades
UNIT_BARK_COLOR, UNIT_BARK_NORMAL, UNIT_LEAF_COLOR, UNIT_LEAF_DETAIL = range(14, 18)
UNIT_GRAMMAR = 24  # facade grammar: rules, noise, tiles on 24, 25, 26
UNIT_RELIEF = 27  # relief facades: BMF X, Y, S of D, M, A on 27..35
UNIT_GRAMMAR_DEFERRED = 36  # deferred grammar pass: its G-buffer on 36..39, its results on 40, 41
