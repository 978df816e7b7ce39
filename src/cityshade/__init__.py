"""cityshade: real-time rendering of large virtual cities, facades, interiors, relief and trees per pixel."""

from . import shader_constants  # noqa: F401  (declares the constants every shader program gets)
from ._version import __version__  # noqa: F401
from .api import render_city, render_image, show, view_widget
from .render import Renderer, RenderSettings
from .scene import Camera, City, make_city

__all__ = [
    "render_image",
    "render_city",
    "show",
    "view_widget",
    "Renderer",
    "RenderSettings",
    "Camera",
    "City",
    "make_city",
]
