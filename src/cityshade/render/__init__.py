"""The frame: passes in order (see _frame.py), the Renderer that runs them, and their settings."""

from ._culling import boxes_visible, frustum_planes
from ._daylight import Daylight, parse_time
from ._renderer import Renderer
from ._settings import RenderSettings

__all__ = ["boxes_visible", "frustum_planes", "Daylight", "parse_time", "Renderer", "RenderSettings"]
