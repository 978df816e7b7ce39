"""The Python API: `render_image` and `render_city`, and for notebooks `show` (a picture Jupyter
displays inline) and `view_widget` (the city in a jupyter_rfb widget)."""

from ._notebook import Picture, show, view_widget
from ._render import AOVS, render_city, render_image

__all__ = ["AOVS", "Picture", "render_city", "render_image", "show", "view_widget"]
