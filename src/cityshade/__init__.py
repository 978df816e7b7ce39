"""cityshade: real-time rendering of large virtual cities, facades, interiors, relief and trees per pixel."""

from .api import render, render_city
from .render import Renderer, RenderSettings
from .scene import Camera, City, make_city

__all__ = ["render", "render_city", "Renderer", "RenderSettings", "Camera", "City", "make_city"]
__version__ = "0.1.0"
