"""The city as files other programs read: glTF 2.0 (GLB or .gltf) and 3D Tiles 1.1 tilesets, with
buildings, their facades baked from the grammars, the ground and instanced trees."""

from ._bake import (
    ATLAS_LIMIT,
    Atlas,
    Canvas,
    GpuBaker,
    bake_atlas,
    bake_reference,
    canvases_of,
    has_grammar,
    pack,
    wall_sides,
)
from ._export import FORMATS, check_output, city_document, default_texel, default_texel_note, export_city
from ._gltf import GEOMETRY, TEXTURES, Encoding
from ._serve import tileset_server, write_page
from ._source import ExportCity, crop, layout_export_city, map_export_city, parse_region

__all__ = [
    "check_output",
    "ATLAS_LIMIT",
    "FORMATS",
    "Atlas",
    "Canvas",
    "Encoding",
    "GEOMETRY",
    "TEXTURES",
    "ExportCity",
    "GpuBaker",
    "bake_atlas",
    "bake_reference",
    "canvases_of",
    "has_grammar",
    "city_document",
    "default_texel",
    "default_texel_note",
    "crop",
    "export_city",
    "layout_export_city",
    "map_export_city",
    "pack",
    "parse_region",
    "tileset_server",
    "wall_sides",
    "write_page",
]
