"""The viewer: the city in a window, WASD + mouse look (`cityshade view`). The same Renderer draws every frame
as in headless rendering; only the context comes from the window."""

from __future__ import annotations

import math
import time
from dataclasses import replace

import moderngl_window as mglw
import numpy as np

from .errors import CityshadeError
from .render import (
    QUALITY_STEPS,
    Renderer,
    RenderSettings,
    ResolutionScale,
    check_memory_budget,
    format_bytes,
    quality_status,
    upscale,
    with_quality_steps,
)
from .scene import Camera, City, make_city

MOVE_SPEED = 25.0  # metres per second
LOOK_SPEED = 0.15  # degrees per pixel of mouse motion
TIME_STEP = 0.25  # hours per key press
DEFAULT_TARGET_FPS = 15.0
MIN_NEAR = 0.3  # metres: the nearest near plane a camera flown down to the street gets
STREET_SHADOWS = 160.0  # metres: below this reach the renderer's default (made for street views) is used

TOGGLES = {"I": "interior_mapping", "P": "depth_prepass", "F": "furniture", "L": "lod", "C": "curtains"}
KEY_NAMES = (
    "W",
    "A",
    "S",
    "D",
    "Q",
    "E",
    "I",
    "P",
    "F",
    "L",
    "C",
    "M",
    "T",
    "G",
    "LEFT_BRACKET",
    "RIGHT_BRACKET",
    "ESCAPE",
)
HELP = (
    "WASD move, Q/E down/up, drag mouse to look, I interiors, P prepass, F furniture, L LOD, "
    "C curtains, M MSAA, [ ] fewer/more lit rooms, T/G later/earlier, Esc quit"
)


class FlyCamera:
    """Position + yaw/pitch, turned into a look-at Camera each frame with the start camera's lens:
    its field of view and far plane, and its near plane and shadow reach scaled with the height
    (an aerial view of a whole city starts kilometres away, far beyond a street view's 4 km far
    plane; flown down to the street, a near plane of a hundred metres would cut the street away)."""

    def __init__(self, start: Camera):
        self.start = start
        self.position = start.eye.copy()
        forward = start.forward
        self.yaw = math.degrees(math.atan2(forward[0], -forward[2]))
        self.pitch = math.degrees(math.asin(np.clip(forward[1], -1, 1)))
        self.fov = start.fov_y

    @property
    def forward(self) -> np.ndarray:
        y, p = math.radians(self.yaw), math.radians(self.pitch)
        return np.array([math.sin(y) * math.cos(p), math.sin(p), -math.cos(y) * math.cos(p)])

    def move(self, forward: float, right: float, up: float, seconds: float):
        f = self.forward
        side = np.cross(f, [0.0, 1.0, 0.0])
        side /= np.linalg.norm(side)
        self.position = self.position + (f * forward + side * right + np.array([0, up, 0])) * MOVE_SPEED * seconds
        self.position[1] = max(self.position[1], 0.5)

    def look(self, dx: float, dy: float):
        self.yaw += dx * LOOK_SPEED
        self.pitch = float(np.clip(self.pitch - dy * LOOK_SPEED, -89.0, 89.0))

    def camera(self) -> Camera:
        start = self.start
        scale = max(float(self.position[1]), 1.0) / max(float(start.position[1]), 1.0)
        reach = None if start.shadow_far is None else start.shadow_far * scale
        return replace(
            start,
            position=tuple(self.position),
            target=tuple(self.position + self.forward),
            fov_y=self.fov,
            near=max(start.near * scale, min(start.near, MIN_NEAR)),
            shadow_far=reach if reach is not None and reach > STREET_SHADOWS else None,
        )


