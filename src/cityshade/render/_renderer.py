"""The Renderer: owns the GL context, programs, textures, targets and the uploaded city."""

from __future__ import annotations

import time

import moderngl
import numpy as np

from .. import assets
from .._budget import check_image_memory, release_freed_memory
from .._values import check_size, check_type
from ..errors import UsageError
from ..frame import HDR, IDS, Daylight, Frame, FrameTargets, FrameView, RenderSettings, run_passes
from ..gl import RenderTarget, create_context, describe_context, programs, upload_cubemap
from ..grammar import DeferredGrammarPass, GrammarTextures
from ..scene import Camera, City
from ..trees import TreePass, city_trees
from ._building_lod import lod_distances
from ._city_gpu import CityGPU
from ._frame import DISPLAY, RESOLVED, frame_passes, id_passes, write_frame_blocks
from ._night_sky import night_amount, night_sky
from ._shadows import CascadedShadows
from ._streaming import StreamedCityGPU
from ._textures import CityTextures
from ._tile_cache import TileCache

ENV_SIZE = 128


def frame_bytes_per_pixel(samples: int) -> int:
    """Estimated memory of a frame per pixel: HDR colour and depth per MSAA sample (12 bytes) and
    the rest (resolved, tone-mapped and id targets, god rays, read-back arrays); 138 at 4x MSAA
    as measured (peak memory 279 MB higher at 1920x1080 than at 320x180)."""
    return 12 * max(samples, 1) + 90


