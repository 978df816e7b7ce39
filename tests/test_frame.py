"""The frame as a whole: GL objects do not pile up from frame to frame."""

from __future__ import annotations

import moderngl
import pytest

from cityshade.render import Renderer, RenderSettings
from cityshade.scene import make_city

# Every Context method that creates a GL object.
CREATORS = ("buffer", "texture", "texture_array", "texture_cube", "depth_texture", "framebuffer", "renderbuffer",
            "depth_renderbuffer", "vertex_array", "program", "compute_shader", "sampler", "query")


class ObjectCounter:
    """Wraps a context's creating methods and counts the objects made through them that are not
    released yet."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self.made = []
        for name in CREATORS:
            setattr(ctx, name, self._wrap(getattr(ctx, name)))

    def detach(self):
        for name in CREATORS:
            delattr(self.ctx, name)  # the class's methods again

    def _wrap(self, create):
        def wrapped(*args, **kwargs):
            obj = create(*args, **kwargs)
            self.made.append(obj)
            return obj

        return wrapped

    def live(self) -> dict[str, int]:
        counts: dict[str, int] = {}
        for obj in self.made:
            if not isinstance(obj.mglo, moderngl.InvalidObject):
                counts[type(obj).__name__] = counts.get(type(obj).__name__, 0) + 1
        return counts


@pytest.fixture(scope="module")
def counted_renderer(gl_context):
    counter = ObjectCounter(gl_context)
    renderer = Renderer((48, 32), RenderSettings(samples=2), ctx=gl_context)
    renderer.set_city(make_city("interior", None))
    yield renderer, counter
    renderer.release()
    counter.detach()


def test_live_gl_objects_stay_flat_over_200_frames(counted_renderer):
    renderer, counter = counted_renderer
    camera = renderer.city.city.camera("front")
    for _ in range(3):  # the first frames compile programs and make targets and vertex arrays
        renderer.render(camera)
    before = counter.live()
    for _ in range(200):
        renderer.draw(camera)
    after = counter.live()
    assert sum(before.values()) > 0, "the counter sees the objects the renderer made"
    assert after == before, f"live GL objects grew over 200 frames: {before} -> {after}"
