"""Procedural, deterministic textures: rooms, facade bay, sky, furniture sprites, curtains.

Arrays are indexed [..., row, col, channel] with row 0 at the bottom (v = 0), so
they upload to OpenGL as they are. Colours are sRGB-encoded uint8 unless stated
(the environment map is linear HDR float32). Results are cached and read-only.
"""

from ._atlas import room_atlas
from ._curtain import curtain_texture
from ._facade import facade_texture
from ._rooms import FACES, ROOM_STYLES, room_textures
from ._sky import SUN_RADIANCE, SUN_RADIUS, cube_directions, environment_cubemap, sky_colour, sun_colour
from ._sprites import SPRITE_KINDS, furniture_sprites
from ._tiles import LABEL_COLOURS, LABELS, TILE_INDEX, TILES, TileArray, tile_array

__all__ = [
    "FACES",
    "LABEL_COLOURS",
    "LABELS",
    "ROOM_STYLES",
    "SPRITE_KINDS",
    "TILES",
    "TILE_INDEX",
    "TileArray",
    "cube_directions",
    "curtain_texture",
    "environment_cubemap",
    "facade_texture",
    "furniture_sprites",
    "room_atlas",
    "room_textures",
    "sky_colour",
    "sun_colour",
    "SUN_RADIANCE",
    "SUN_RADIUS",
    "tile_array",
]