class CityViewer(mglw.WindowConfig):
    gl_version = (4, 3)
    title = "cityshade"
    window_size = (1280, 720)
    aspect_ratio = None
    resizable = True
    vsync = False
    city: str | City = "default"
    camera_name = "street"
    start_settings = RenderSettings()
    sky = None  # hours -> sun and moon settings, for a city from a map
    target_fps: float | None = DEFAULT_TARGET_FPS  # None: always the window's full resolution
    tiles = None  # a tile cache to stream the city from (render.open_tiles), instead of `city`
    memory_budget: int | None = None  # bytes of tiles resident at most (None: all)
    stop_after: int | None = None  # frames to draw before the window closes by itself (a screenshot)

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.renderer = Renderer(self.wnd.buffer_size, self.start_settings, ctx=self.ctx)
        if self.tiles is not None:
            city = self.tiles.city
            self.renderer.set_tiles(self.tiles, self.memory_budget)
        else:
            city = self.city if isinstance(self.city, City) else make_city(self.city)
            self.renderer.set_city(city)
        self.fly = FlyCamera(city.camera(self.camera_name))
        if self.stop_after is not None:  # a screenshot shows the view streamed in, as a still does
            self.renderer.wait_for_tiles(self.fly.camera())
        self.held: set = set()
        self.frame_times: list[float] = []
        self.lights = self.renderer.settings.lights
        self.last_image = None  # with stop_after: the last frame drawn, HxWx3 uint8, top row first
        self.frames_drawn = 0
        self.seconds_after_first = 0.0  # drawing the frames after the first (which compiles and uploads)
        self.resolution = ResolutionScale(self.target_fps, steps=len(QUALITY_STEPS)) if self.target_fps else None
        # what the keys choose; the frame-rate controller's quality steps are taken from these
        self.chosen = self.start_settings
        self.chosen_trees = self.renderer.trees.settings

    # --- per frame -----------------------------------------------------------------------
    def on_render(self, time: float, frametime: float):
        forward = ("W" in self.held) - ("S" in self.held)
        right = ("D" in self.held) - ("A" in self.held)
        up = ("E" in self.held) - ("Q" in self.held)
        self.fly.move(forward, right, up, min(frametime, 0.1))
        self.chosen = replace(self.chosen, animation_time=time)
        seconds = self.draw_frame()
        self.frames_drawn += 1
        self.seconds_after_first += seconds if self.frames_drawn > 1 else 0.0
        self.frame_times = (self.frame_times + [seconds])[-30:]
        if self.resolution is not None:
            self.resolution.update(self.frame_times[-1])
        self.wnd.title = self.status()
        if self.stop_after is not None and self.frames_drawn >= self.stop_after:
            self.last_image = self.read_window()
            self.wnd.close()

    def read_window(self) -> np.ndarray:
        """What the window shows now (its back buffer, before the swap), HxWx3 uint8, top row first."""
        width, height = self.wnd.fbo.size
        data = self.wnd.fbo.read(viewport=(0, 0, width, height), components=3)
        return np.frombuffer(data, np.uint8).reshape(height, width, 3)[::-1].copy()

    def draw_frame(self) -> float:
        """Draws the view into the window, at the internal resolution the frame rate allows and
        stretched to the window; returns the seconds it took."""
        start = time.perf_counter()
        window = tuple(self.wnd.buffer_size)
        size = self.resolution.size(window) if self.resolution is not None else window
        self.renderer.resize(size)
        self._apply_settings()
        if size == window:
            self.renderer.draw(self.fly.camera(), framebuffer=self.wnd.fbo)
        else:
            display = self.renderer.draw(self.fly.camera())
            upscale(self.renderer.programs, display.colors[0], self.wnd.fbo)
            self.ctx.finish()
        return time.perf_counter() - start

    def _apply_settings(self):
        """The chosen settings, with the shadow maps' resolution following the scale and the
        quality steps the frame rate asks for."""
        settings, trees = self.chosen, self.chosen_trees
        if self.resolution is not None:
            shadows = self.resolution.shadow_resolution(self.chosen.shadow_resolution)
            settings, trees = with_quality_steps(
                replace(settings, shadow_resolution=shadows), trees, self.resolution.level
            )
        self.renderer.set_settings(settings)
        self.renderer.trees.settings = trees

    def status(self) -> str:
        s = self.chosen
        ms = 1000 * float(np.median(self.frame_times)) if self.frame_times else float("nan")
        lights = "auto" if s.lights is None else f"{s.lights:.2f}"
        hours = s.time_of_day % 24
        scale = (
            f"  scale {self.resolution.scale:.2f} (target {self.resolution.target_fps:g} fps)"
            + quality_status(self.resolution.level)
            if self.resolution
            else ""
        )
        return (
            f"cityshade  {1000 / ms if ms else 0:.1f} fps ({ms:.1f} ms){scale}  interiors {'on' if s.interior_mapping else 'off'}"
            f"  prepass {'on' if s.depth_prepass else 'off'}  furniture {'on' if s.furniture else 'off'}"
            f"  LOD {'on' if s.lod else 'off'}  MSAA {self.renderer.samples}x  c={lights}"
            f"  {int(hours):02d}:{int(hours % 1 * 60):02d}{self._streaming()}"
        )

    def _streaming(self) -> str:
        streamer = getattr(self.renderer.city, "streamer", None)
        if streamer is None:
            return ""
        return f"  tiles {len(streamer.resident)}/{len(streamer.tiles)} {format_bytes(streamer.resident_bytes)}"

    # --- input: keys by name, so the same actions run whatever the window backend ----------
    def press(self, name: str):
        self.held.add(name)
        if name == "ESCAPE":
            self.wnd.close()
        changed = self._setting_for_key(name)
        if changed is not None:
            self.chosen = changed
            self._apply_settings()

    def release(self, name: str):
        self.held.discard(name)

    def _setting_for_key(self, name: str) -> RenderSettings | None:
        s = self.chosen
        if name in TOGGLES:
            return replace(s, **{TOGGLES[name]: not getattr(s, TOGGLES[name])})
        if name in ("LEFT_BRACKET", "RIGHT_BRACKET"):
            current = s.lights if s.lights is not None else 0.5
            step = 0.1 if name == "RIGHT_BRACKET" else -0.1
            return replace(s, lights=round(float(np.clip(current + step, 0.0, 1.0)), 2))
        if name == "M":
            return replace(s, samples=0 if s.samples else 4)
        if name in ("T", "G"):
            hours = (s.time_of_day + (TIME_STEP if name == "T" else -TIME_STEP)) % 24
            return replace(s, time_of_day=hours, **(self.sky(hours) if self.sky else {}))
        return None

    def on_key_event(self, key, action, modifiers):
        keys = self.wnd.keys
        names = {getattr(keys, n, None): n for n in KEY_NAMES}
        name = names.get(key)
        if name is None:
            return
        if action == keys.ACTION_PRESS:
            self.press(name)
        elif action == keys.ACTION_RELEASE:
            self.release(name)

    def on_mouse_drag_event(self, x, y, dx, dy):
        self.fly.look(dx, dy)

    def on_resize(self, width: int, height: int):
        self.renderer.resize((width, height))


