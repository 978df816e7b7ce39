"""The frame layer under the techniques: passes and the GL state they draw with, the targets they
declare, the frame's view and settings, what a frame hands every pass, and the culling any pass
can use (docs/frame.md)."""

from .._values import parse_time  # "HH:MM" as the hours RenderSettings.time_of_day takes
from ._context import Frame, FrameView
from ._culling import BuildingChunks, boxes_visible, building_cells, chunk_vertices, frustum_planes
from ._daylight import Daylight
from ._gpu_culling import (
    BOX_DTYPE,
    COMMAND_WORDS,
    OCCLUDER_SIZE,
    hiz_twin,
    run_cull,
    visible_twin,
)
from ._passes import Pass, declared_targets, run_passes
from ._settings import CommandFlag, RenderSettings
from ._state import GLState
from ._targets import HDR, IDS, FrameTargets, Target

__all__ = [
    "Frame",
    "FrameView",
    "BuildingChunks",
    "boxes_visible",
    "building_cells",
    "chunk_vertices",
    "frustum_planes",
    "Daylight",
    "BOX_DTYPE",
    "COMMAND_WORDS",
    "OCCLUDER_SIZE",
    "hiz_twin",
    "run_cull",
    "visible_twin",
    "Pass",
    "declared_targets",
    "run_passes",
    "CommandFlag",
    "RenderSettings",
    "parse_time",
    "GLState",
    "HDR",
    "IDS",
    "FrameTargets",
    "Target",
]