class Renderer:
    """Renders a City from a Camera. Headless by default; pass a window's context to draw on screen."""

    def __init__(
        self,
        size: tuple[int, int] = (1280, 720),
        settings: RenderSettings | None = None,
        ctx: moderngl.Context | None = None,
    ):
        self.size = check_size(size)
        self.settings = settings or RenderSettings()
        check_image_memory(self.size, frame_bytes_per_pixel(self.settings.samples), "a render")
        self.ctx = ctx or create_context(headless=True)
        self._current()
        self.programs = programs(self.ctx)
        self.textures = self._textures(self.settings)
        self.city: CityGPU | None = None
        self._grammar_start: tuple | None = None  # (settings.grammar_start,) as in the city's records; None: not yet
        self.trees: TreePass | None = None
        self.shadows: CascadedShadows | None = None
        self.frame_index = 0  # drives the shadow cascades' update rates
        self._env_key = None
        self.env = self.sky = None  # the sky's cube maps, with and without the discs (_sky_cubemap)
        self.targets = FrameTargets(self.ctx)  # made by the passes that run, from their declarations
        self.last_frame_seconds = float("nan")
        self.last_pass_seconds: dict[str, float] = {}  # by pass name, from draw(..., profile=True)
        self.last_lod_colours = 0  # building LOD colours the last frame evaluated before its passes
        self.last_lod_seconds = 0.0  # and the time they took (within last_frame_seconds)

    def _current(self):
        """Makes this renderer's context the current one: GL calls go to the current context, and
        a process may hold several (each cityshade.render_image call makes its own)."""
        self.ctx.__enter__()

    @property
    def samples(self) -> int:
        """MSAA samples in use: the setting, clamped to the device's maximum."""
        return min(self.settings.samples, self.ctx.max_samples) if self.settings.samples else 0

    @property
    def device(self) -> str:
        return describe_context(self.ctx)

    def set_city(self, city: City):
        check_type(
            city, City, "city", "Renderer.set_city takes a City: cityshade.make_city(name) or maps.map_city(data)"
        )
        self._current()
        if self.city is not None:
            self.city.release()
        self._set_city_gpu(CityGPU(self.ctx, city), city)

    def set_tiles(self, cache: TileCache, memory_budget: int | None = None, read=None):
        """A tiled city (render/_tile_cache.py), its buildings streamed around the camera with at
        most `memory_budget` bytes of tiles resident (None: all of them); `read` replaces the
        tile reader (tests)."""
        self._current()
        if self.city is not None:
            self.city.release()
            self.city = None
        self._set_city_gpu(StreamedCityGPU(self.ctx, cache, memory_budget, read), cache.city)

    def wait_for_tiles(self, camera: Camera):
        """For a still: loads the tiles `camera` wants (a whole city has them all)."""
        if isinstance(self.city, StreamedCityGPU):
            self._current()
            self.city.wait(camera.eye)

    def _set_city_gpu(self, gpu: CityGPU, city: City):
        self.city = gpu
        self._grammar_start = None
        if self.trees is not None:
            self.trees.release()
        trees = city_trees(city) if city.trees is None else city.trees
        self.trees = TreePass(self.ctx, self.programs, trees, seed=city.seed)
        release_freed_memory()

    def _textures(self, settings: RenderSettings) -> CityTextures:
        return CityTextures.create(self.ctx, settings.room_texture_size, settings.room_variants, settings.grammar_files)

    def set_settings(self, settings: RenderSettings):
        self._current()
        textures = ("room_texture_size", "room_variants", "grammar_files")
        if any(getattr(settings, name) != getattr(self.settings, name) for name in textures):
            self.textures.release()
            self.textures = self._textures(settings)
            self._grammar_start = None  # the addresses may have moved
        self.settings = settings

    def resize(self, size: tuple[int, int]):
        self.size = tuple(size)  # the targets follow when the next frame declares them

    def _daylight(self) -> Daylight:
        s = self.settings
        daylight = Daylight.at(s.time_of_day, s.sun, s.moon)
        key = (round(daylight.hours, 3), s.sun, s.moon)
        if key != self._env_key:
            self._release_sky()
            self.env, self.sky = (self._sky_cubemap(daylight, disc) for disc in (True, False))
            self._env_key = key
        return daylight

    def _sky_cubemap(self, daylight: Daylight, disc: bool) -> moderngl.TextureCube:
        """The sky's radiance, with the sun's and moon's discs (for reflections) or without them."""
        radiance = assets.environment_cubemap(ENV_SIZE, tuple(daylight.sky_sun), daylight.dusk, disc)
        night = night_amount(daylight.sun_elevation)
        if night > 0.0 or daylight.moon_direction is not None:
            directions = assets.cube_directions(ENV_SIZE)
            radiance = night_sky(radiance, directions, night, daylight.moon_direction, daylight.moon_lit, disc)
        return upload_cubemap(self.ctx, radiance)

    def _release_sky(self):
        for cube in (self.env, self.sky):
            if cube is not None:
                cube.release()

    def _inputs(self, camera: Camera, lod_budget: int | None = None) -> Frame:
        """The frame's inputs for `camera`, with at most `lod_budget` cheap colours evaluated first
        (None: every one the view needs)."""
        check_type(camera, Camera, "camera", "give a Camera, e.g. city.camera('street')")
        if self.city is None:
            raise RuntimeError("no city: call set_city() first")
        if isinstance(self.city, StreamedCityGPU):
            self.city.follow(camera.eye)
        daylight = self._daylight()
        resolution = self.settings.shadow_resolution
        if self.settings.shadows and (self.shadows is None or self.shadows.resolution != resolution):
            if self.shadows is not None:
                self.shadows.release()
            self.shadows = CascadedShadows(self.ctx, resolution)
        self.frame_index += 1
        self._start_grammars()
        if self.settings.building_lod and lod_budget != 0:
            self._update_lod_colours(camera, lod_budget)
        s = self.settings
        if s.grammar_deferred:
            self.textures.grammar_pass.keep_cache(s.grammar_cache_pages if s.grammar_cache else None)
        t = self.textures
        techniques = {CityTextures: t, GrammarTextures: t.grammar, DeferredGrammarPass: t.grammar_pass}
        if s.trees and self.trees is not None:
            techniques[TreePass] = self.trees
        frame = Frame(
            self.ctx,
            self.programs,
            FrameView(camera, s, daylight, self.size, self.frame_index - 1),
            self.targets,
            self.city,
            self.env,
            self.sky,
            shadows=self.shadows if s.shadows else None,
            room_textures=dict(u_rooms=t.rooms, u_room_atlas=t.atlas, u_sprites=t.sprites, u_curtain=t.curtain),
            techniques=techniques,
        )
        write_frame_blocks(frame, t)
        return frame

    def _update_lod_colours(self, camera: Camera, budget: int | None):
        """The cheap colours `camera`'s view needs (render/_lod_colours.py), timed into last_lod_seconds."""
        start = time.perf_counter()
        distances = lod_distances(self.settings.building_lod_pixels, self.size[1], camera.fov_y)
        self.last_lod_colours = self.city.update_lod_colours(
            self.textures.grammar, camera, self.size, distances, budget
        )
        self.ctx.finish()
        self.last_lod_seconds = time.perf_counter() - start

    def _start_grammars(self):
        """Writes settings.grammar_start into the city's records when it or the city changed."""
        start = self.settings.grammar_start
        if self._grammar_start == (start,):
            return
        compiled = self.textures.grammar.compiled
        if start is not None and start not in compiled.starts:
            raise UsageError(
                f"unknown grammar_start {start!r}; allowed: {', '.join(compiled.starts)} "
                "(or add its file to grammar_files)"
            )
        self.city.start_grammars_at(None if start is None else compiled.address(start))
        self._grammar_start = (start,)

    def draw(
        self,
        camera: Camera,
        framebuffer: moderngl.Framebuffer | None = None,
        profile: bool = False,
        still: bool = False,
    ) -> RenderTarget:
        """Draws one frame; returns the display target (also blitted to `framebuffer` if given).
        With `profile`, each pass is timed on its own (ctx.finish() around it) into last_pass_seconds.
        Building LOD evaluates settings.building_lod_budget of the cheap colours the view needs per
        frame (the others stay at the finer level until a later frame), or with `still` all of them."""
        self._current()
        self.last_lod_colours, self.last_lod_seconds = 0, 0.0
        inputs = self._inputs(camera, None if still else self.settings.building_lod_budget)
        times = {} if profile else None
        start = time.perf_counter()
        run_passes(inputs, frame_passes(self.settings), times)
        display = self.targets[DISPLAY.name]
        if framebuffer is not None:
            self.ctx.copy_framebuffer(framebuffer, display.fbo)
        self.ctx.finish()
        self.last_frame_seconds = time.perf_counter() - start + self.last_lod_seconds
        if times is not None:
            self.last_pass_seconds = (
                {"lod colours": self.last_lod_seconds, **times} if self.settings.building_lod else times
            )
        return display

    def render(self, camera: Camera) -> np.ndarray:
        """One frame as an HxWx3 uint8 sRGB array: a still, every building LOD colour its view needs evaluated."""
        return self.draw(camera, still=True).read()[..., :3].copy()

    def read_hdr(self) -> np.ndarray:
        """The last frame's linear HDR colour before tone mapping, HxWx3 float32 (to check it is finite)."""
        resolved = self.targets.get(RESOLVED.name)
        if resolved is None:
            raise RuntimeError("no frame drawn yet: call draw() or render() first")
        self._current()
        return resolved.read()[..., :3].astype(np.float32)

    def render_ids(self, camera: Camera, room_state: bool = False, windows: bool = False) -> np.ndarray:
        """The id AOV as HxWx4 uint32: face code, room id, building index + 1, grammar label (with
        `room_state`: the room seen, 1 | lit << 1 | texture variant << 2, 0 where none; with
        `windows`: the window a room is seen through, a key per window of the building, 0 where none)."""
        self._current()
        run_passes(self._inputs(camera, lod_budget=0), id_passes(self.settings, room_state, windows))  # full detail
        return self.targets[IDS.name].read().copy()

    def depth(self, aov: bool = False) -> np.ndarray:
        """The depth buffer (HxW float32, 0 at `near` .. 1 at `far`, top row first) of the last frame,
        or with `aov` of the last id AOV. The frame's needs settings.samples == 0 (single-sample)."""
        self._current()
        target = self.targets.get((IDS if aov else HDR).name)
        if target is None or target.samples:
            raise RuntimeError("no single-sample depth: draw first, with settings.samples = 0 for the frame")
        data = np.frombuffer(target.depth.read(), dtype=np.float32)
        return data.reshape(self.size[1], self.size[0])[::-1].copy()

    def release(self):
        self._current()
        self.targets.release()
        if self.city is not None:
            self.city.release()
        self.textures.release()
        self._release_sky()
        for owned in (self.trees, self.shadows):
            if owned is not None:
                owned.release()