def open_viewer(
    city: str | City = "default",
    camera: str = "street",
    settings: RenderSettings | None = None,
    window: str = "pyglet",
    size: tuple[int, int] = (1280, 720),
    sky=None,
    target_fps: float | None = DEFAULT_TARGET_FPS,
    tiles=None,
    memory_budget: int | None = None,
    stop_after: int | None = None,
) -> CityViewer:
    """Creates the viewer (window + renderer) without entering the main loop. `sky` (hours -> settings,
    e.g. `maps.sky_clock`) moves the sun and moon with the clock keys. `target_fps`: the frame rate
    the internal resolution is scaled to keep, quality steps taken below its smallest scale (None or 0:
    always full resolution and quality). `tiles` (a tile
    cache) streams its city instead, at most `memory_budget` bytes of tiles resident, never waiting.
    `stop_after`: the window closes itself after that many frames, keeping the last in `last_image`."""
    if tiles is not None:
        city = tiles.city
    start = (city if isinstance(city, City) else make_city(city)).camera(camera)  # fail early on bad names
    if tiles is not None:
        check_memory_budget(tiles.tiles, memory_budget, start.eye)
    if target_fps:
        ResolutionScale(target_fps)  # a bad rate fails here, before a window opens
    CityViewer.target_fps = target_fps or None
    CityViewer.city, CityViewer.camera_name = city, camera
    CityViewer.tiles, CityViewer.memory_budget = tiles, memory_budget
    CityViewer.stop_after = stop_after
    CityViewer.sky = staticmethod(sky) if sky else None  # a plain function, not bound to the viewer
    CityViewer.start_settings = settings or RenderSettings()
    args = ["--window", window, "--size", f"{size[0]}x{size[1]}"]
    if window == "headless":
        args += ["--backend", "egl"]
    try:
        return mglw.create_window_config_instance(CityViewer, args=args)
    except CityshadeError:
        raise
    except Exception as exc:  # no display, no GL 4.3: one line, no traceback
        raise CityshadeError(
            f"could not open a {window} window ({exc}); on a machine without a display use `cityshade render` instead"
        ) from None
