"""The frame: passes in order (see _frame.py and docs/frame.md), the Renderer that runs them, and their settings."""

from ._daylight import Daylight, parse_time
from ._facades import FACADE_KINDS, FacadeKind, assign_facades, choose_facade
from ._frame import FrameTargets, GLState, Pass, frame_passes, id_passes
from ._renderer import Renderer
from ._settings import RenderSettings

__all__ = ["Daylight", "parse_time", "FACADE_KINDS", "FacadeKind", "assign_facades", "choose_facade", "FrameTargets", "GLState", "Pass", "frame_passes", "id_passes", "Renderer",
           "RenderSettings"]
