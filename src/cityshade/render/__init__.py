"""The frame: passes in order (see _frame.py and docs/frame.md), the Renderer that runs them, and their settings."""

from ..frame import Daylight, RenderSettings
from ._building_lod import bay_mean
from ._facades import FACADE_KINDS, FacadeKind, GrammarFitWarning, assign_facades, choose_facade, styles_with_relief
from ._frame import frame_passes, id_passes
from ._guessed import guessed_aov
from ._quality import QUALITY_STEPS, QualityStep, quality_status, with_quality_steps
from ._renderer import Renderer
from ._resolution import ResolutionScale
from ._streaming import check_memory_budget, format_bytes
from ._tile_cache import (
    TILE_SIZE,
    CacheProblem,
    TileCache,
    open_tiles,
    read_tile,
    source_identity,
)
from ._tile_writer import check_cache_folder, mesh_tile, on_ray, run_here, write_tiles
from ._upscale import upscale, upscale_reference

__all__ = [
    "bay_mean",
    "Daylight",
    "FACADE_KINDS",
    "FacadeKind",
    "assign_facades",
    "GrammarFitWarning",
    "choose_facade",
    "styles_with_relief",
    "guessed_aov",
    "frame_passes",
    "id_passes",
    "QUALITY_STEPS",
    "QualityStep",
    "quality_status",
    "with_quality_steps",
    "Renderer",
    "RenderSettings",
    "ResolutionScale",
    "check_memory_budget",
    "format_bytes",
    "CacheProblem",
    "TileCache",
    "open_tiles",
    "write_tiles",
    "mesh_tile",
    "run_here",
    "on_ray",
    "read_tile",
    "TILE_SIZE",
    "check_cache_folder",
    "source_identity",
    "upscale",
    "upscale_reference",
]
