"""The viewer's per-frame code, in a headless window: draws, moves, toggles."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.render import RenderSettings
from cityshade.viewer import open_viewer


@pytest.fixture(scope="module")
def viewer():
    v = open_viewer(settings=RenderSettings(samples=0), window="headless", size=(160, 96))
    yield v
    v.renderer.release()
    v.wnd.destroy()


def _frame(viewer, t=0.0, dt=0.05) -> np.ndarray:
    viewer.wnd.use()
    viewer.on_render(t, dt)
    data = viewer.wnd.fbo.read(components=3)
    w, h = viewer.wnd.fbo.size
    return np.frombuffer(data, dtype=np.uint8).reshape(h, w, 3)


def test_frames_draw_the_city_and_report_fps(viewer):
    image = _frame(viewer)
    assert image.std() > 10, "the window shows a picture, not a flat colour"
    assert "fps" in viewer.wnd.title and "interiors on" in viewer.wnd.title


def test_wasd_moves_the_camera(viewer):
    start = viewer.fly.position.copy()
    viewer.press("W")
    _frame(viewer, 0.1, 0.1)
    viewer.release("W")
    moved = viewer.fly.position - start
    assert np.dot(moved, viewer.fly.forward) > 1.0


def test_keys_toggle_features_and_change_lights(viewer):
    before = _frame(viewer)
    viewer.press("I")
    assert viewer.renderer.settings.interior_mapping is False
    after = _frame(viewer)
    assert "interiors off" in viewer.wnd.title
    assert np.any(before != after), "turning interiors off changes the picture"
    viewer.press("I")
    viewer.press("RIGHT_BRACKET")
    assert viewer.renderer.settings.lights == pytest.approx(0.6)
    viewer.press("P")
    assert viewer.renderer.settings.depth_prepass is False
    viewer.press("M")
    _frame(viewer)
    assert viewer.renderer.samples == 4 and "MSAA 4x" in viewer.wnd.title


def test_mouse_drag_turns_the_view(viewer):
    yaw = viewer.fly.yaw
    viewer.on_mouse_drag_event(0, 0, 40, 0)
    assert viewer.fly.yaw != yaw
