"""Every named camera of every city (and of the tree scene) renders a finite, non-flat picture.
Marked slow: one city set-up per city (`make test-slow`)."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from cityshade.render import Renderer, RenderSettings
from cityshade.scene import CITIES, make_city
from cityshade.trees import park_scene
from render_checks import render_finite

pytestmark = pytest.mark.slow
SIZE = (64, 40)


@pytest.mark.parametrize("name", [*sorted(CITIES), "trees"])
def test_every_camera_renders(gl_context, name, output_dir):
    city = park_scene() if name == "trees" else make_city(name)
    renderer = Renderer(SIZE, RenderSettings(samples=0), ctx=gl_context)
    renderer.set_city(city)
    pictures = {camera: render_finite(renderer, city.camera(camera)) for camera in city.viewpoints}
    renderer.release()
    Image.fromarray(np.hstack(list(pictures.values()))).save(output_dir / f"cameras_{name}.png")
    for camera, image in pictures.items():
        assert image.std() > 8, f"{name} {camera}: a flat picture"
    assert len({image.tobytes() for image in pictures.values()}) == len(pictures), "two cameras show the same"
