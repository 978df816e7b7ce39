"""The Renderer: owns the GL context, programs, textures, targets and the uploaded city."""

from __future__ import annotations

import time

import moderngl
import numpy as np

from .. import assets
from ..gl import ProgramCache, RenderTarget, create_context, describe_context
from ..scene import Camera, City
from ._city_gpu import CityGPU
from ._daylight import Daylight
from ._frame import FrameInputs, draw_frame, draw_ids
from ._night_sky import night_amount, night_sky
from ._settings import RenderSettings
from ._shadows import CascadedShadows
from ._textures import CityTextures, cubemap
from ._trees import TreePass
from ..trees import city_trees

ENV_SIZE = 128


class Renderer:
    """Renders a City from a Camera. Headless by default; pass a window's context to draw on screen."""

    def __init__(self, size: tuple[int, int] = (1280, 720), settings: RenderSettings | None = None,
                 ctx: moderngl.Context | None = None):
        self.ctx = ctx or create_context(headless=True)
        self.size = tuple(size)
        self.settings = settings or RenderSettings()
        self.programs = ProgramCache(self.ctx)
        self.textures = CityTextures.create(self.ctx, self.settings.room_texture_size, self.settings.room_variants)
        self.city: CityGPU | None = None
        self.trees: TreePass | None = None
        self.shadows: CascadedShadows | None = None
        self.frame_index = 0  # drives the shadow cascades' update rates
        self._env_key = None
        self.env = None
        self._targets = None
        self._ids = None
        self.last_frame_seconds = float("nan")

    @property
    def samples(self) -> int:
        """MSAA samples in use: the setting, clamped to the device's maximum."""
        return min(self.settings.samples, self.ctx.max_samples) if self.settings.samples else 0

    @property
    def device(self) -> str:
        return describe_context(self.ctx)

    def set_city(self, city: City):
        if self.city is not None:
            self.city.release()
        self.city = CityGPU(self.ctx, city)
        if self.trees is not None:
            self.trees.release()
        trees = city_trees(city) if city.trees is None else city.trees
        self.trees = TreePass(self.ctx, self.programs, trees, seed=city.seed)

    def set_settings(self, settings: RenderSettings):
        if settings.room_texture_size != self.settings.room_texture_size or settings.room_variants != self.settings.room_variants:
            self.textures.release()
            self.textures = CityTextures.create(self.ctx, settings.room_texture_size, settings.room_variants)
        if settings.samples != self.settings.samples:
            self._release_targets()
        self.settings = settings

    def resize(self, size: tuple[int, int]):
        if tuple(size) != self.size:
            self.size = tuple(size)
            self._release_targets()

    def _release_targets(self):
        for group in (self._targets or ()), ((self._ids,) if self._ids else ()):
            for target in group:
                target.release()
        self._targets = self._ids = None

    def _daylight(self) -> Daylight:
        s = self.settings
        daylight = Daylight.at(s.time_of_day, s.sun, s.moon)
        key = (round(daylight.hours, 3), s.sun, s.moon)
        if key != self._env_key:
            if self.env is not None:
                self.env.release()
            radiance = assets.environment_cubemap(ENV_SIZE, sun_direction=tuple(daylight.sky_sun), dusk=daylight.dusk)
            night = night_amount(daylight.sun_elevation)
            if night > 0.0 or daylight.moon_direction is not None:
                radiance = night_sky(radiance, assets.cube_directions(ENV_SIZE), night, daylight.moon_direction,
                                     daylight.moon_lit)
            self.env = cubemap(self.ctx, radiance)
            self._env_key = key
        return daylight

    def _inputs(self, camera: Camera) -> FrameInputs:
        if self.city is None:
            raise RuntimeError("no city: call set_city() first")
        daylight = self._daylight()
        if self.settings.shadows and self.shadows is None:
            self.shadows = CascadedShadows(self.ctx)
        self.frame_index += 1
        return FrameInputs(self.ctx, self.programs, self.city, self.textures, self.env, camera, self.settings,
                           daylight, self.size, shadows=self.shadows if self.settings.shadows else None,
                           trees=self.trees if self.settings.trees else None, frame_index=self.frame_index - 1)

    def draw(self, camera: Camera, framebuffer: moderngl.Framebuffer | None = None) -> RenderTarget:
        """Draws one frame; returns the display target (also blitted to `framebuffer` if given)."""
        if self._targets is None:
            self._targets = (
                RenderTarget(self.ctx, self.size, (("f2", 4),), samples=self.settings.samples),
                RenderTarget(self.ctx, self.size, (("f2", 4),)),
                RenderTarget(self.ctx, self.size, (("f1", 4),)),
            )
        inputs = self._inputs(camera)
        start = time.perf_counter()
        draw_frame(inputs, *self._targets)
        if framebuffer is not None:
            self.ctx.copy_framebuffer(framebuffer, self._targets[2].fbo)
        self.ctx.finish()
        self.last_frame_seconds = time.perf_counter() - start
        return self._targets[2]

    def render(self, camera: Camera) -> np.ndarray:
        """One frame as an HxWx3 uint8 sRGB array."""
        return self.draw(camera).read()[..., :3].copy()

    def render_ids(self, camera: Camera) -> np.ndarray:
        """The id AOV as HxWx4 uint32: face code, room id, building index + 1, 0."""
        if self._ids is None:
            self._ids = RenderTarget(self.ctx, self.size, (("u4", 4),))
        draw_ids(self._inputs(camera), self._ids)
        return self._ids.read().copy()

    def depth(self, aov: bool = False) -> np.ndarray:
        """The depth buffer (HxW float32, 0 at `near` .. 1 at `far`, top row first) of the last frame,
        or with `aov` of the last id AOV. The frame's needs settings.samples == 0 (single-sample)."""
        target = self._ids if aov else (self._targets[0] if self._targets else None)
        if target is None or target.samples:
            raise RuntimeError("no single-sample depth: draw first, with settings.samples = 0 for the frame")
        data = np.frombuffer(target.depth.read(), dtype=np.float32)
        return data.reshape(self.size[1], self.size[0])[::-1].copy()

    def release(self):
        self._release_targets()
        if self.city is not None:
            self.city.release()
        self.textures.release()
        if self.env is not None:
            self.env.release()
        for owned in (self.trees, self.shadows):
            if owned is not None:
                owned.release()
