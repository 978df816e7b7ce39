"""The frame: its passes, listed in the order they run.

    0. shadows           cascaded shadow maps of buildings and trees, each cascade at its own
                         rate (SpeedTree §4.3.2; _shadows.py)
    1. facade grammar    only with settings.grammar_deferred: G-buffer + one full-screen grammar
                         evaluation per pixel (Krecklau §4), shadowed, read back by the buildings pass
    2. depth prepass     all opaque geometry into the z-buffer (interior-mapping §3.1 "z-cull")
    3. buildings         facades; behind the glass, interior-mapped rooms (or the polygonised-
                         rooms baseline: exteriors, floors, ceilings, walls, blended glass)
    4. ground            streets, pavements, parks; receives the shadows
    5. trees             trunks, fins, leaf cards, fronds with alpha to coverage (_trees.py)
    6. sky               environment map where nothing was drawn
    7. resolve           multisampled HDR -> single-sample HDR
    8. tone map          god rays around the sun (SpeedTree §4.5), then HDR -> sRGB 8-bit

`draw_ids` renders the id AOV (face, room, building) used by tests and datasets.
"""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..gl import ProgramCache, RenderTarget
from ..grammar._gpu import shader_defines as grammar_defines
from ..scene import Camera
from ..scene._records import FLAG_CURTAINS, FLAG_FURNITURE, FLAG_ROOM_VARIATION
from ._city_gpu import CityGPU
from ._daylight import Daylight
from ._godrays import god_ray_uniforms
from ._night_sky import night_amount
from ._polygonised import draw_interior_layers
from ._settings import RenderSettings
from ._shadows import CascadedShadows, shadow_pass
from ._textures import CityTextures
from ._trees import TreePass, draw_trees
from ._uniforms import (
    UNIT_ATLAS, UNIT_CEILING, UNIT_CURTAIN, UNIT_ENV, UNIT_FACADE, UNIT_FLOOR, UNIT_HDR, UNIT_SPRITES,
    UNIT_GRAMMAR, UNIT_GRAMMAR_DEFERRED, UNIT_RELIEF, UNIT_WALL_X, UNIT_WALL_Z, set_uniforms,
)

ROOM_LIGHT = np.array([1.0, 0.78, 0.52]) * 1.1
ROOM_DARK = np.array([0.018, 0.02, 0.03])


@dataclass
class FrameInputs:
    """What one frame needs, gathered once and handed to every pass."""

    ctx: moderngl.Context
    programs: ProgramCache
    city: CityGPU
    textures: CityTextures
    env: moderngl.TextureCube
    camera: Camera
    settings: RenderSettings
    daylight: Daylight
    size: tuple[int, int]
    shadows: CascadedShadows | None = None
    trees: TreePass | None = None
    frame_index: int = 0

    @property
    def view_projection(self) -> np.ndarray:
        return self.camera.view_projection(self.size[0] / self.size[1])

    def building_defines(self, **extra) -> dict:
        s = self.settings
        return {"INTERIOR_MAPPING": s.interior_mapping, "IM_SINGLE_ATLAS": s.single_atlas, "INTERIOR_LOD": s.lod,
                "NO_SHADOWS": self.shadows is None, **extra}

    def common_uniforms(self) -> dict:
        s, d, t = self.settings, self.daylight, self.textures
        mask = (FLAG_FURNITURE * s.furniture) | (FLAG_CURTAINS * s.curtains) | (FLAG_ROOM_VARIATION * s.room_variation)
        layout = t.atlas_layout
        atlas_size = (t.atlas.width, t.atlas.height)
        return dict(
            u_view_proj=self.view_projection, u_camera=self.camera.eye, u_sun_dir=d.sun_direction,
            u_sun_color=d.sun_color, u_sky_ambient=d.sky_ambient, u_ground_ambient=d.ground_ambient,
            u_lights=float(d.lights if s.lights is None else s.lights), u_time=float(s.animation_time),
            u_street_lights=d.street_lights,
            u_room_variants=t.room_variants, u_sprite_kinds=t.sprite_kinds, u_sprite_frames=t.sprite_frames,
            u_glass_rect=np.array(t.glass_rect), u_room_light=ROOM_LIGHT, u_room_dark=ROOM_DARK,
            u_feature_mask=int(mask), u_lod_range=np.array(s.lod_range), u_window_tint=np.array([0.02, 0.025, 0.03]),
            u_atlas_layout=np.array([layout["tile"], layout["padding"], *atlas_size], dtype=float),
            u_env=UNIT_ENV, u_facade=UNIT_FACADE, u_ceiling=UNIT_CEILING, u_floor=UNIT_FLOOR, u_wall_x=UNIT_WALL_X,
            u_wall_z=UNIT_WALL_Z, u_room_atlas=UNIT_ATLAS, u_sprites=UNIT_SPRITES, u_curtain=UNIT_CURTAIN,
        )

    def bind_textures(self):
        t = self.textures
        self.env.use(UNIT_ENV)
        t.facade.use(UNIT_FACADE)
        for unit, face in ((UNIT_CEILING, "ceiling"), (UNIT_FLOOR, "floor"), (UNIT_WALL_X, "wall_x"), (UNIT_WALL_Z, "wall_z")):
            t.rooms[face].use(unit)
        t.atlas.use(UNIT_ATLAS)
        t.sprites.use(UNIT_SPRITES)
        t.curtain.use(UNIT_CURTAIN)


