"""The frame: passes in order (see _frame.py), the Renderer that runs them, and their settings."""

from ._daylight import Daylight, parse_time
from ._guessed import guessed_aov
from ._renderer import Renderer
from ._settings import RenderSettings

__all__ = ["Daylight", "guessed_aov", "parse_time", "Renderer", "RenderSettings"]
