"""Facade relief from compressed facade displacement maps (Ali, Ye, Razdan, Wonka 2009).

Detail maps D (depth) and M (material) per facade, the free-box acceleration A, exact SVD and
binary factorisations, bit packing, the .cfdm file format and a numpy reference ray tracer.
"""

from ._boxes import free_boxes
from ._cache import CACHE_ENV, cache_dir, cached_arrays, cached_compress, smallest_compression
from ._city import FACADE_RELIEF, RELIEF_SHAPES, RELIEF_STYLES, CityRelief, relief_atlas, stack_bmf, switch_distance
from ._compress import MAP_NAMES, CompressedFacade, compress, detail_matrices, digest
from ._factor import MAX_TERMS, METHODS, Factors, factorize, greedy_biclique
from ._format import VERSION, from_bytes, read_compressed, to_bytes, write_compressed
from ._gpu import RENDERERS, GpuFacade, decode_on_gpu, renderer_defines
from ._grammar_source import PROFILE, StyleOpenings, grammar_maps, style_openings
from ._layout import DEPTH_UNIT, PAPER_FACADES, PAPER_TEXEL, FacadeLayout, generate_bay, generate_facade, paper_facade
from ._limits import check_facade_texels
from ._maps import GLASS, MATERIALS, DetailMaps, load_png_maps, save_png_maps
from ._mesh import relief_mesh
from ._pack import pack_bits, unpack_bits
from ._reference import RELIEF_FACE_CODES, Hits, trace_reference
from ._view import (
    FRAME_DTYPE,
    FacadeImages,
    FacadeView,
    MeshFacade,
    draw_facades,
    facade_camera,
    slab_faces,
    trace_view,
)

__all__ = [
    "grammar_maps",
    "MAX_TERMS",
    "DEPTH_UNIT",
    "PAPER_TEXEL",
    "check_facade_texels",
    "FACADE_RELIEF",
    "RELIEF_SHAPES",
    "RELIEF_STYLES",
    "CityRelief",
    "relief_atlas",
    "stack_bmf",
    "switch_distance",
    "CACHE_ENV",
    "cache_dir",
    "cached_arrays",
    "cached_compress",
    "smallest_compression",
    "PROFILE",
    "StyleOpenings",
    "style_openings",
    "free_boxes",
    "MAP_NAMES",
    "CompressedFacade",
    "compress",
    "detail_matrices",
    "digest",
    "METHODS",
    "Factors",
    "factorize",
    "greedy_biclique",
    "VERSION",
    "from_bytes",
    "read_compressed",
    "to_bytes",
    "write_compressed",
    "PAPER_FACADES",
    "FacadeLayout",
    "generate_bay",
    "generate_facade",
    "paper_facade",
    "GLASS",
    "MATERIALS",
    "DetailMaps",
    "load_png_maps",
    "save_png_maps",
    "pack_bits",
    "unpack_bits",
    "RENDERERS",
    "GpuFacade",
    "decode_on_gpu",
    "renderer_defines",
    "RELIEF_FACE_CODES",
    "Hits",
    "trace_reference",
    "relief_mesh",
    "FRAME_DTYPE",
    "FacadeImages",
    "FacadeView",
    "MeshFacade",
    "draw_facades",
    "facade_camera",
    "slab_faces",
    "trace_view",
]