def depth_prepass(f: FrameInputs):
    f.ctx.depth_func = "<"
    f.ctx.color_mask = (False, False, False, False)
    buildings = f.programs.get("city/building.glsl", {"DEPTH_ONLY": True})
    set_uniforms(buildings, u_view_proj=f.view_projection)
    f.city.draw_buildings(buildings, f.view_projection)
    ground = f.programs.get("city/ground.glsl", {"DEPTH_ONLY": True})
    set_uniforms(ground, u_view_proj=f.view_projection)
    f.city.draw_ground(ground)
    f.ctx.color_mask = (True, True, True, True)
    f.ctx.depth_func = "<="  # shading passes now touch only the visible surface


def grammar_deferred_pass(f: FrameInputs):
    """Facade grammars evaluated once per pixel from a G-buffer (Krecklau §4); see grammar._frame_pass."""
    f.textures.grammar_pass.run(f, f.textures.grammar, set_uniforms, UNIT_GRAMMAR, UNIT_GRAMMAR_DEFERRED)


def draw_buildings(f: FrameInputs, defines: dict | None = None):
    defines = {**grammar_defines(), "GRAMMAR_DEFERRED": f.settings.grammar_deferred, **(defines or {})}
    program = f.programs.get("city/building.glsl", f.building_defines(**defines))
    set_uniforms(program, **f.common_uniforms())
    f.textures.grammar.bind(program, UNIT_GRAMMAR)
    if f.settings.grammar_deferred:
        f.textures.grammar_pass.bind_results(program, UNIT_GRAMMAR_DEFERRED + 4)
    f.city.relief.bind(program, UNIT_RELIEF)
    f.city.street_lights.bind(program)
    if f.shadows is not None:
        f.shadows.bind(program)
    f.city.draw_buildings(program, f.view_projection)


def draw_polygonised_buildings(f: FrameInputs):
    """The polygonised-interiors baseline (interior-mapping §3.1): the exterior walls with the glass
    cut out first (they hide most of the rooms' geometry, so no prepass is needed), then the real
    floors, ceilings and walls, then the glass's reflection blended over them: five draw calls."""
    f.ctx.depth_func = "<"
    draw_buildings(f, {"INTERIOR_MAPPING": False, "POLYGONISED_EXTERIOR": True})
    draw_interior_layers(f)
    f.ctx.enable(moderngl.BLEND)
    f.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
    f.ctx.depth_mask = False
    draw_buildings(f, {"INTERIOR_MAPPING": False, "POLYGONISED_WINDOWS": True})
    f.ctx.depth_mask = True
    f.ctx.disable(moderngl.BLEND)


def draw_ground(f: FrameInputs, defines: dict | None = None):
    program = f.programs.get("city/ground.glsl", {"NO_SHADOWS": f.shadows is None, **(defines or {})})
    set_uniforms(program, **f.common_uniforms())
    if f.shadows is not None:
        f.shadows.bind(program)
    f.city.street_lights.bind(program)
    f.city.draw_ground(program)


def draw_sky(f: FrameInputs):
    program = f.programs.get("frame/sky.glsl")
    set_uniforms(program, u_inv_view_proj=np.linalg.inv(f.view_projection), u_camera=f.camera.eye, u_env=UNIT_ENV,
                 u_stars=night_amount(f.daylight.sun_elevation))
    f.ctx.depth_func = "<="
    f.ctx.vertex_array(program, []).render(moderngl.TRIANGLES, vertices=3)


def tone_map(f: FrameInputs, hdr: moderngl.Texture, target: RenderTarget):
    target.use()
    f.ctx.disable(moderngl.DEPTH_TEST)
    program = f.programs.get("frame/tonemap.glsl", {"GOD_RAYS": f.settings.god_rays})
    hdr.use(UNIT_HDR)
    set_uniforms(program, u_hdr=UNIT_HDR, u_exposure=f.daylight.exposure,
                 **god_ray_uniforms(f.view_projection, f.camera.eye, f.daylight.sun_direction, f.daylight.sun_color))
    f.ctx.vertex_array(program, []).render(moderngl.TRIANGLES, vertices=3)


def draw_frame(f: FrameInputs, hdr: RenderTarget, resolved: RenderTarget, display: RenderTarget):
    """Runs the passes in order; the tone-mapped image ends in `display`."""
    ctx = f.ctx
    shadow_pass(f)
    if f.settings.grammar_deferred:
        grammar_deferred_pass(f)
    hdr.use()
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.disable(moderngl.CULL_FACE)
    ctx.clear(0.0, 0.0, 0.0, 1.0, depth=1.0)
    f.bind_textures()
    ctx.depth_func = "<"
    if f.settings.polygonised_interiors:
        draw_polygonised_buildings(f)
    else:
        if f.settings.depth_prepass:
            depth_prepass(f)
        draw_buildings(f)
    draw_ground(f)
    draw_trees(f)
    draw_sky(f)
    ctx.copy_framebuffer(resolved.fbo, hdr.fbo)
    tone_map(f, resolved.colors[0], display)


def draw_ids(f: FrameInputs, target: RenderTarget):
    """The id AOV: per pixel (face, room id, building index + 1, 0) as uint32."""
    ctx = f.ctx
    target.use()
    ctx.enable(moderngl.DEPTH_TEST)
    ctx.depth_func = "<"
    target.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
    f.bind_textures()
    draw_buildings(f, {"ID_PASS": True, "INTERIOR_LOD": False})
    draw_ground(f, {"ID_PASS": True})
