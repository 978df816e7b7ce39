"""What the tests use of cityshade.render's internals: its numpy twins and the parts they check one by one."""

from ._building_lod import grammar_colours
from ._city_gpu import GROUND_MARGIN, ground_vertices
from ._facades import NARROW_FACES
from ._godrays import god_ray_uniforms, god_rays_reference
from ._lod_colours import NOT_READY, grammar_colours_gpu
from ._night_sky import night_amount
from ._renderer import frame_bytes_per_pixel
from ._shadows import CascadedShadows
from ._sky_discs import sky_disc_uniforms, sky_discs_reference
from ._streaming import StreamedCityGPU, TileStreamer
from ._street_lights import CELL, lamps_reaching_cell, light_grid
from ._tile_cache import GROUND_DTYPE, SLOT_UNIT, ground_offset, read_tile, slot_bytes
from ._visibility import building_boxes, building_ranges

__all__ = [
    "CELL",
    "CascadedShadows",
    "GROUND_DTYPE",
    "GROUND_MARGIN",
    "NARROW_FACES",
    "NOT_READY",
    "SLOT_UNIT",
    "StreamedCityGPU",
    "TileStreamer",
    "building_boxes",
    "building_ranges",
    "frame_bytes_per_pixel",
    "god_ray_uniforms",
    "night_amount",
    "god_rays_reference",
    "grammar_colours",
    "grammar_colours_gpu",
    "ground_offset",
    "ground_vertices",
    "lamps_reaching_cell",
    "light_grid",
    "read_tile",
    "sky_disc_uniforms",
    "sky_discs_reference",
    "slot_bytes",
]
