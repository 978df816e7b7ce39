"""The viewer's per-frame code, in a headless window: draws, moves, toggles."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from moderngl_window.context.base.keys import BaseKeys
from PIL import Image

from cityshade.commands import main
from cityshade.errors import UsageError
from cityshade.interior import FACE_CODES
from cityshade.maps import city_from_map
from cityshade.render import Renderer, RenderSettings, open_tiles, upscale_reference
from cityshade.scene import Camera
from cityshade.viewer import KEY_NAMES, FlyCamera, open_viewer

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


@pytest.fixture(scope="module")
def viewer():
    v = open_viewer(settings=RenderSettings(samples=0), window="headless", size=(160, 96), target_fps=None)
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


@pytest.mark.parametrize("key, direction", [("S", "back"), ("A", "left"), ("D", "right"), ("Q", "down"), ("E", "up")])
def test_every_movement_key_moves_its_way(viewer, key, direction):
    viewer.fly.position = viewer.fly.position + np.array([0.0, 20.0, 0.0])  # room to go down
    start, forward = viewer.fly.position.copy(), viewer.fly.forward
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    viewer.press(key)
    viewer.fly.move(
        ("W" in viewer.held) - ("S" in viewer.held),
        ("D" in viewer.held) - ("A" in viewer.held),
        ("E" in viewer.held) - ("Q" in viewer.held),
        0.1,
    )
    viewer.release(key)
    moved = viewer.fly.position - start
    axis = {
        "back": -forward,
        "left": -right,
        "right": right,
        "down": np.array([0.0, -1.0, 0.0]),
        "up": np.array([0.0, 1.0, 0.0]),
    }[direction]
    assert np.dot(moved, axis) > 1.0 and np.linalg.norm(moved - axis * np.dot(moved, axis)) < 1e-6


@pytest.mark.parametrize("key, setting", [("F", "furniture"), ("L", "lod"), ("C", "curtains"), ("P", "depth_prepass")])
def test_toggle_keys_flip_their_setting_and_back(viewer, key, setting):
    before = getattr(viewer.renderer.settings, setting)
    viewer.press(key)
    viewer.release(key)
    assert getattr(viewer.renderer.settings, setting) is (not before)
    viewer.press(key)
    viewer.release(key)
    assert getattr(viewer.renderer.settings, setting) is before


def test_bracket_keys_step_the_lit_share_within_0_and_1(viewer):
    viewer.chosen = viewer.chosen.with_(lights=0.1)
    viewer.press("LEFT_BRACKET")
    assert viewer.renderer.settings.lights == 0.0
    viewer.press("LEFT_BRACKET")
    assert viewer.renderer.settings.lights == 0.0, "never below 0"
    for _ in range(12):
        viewer.press("RIGHT_BRACKET")
    assert viewer.renderer.settings.lights == 1.0, "never above 1"
    assert "c=1.00" in viewer.status()


def test_time_keys_move_the_sun_and_change_the_picture(viewer):
    viewer.chosen = viewer.chosen.with_(time_of_day=12.0, lights=0.5)
    noon = _frame(viewer)
    for _ in range(24):  # six hours later: 18:00
        viewer.press("T")
    assert viewer.renderer.settings.time_of_day == pytest.approx(18.0) and "18:00" in viewer.status()
    evening = _frame(viewer)
    assert np.abs(noon.astype(int) - evening.astype(int)).mean() > 5, "the light changes with the hour"
    viewer.press("G")
    assert viewer.renderer.settings.time_of_day == pytest.approx(17.75)
    viewer.chosen = viewer.chosen.with_(time_of_day=0.0)
    viewer.press("G")
    assert viewer.renderer.settings.time_of_day == pytest.approx(23.75), "the clock wraps around midnight"


def test_window_key_events_reach_the_actions(viewer, monkeypatch):
    """Keys arrive as the window backend's codes (here a table of distinct ones: the headless
    backend has no keyboard); press and release map to the same actions."""
    codes = {name: 100 + i for i, name in enumerate(KEY_NAMES + ("Z",))}
    monkeypatch.setattr(viewer.wnd, "keys", type("Codes", (BaseKeys,), codes))
    keys = viewer.wnd.keys
    before = viewer.renderer.settings.curtains
    viewer.on_key_event(keys.C, keys.ACTION_PRESS, None)
    assert viewer.renderer.settings.curtains is (not before) and "C" in viewer.held
    viewer.on_key_event(keys.C, keys.ACTION_RELEASE, None)
    assert "C" not in viewer.held
    viewer.on_key_event(keys.C, keys.ACTION_PRESS, None)
    viewer.on_key_event(keys.C, keys.ACTION_RELEASE, None)
    assert viewer.renderer.settings.curtains is before
    viewer.on_key_event(keys.Z, keys.ACTION_PRESS, None)  # not bound: nothing happens
    assert "Z" not in viewer.held


def test_escape_closes_the_window():
    v = open_viewer(settings=RenderSettings(samples=0), window="headless", size=(32, 24))
    assert not v.wnd.is_closing
    v.press("ESCAPE")
    assert v.wnd.is_closing
    v.renderer.release()
    v.wnd.destroy()


def test_a_target_frame_rate_draws_fewer_pixels_and_stretches_them(viewer):
    """At scale 0.5 the frame is drawn at half the window's size and the window shows it stretched
    (the upscale's numpy twin); the title shows the scale; full resolution again without a target."""
    from cityshade.render import ResolutionScale

    viewer.resolution = ResolutionScale(15.0, scale=0.5, settle=10_000)  # held at 0.5 for the check
    window = _frame(viewer)
    assert viewer.renderer.size == (80, 48)
    drawn = viewer.renderer.targets["display"].read()[..., :3]
    expected = upscale_reference(drawn, (160, 96))
    differing = int(np.any(np.abs(window.astype(int) - expected[::-1]) > 1, axis=-1).sum())
    assert differing == 0, f"{differing} window pixels differ from the stretched frame"
    assert "scale 0.50 (target 15 fps)" in viewer.wnd.title
    viewer.resolution = None
    _frame(viewer)
    assert viewer.renderer.size == (160, 96) and "scale" not in viewer.wnd.title


def test_a_slow_frame_rate_lowers_the_scale(viewer):
    from cityshade.render import ResolutionScale

    viewer.resolution = ResolutionScale(1000.0, settle=2)  # no frame is that fast
    for k in range(4):
        _frame(viewer, 0.1 * k)
    assert viewer.resolution.scale < 1.0 and viewer.renderer.size[0] < 160
    viewer.resolution = None


@pytest.mark.parametrize("rate", [-1.0, float("nan")])
def test_bad_target_rates_are_refused_before_a_window_opens(rate):
    with pytest.raises(UsageError, match="target frame rate"):
        open_viewer(window="headless", size=(160, 96), target_fps=rate)


def test_quality_steps_engage_when_too_slow_show_in_the_title_and_release_to_the_same_picture(viewer):
    """Held at full resolution (minimum scale 1), a target no frame meets takes every quality step,
    one per frame; the title names them and the frame changes. A target every frame meets
    releases them all, and the window shows the very picture it showed before they were taken."""
    from cityshade.render import QUALITY_STEPS, ResolutionScale

    def frames(count):
        for _ in range(count):
            image = _frame(viewer, 0.0)
        return image

    viewer.resolution = ResolutionScale(1e-6, minimum=1.0, settle=1, steps=len(QUALITY_STEPS))
    before = frames(4)  # every shadow cascade redrawn
    assert viewer.resolution.level == 0
    viewer.resolution.target_fps = 1e6
    lowest = frames(len(QUALITY_STEPS) + 4)
    assert viewer.resolution.level == len(QUALITY_STEPS)
    assert "quality -5: shadows every 2nd frame, far trees fade sooner" in viewer.wnd.title
    s, trees = viewer.renderer.settings, viewer.renderer.trees.settings
    assert s.shadow_refresh == 2 and not s.relief and not s.shadows and not trees.relief
    assert viewer.chosen.relief and viewer.chosen.shadows, "the chosen settings are kept"
    assert np.any(lowest != before)
    viewer.resolution.target_fps = 1e-6
    frames(len(QUALITY_STEPS))
    assert viewer.resolution.level == 0
    after = frames(4)  # every cascade redrawn at full quality
    assert "quality" not in viewer.wnd.title
    differing = int(np.any(after != before, axis=-1).sum())
    assert differing == 0, f"{differing} pixels differ at full quality after the steps were released"
    viewer.resolution = None


# -- the viewer on a tile cache, through `cityshade view --screenshot` ----------------------------

MAPS = Path(__file__).parents[1] / "data" / "maps"
SHOT = (96, 64)
NOON = "12:00"
EYE_HEIGHT = "24.9385,60.1701,2,90"  # 2 m above the ground west of the tagged map's buildings, facing east
COLOUR_TOLERANCE = 12  # of 255: the viewer's camera, rebuilt from yaw and pitch, moves edges by a hair


def test_fly_camera_keeps_the_start_cameras_lens():
    """A whole city's aerial view starts kilometres away with a far plane to match: the viewer draws
    through that lens (a street view's 4 km far plane drew nothing but the cleared frame), with the
    near plane and shadow reach following the height as it flies down."""
    start = Camera((-4500.0, 4500.0, 8.0), (-6.0, 0.0, 8.0), fov_y=50.0, near=159.0, far=1e6, shadow_far=12700.0)
    fly = FlyCamera(start)
    kept = fly.camera()
    assert (kept.near, kept.far, kept.fov_y, kept.shadow_far) == (159.0, 1e6, 50.0, 12700.0)
    assert np.allclose(kept.eye, start.eye) and np.allclose(kept.forward, start.forward)
    fly.position = np.array([0.0, 2.0, 0.0])
    low = fly.camera()
    assert low.far == 1e6 and low.near == pytest.approx(0.3) and low.shadow_far is None
    fly.position = np.array([0.0, 450.0, 0.0])
    assert fly.camera().near == pytest.approx(15.9) and fly.camera().shadow_far == pytest.approx(1270.0)


@pytest.fixture(scope="module")
def tagged_cache(tmp_path_factory):
    folder = tmp_path_factory.mktemp("tagged") / "tiles"
    assert main(["tile", str(MAPS / "tagged.osm"), "--out", str(folder)]) == 0
    return folder


@pytest.mark.slow  # three contexts' shaders compiled: about 10 s of CPU
def test_view_screenshot_of_tiles_draws_the_city_and_the_sky_as_render_does(tagged_cache, tmp_path, capsys):
    """`view --tiles DIR --screenshot` draws the streamed city as `render --tiles` of the same view
    (render_city's still, in process):
    the pixels that show buildings and those that show the sky (from the still's id AOV) are there,
    and the two pictures agree within a small tolerance (the viewer's camera is rebuilt from yaw and
    pitch, so a few edge pixels may fall the other way)."""
    size, camera = f"{SHOT[0]}x{SHOT[1]}", EYE_HEIGHT
    shot = tmp_path / "view.png"
    view = ["view", "--tiles", str(tagged_cache), "--size", size, "--camera", camera, "--time", NOON]
    assert main([*view, "--screenshot", str(shot), "--frames", "3", "--target-fps", "0"]) == 0
    out = capsys.readouterr().out
    assert f"wrote {shot} ({size}): frame 3 of a headless window" in out and " fps after the first" in out
    assert "tiles 3/3" in out
    viewed = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    rendered, ids = _still(tagged_cache, camera)
    buildings, sky = ids[..., 2] > 0, ids[..., 0] == FACE_CODES["FACE_NONE"]
    assert sky.sum() > 0.1 * sky.size, "the view across the ground shows the sky"
    assert np.all(viewed[sky][:, 2] > viewed[sky][:, 0]), "the sky is blue"
    assert buildings.sum() > 0.01 * buildings.size, "the view shows buildings"
    off = np.abs(viewed - rendered).max(axis=-1)
    differing = int(np.count_nonzero(off > COLOUR_TOLERANCE))
    assert differing <= 0.005 * off.size, f"{differing} of {off.size} pixels differ by more than {COLOUR_TOLERANCE}"
    for name, where in (("building", buildings), ("sky", sky)):
        bad = int(np.count_nonzero(off[where] > COLOUR_TOLERANCE))
        assert bad <= 0.01 * where.sum(), f"{bad} of {where.sum()} {name} pixels differ by more than {COLOUR_TOLERANCE}"


def _still(folder: Path, camera: str) -> tuple[np.ndarray, np.ndarray]:
    """The picture and the id AOV of the cache's `camera` as `render --tiles --samples 0` draws it."""
    tiles = open_tiles(folder)
    city, name, sky = city_from_map(None, camera, None, NOON, city=tiles.city)
    renderer = Renderer(SHOT, RenderSettings(samples=0, time_of_day=12.0, **sky))
    try:
        renderer.set_tiles(tiles)
        view = city.camera(name)
        renderer.wait_for_tiles(view)
        return renderer.render(view).astype(int), renderer.render_ids(view)
    finally:
        renderer.release()


@pytest.mark.parametrize(
    "args, message",
    [
        (["--screenshot", "x.png", "--frames", "0"], "invalid --frames '0'"),
        (["--frames", "3"], "--frames N counts the frames of a --screenshot FILE"),
    ],
)
def test_view_screenshot_refuses_bad_frame_counts(capsys, args, message):
    assert main(["view", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"cityshade: error: {message}") and "\n" not in err
