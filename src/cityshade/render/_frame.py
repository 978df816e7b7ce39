"""The frame: an ordered list of passes, built from the settings (docs/frame.md lists them).

Each pass has a name, says what it reads and which target it writes, and sets every piece of GL
state it relies on (GLState) before it draws, so no pass depends on what an earlier one left.
`frame_passes` below reads top to bottom in the order the passes run; `run_passes` runs them and,
when asked, times each one with ctx.finish() around it.

`id_passes` render the id AOV (face, room, building, label) used by tests and datasets.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Callable

import moderngl
import numpy as np

from ..gl import (
    FRAME_BLOCK,
    MAX_USES,
    R32F,
    SHADING_BLOCK,
    ProgramCache,
    RenderTarget,
    bind_textures,
    binding,
    draw_fullscreen,
    set_uniforms,
)
from ..grammar import shader_defines as grammar_defines
from ..scene import Camera
from ..scene import FLAG_CURTAINS, FLAG_FURNITURE, FLAG_ROOM_VARIATION, lit_shares
from ..relief import switch_distance
from ._building_lod import bay_mean, lod_distances, relief_mean
from ._city_gpu import CityGPU
from ._daylight import Daylight
from ._godrays import GodRayTargets, god_ray_uniforms
from ._night_sky import night_amount
from ._sky_discs import sky_disc_uniforms
from ._polygonised import draw_interior_depth, draw_interior_layers
from ._settings import RenderSettings
from ._shadows import CascadedShadows, shadow_pass
from ._textures import CityTextures
from ._trees import TreePass, draw_trees
from ._visibility import cull_pass, farthest_pass, hiz_pass, occluder_pass

ROOM_LIGHT = np.array([1.0, 0.78, 0.52]) * 1.1
ROOM_DARK = np.array([0.018, 0.02, 0.03])
WINDOW_TINT = np.array([0.02, 0.025, 0.03])  # the glass where no room is drawn behind it


@dataclass
class FrameTargets:
    """Where passes draw: the multisampled HDR target, its resolve, the resolve with ambient
    occlusion, the 8-bit display image, the id AOV, the deferred grammar's G-buffer and results and
    the god rays' half-resolution steps (None until a pass needs them)."""

    hdr: RenderTarget | None = None
    resolved: RenderTarget | None = None
    occluded: RenderTarget | None = None
    display: RenderTarget | None = None
    ids: RenderTarget | None = None
    grammar_gbuffer: RenderTarget | None = None
    grammar_result: RenderTarget | None = None
    god_rays: GodRayTargets | None = None  # drawn by its pass, which binds them itself

    def get(self, name: str) -> RenderTarget | None:
        """The target called `name`; None for what a pass binds itself (the shadow maps, the god rays' steps)."""
        target = getattr(self, name, None)
        return target if isinstance(target, RenderTarget) else None


@dataclass
class FrameResources:
    """What the frame draws with and into: made by the renderer and kept across frames."""

    ctx: moderngl.Context
    programs: ProgramCache
    city: CityGPU  # the buildings', ground's and lamps' buffers
    textures: CityTextures  # rooms, facades, sprites, grammars
    env: moderngl.TextureCube  # the sky's radiance with the sun and moon, remade when the daylight changes
    sky: moderngl.TextureCube  # the same without their discs, which the sky pass draws per pixel
    targets: FrameTargets
    shadows: CascadedShadows | None = None  # None: shadows off
    trees: TreePass | None = None  # None: no trees drawn
    camera_draws: moderngl.Buffer | None = None  # this frame's cull pass's draw commands for the camera


@dataclass
class FrameView:
    """What this frame shows: from where, when, how, at what size, and which frame it is."""

    camera: Camera
    settings: RenderSettings
    daylight: Daylight
    size: tuple[int, int]
    frame_index: int = 0  # the shadow cascades update at their own rates (SpeedTree §4.3.2)

    @property
    def view_projection(self) -> np.ndarray:
        return self.camera.view_projection(self.size[0] / self.size[1])


@dataclass
class FrameInputs:
    """What one frame needs, handed to every pass: the GPU resources and the view."""

    gpu: FrameResources
    view: FrameView

    def draw_buildings(self, program, view_projection: np.ndarray | None = None):
        """The buildings seen through `view_projection` (default: the camera's), culled as
        settings.culling says: "gpu", the cull pass's commands for the camera and a frustum test on
        the GPU for any other view (render/_visibility.py); "frustum", chunks on the CPU; "off", all."""
        city, culling = self.gpu.city, self.view.settings.culling
        view = self.view.view_projection if view_projection is None else view_projection
        if culling == "off":
            city.draw_buildings(program)
        elif culling == "frustum":
            city.draw_buildings(program, view)
        elif view_projection is None and self.gpu.camera_draws is not None:
            city.draw_buildings(program, draws=self.gpu.camera_draws)
        else:
            city.draw_buildings(program, draws=city.visibility.frustum(view))

    def building_defines(self, **extra) -> dict:
        s = self.view.settings
        return {
            "INTERIOR_MAPPING": s.interior_mapping,
            "IM_SINGLE_ATLAS": s.single_atlas,
            "INTERIOR_LOD": s.lod,
            "BUILDING_LOD": s.building_lod,
            "RELIEF_OFF": not s.relief,
            "NO_SHADOWS": self.gpu.shadows is None,
            **extra,
        }

    def relief_switch(self) -> float:
        """Metres within which grammar and window-bay openings are traced (relief.switch_distance)."""
        switch = self.view.settings.relief_range
        return switch_distance(self.view.size[1], self.view.camera.fov_y) if switch is None else switch

    def relief_parts(self) -> tuple[dict, ...]:
        """The buildings' draws, as defines: with relief on, two (common/building_vertex.glsl): the
        buildings a relief may be traced on (RELIEF_NEAR: relief-bay buildings, and those within the
        switch distance), by a program that writes the relief's depth, then the others (RELIEF_FAR)
        by one that keeps the rasterised depth, whose fragments a rasteriser can still reject by
        depth before shading them (llvmpipe tests depth after shading in a program that writes
        gl_FragDepth); with relief off, one."""
        return ({"RELIEF_NEAR": True}, {"RELIEF_FAR": True}) if self.view.settings.relief else ({},)

    def buildings_depth_programs(self) -> list:
        """The buildings' depth-only programs for the camera (the depth prepass, GPU culling's
        occluders), one per relief part: a wall that may be recessed writes the deepest depth its
        relief may give (shaders/relief/depth.glsl), so the traced depth passes the buildings pass's
        test; the far part writes the rasterised depth as its shading program does, sample by sample."""
        out = []
        for part in self.relief_parts():
            program = self.gpu.programs.get(
                "city/building.glsl", {"DEPTH_ONLY": True, "RELIEF_DEPTH_BOUND": "RELIEF_NEAR" in part, **part}
            )
            set_uniforms(program, u_view_proj=self.view.view_projection)
            if part:
                self.gpu.city.relief.bind_depth_bound(program, self.relief_switch())
            out.append(program)
        return out

    def write_frame_blocks(self):
        """The values programs share, once per frame: camera, sun and sky for every program
        (cityshade.gl.FRAME_BLOCK), rooms, windows and lamps for the city's (SHADING_BLOCK)."""
        s, d, t = self.view.settings, self.view.daylight, self.gpu.textures
        FRAME_BLOCK.write(
            self.gpu.ctx,
            u_inv_view_proj=np.linalg.inv(self.view.view_projection),
            u_camera=self.view.camera.eye,
            u_time=s.animation_time,
            u_sun_dir=d.sun_direction,
            u_exposure=d.exposure,
            u_sun_color=d.sun_color,
            u_sky_ambient=d.sky_ambient,
            u_ground_ambient=d.ground_ambient,
        )
        mask = (FLAG_FURNITURE * s.furniture) | (FLAG_CURTAINS * s.curtains) | (FLAG_ROOM_VARIATION * s.room_variation)
        layout = t.atlas_layout
        shares = lit_shares(d.hours, s.lights)
        SHADING_BLOCK.write(
            self.gpu.ctx,
            u_lit_share=np.pad(shares, (0, MAX_USES - len(shares))),
            u_street_lights=d.street_lights,
            u_room_variants=t.room_variants,
            u_sprite_kinds=t.sprite_kinds,
            u_sprite_frames=t.sprite_frames,
            u_glass_rect=t.glass_rect,
            u_room_light=ROOM_LIGHT,
            u_room_dark=ROOM_DARK,
            u_feature_mask=int(mask),
            u_lod_range=s.lod_range,
            u_window_tint=WINDOW_TINT,
            u_bay_mean=bay_mean(),
            u_relief_mean=relief_mean(),
            u_building_lod=lod_distances(s.building_lod_pixels, self.view.size[1], self.view.camera.fov_y),
            u_atlas_layout=(layout["tile"], layout["padding"], t.atlas.width, t.atlas.height),
        )

    def room_textures(self) -> dict:
        """The textures of the interior-mapped rooms (shaders/interior/interior.glsl), by sampler name."""
        t = self.gpu.textures
        return dict(u_rooms=t.rooms, u_room_atlas=t.atlas, u_sprites=t.sprites, u_curtain=t.curtain)


@dataclass(frozen=True)
class GLState:
    """Every piece of fixed-function state a pass relies on; applied in full before it draws."""

    depth_test: bool = True
    depth_func: str = "<"
    depth_write: bool = True
    colour_write: bool = True
    blend: tuple[int, int] | None = None  # (source, destination) factors; None: off
    cull: bool = False  # back faces

    def apply(self, ctx: moderngl.Context):
        ctx.enable(moderngl.DEPTH_TEST) if self.depth_test else ctx.disable(moderngl.DEPTH_TEST)
        ctx.depth_func = self.depth_func
        ctx.depth_mask = self.depth_write
        ctx.color_mask = (self.colour_write,) * 4
        if self.blend is None:
            ctx.disable(moderngl.BLEND)
        else:
            ctx.enable(moderngl.BLEND)
            ctx.blend_func = self.blend
        ctx.enable(moderngl.CULL_FACE) if self.cull else ctx.disable(moderngl.CULL_FACE)


@dataclass(frozen=True)
class Pass:
    """One step of the frame. `writes` names what it draws into: a FrameTargets field, which the
    runner binds (and clears to `clear` if given) before `draw`, or the shadow maps, which the
    shadow pass binds cascade by cascade."""

    name: str
    draw: Callable[[FrameInputs], None]
    reads: tuple[str, ...]
    writes: str
    state: GLState = GLState()
    clear: tuple[float, float, float, float] | None = None


# -- what the passes draw ---------------------------------------------------------------------------


def grammar_gbuffer(f: FrameInputs):
    f.gpu.textures.grammar_pass.draw_gbuffer(f, f.gpu.textures.grammar, set_uniforms)


def grammar_cache_update(f: FrameInputs):
    """The pages of the grammar cache this frame's G-buffer asks for (grammar._cache)."""
    f.gpu.textures.grammar_pass.update_cache(f, f.gpu.textures.grammar)


def grammar_evaluation(f: FrameInputs):
    """Facade grammars evaluated once per pixel from the G-buffer (Krecklau §4); see grammar._frame_pass."""
    f.gpu.textures.grammar_pass.evaluate(f, f.gpu.textures.grammar, set_uniforms)


def depth_prepass(f: FrameInputs):
    for program in f.buildings_depth_programs():
        f.draw_buildings(program)


def draw_buildings(f: FrameInputs, defines: dict | None = None):
    """The buildings' shading program (city/building.glsl), in FrameInputs.relief_parts's draws
    (the polygonised baseline's, which write no relief depth, in one)."""
    defines = {**grammar_defines(), "GRAMMAR_DEFERRED": f.view.settings.grammar_deferred, **(defines or {})}
    polygonised = defines.get("POLYGONISED_EXTERIOR") or defines.get("POLYGONISED_WINDOWS")
    after_prepass = f.view.settings.depth_prepass and not defines.get("ID_PASS")
    for part in ({},) if polygonised else f.relief_parts():
        # the part that writes its depth rejects what lies behind the prepass itself (farthest_pass)
        farthest = after_prepass and "RELIEF_NEAR" in part
        # and is drawn in two, its grammar buildings and the others (common/building_vertex.glsl)
        for kind in ({"NEAR_GRAMMAR": True}, {"NEAR_OTHER": True}) if "RELIEF_NEAR" in part else ({},):
            draw_buildings_with(f, {**defines, **part, **kind, "PREPASS_FARTHEST": farthest})


def draw_buildings_with(f: FrameInputs, defines: dict):
    program = f.gpu.programs.get("city/building.glsl", f.building_defines(**defines))
    bind_textures(program, {**f.room_textures(), "u_env": f.gpu.env, "u_facade": f.gpu.textures.facade})
    set_uniforms(program, u_view_proj=f.view.view_projection)
    f.gpu.textures.grammar.bind(program)
    if f.view.settings.grammar_deferred:
        f.gpu.textures.grammar_pass.bind_results(program)
    if defines.get("PREPASS_FARTHEST"):
        f.gpu.city.visibility.farthest.bind_to_image(binding("u_prepass_farthest"), read=True, write=False, format=R32F)
    f.gpu.city.relief.bind(program, f.relief_switch())
    f.gpu.city.street_lights.bind(program)
    if defines.get("BUILDING_LOD", f.view.settings.building_lod):
        f.gpu.city.bind_lod_colours()
    if f.gpu.shadows is not None:
        f.gpu.shadows.bind(program)
    f.draw_buildings(program)


def polygonised_exteriors(f: FrameInputs):
    """The polygonised-interiors baseline (interior-mapping §3.1), with what a competent
    implementation has (back faces culled throughout, a depth prepass for the rooms), starts with
    the exterior walls, the glass cut out: they hide most of the rooms' geometry."""
    draw_buildings(f, {"INTERIOR_MAPPING": False, "POLYGONISED_EXTERIOR": True})


def polygonised_rooms(f: FrameInputs):
    draw_interior_layers(f)


def polygonised_glass(f: FrameInputs):
    draw_buildings(f, {"INTERIOR_MAPPING": False, "POLYGONISED_WINDOWS": True})


def draw_ground(f: FrameInputs, defines: dict | None = None):
    program = f.gpu.programs.get("city/ground.glsl", {"NO_SHADOWS": f.gpu.shadows is None, **(defines or {})})
    bind_textures(program, {"u_env": f.gpu.env})
    set_uniforms(program, u_view_proj=f.view.view_projection)
    if f.gpu.shadows is not None:
        f.gpu.shadows.bind(program)
    f.gpu.city.street_lights.bind(program)
    f.gpu.city.draw_ground(program)


def trees(f: FrameInputs):
    draw_trees(f)


def draw_sky(f: FrameInputs):
    program = f.gpu.programs.get("frame/sky.glsl")
    bind_textures(program, {"u_env": f.gpu.sky})
    v = f.view
    set_uniforms(
        program,
        u_stars=night_amount(v.daylight.sun_elevation),
        **sky_disc_uniforms(v.daylight, v.size[1], v.camera.fov_y),
    )
    draw_fullscreen(program)


def resolve(f: FrameInputs):
    f.gpu.ctx.copy_framebuffer(f.gpu.targets.resolved.fbo, f.gpu.targets.hdr.fbo)


def ssao(f: FrameInputs):
    """Ambient occlusion from the resolved depth (resolve blits depth with colour)."""
    program = f.gpu.programs.get("frame/ssao.glsl")
    resolved, camera = f.gpu.targets.resolved, f.view.camera
    bind_textures(program, {"u_color": resolved.colors[0], "u_depth": resolved.depth})
    set_uniforms(
        program,
        u_near_far=(camera.near, camera.far),
        u_pixels_per_metre=f.view.size[1] / (2 * np.tan(np.radians(camera.fov_y) / 2)),
    )
    draw_fullscreen(program)


def tone_map_source(settings: RenderSettings) -> str:
    return "occluded" if settings.ssao else "resolved"


def _god_ray_uniforms(f: FrameInputs) -> dict:
    v = f.view
    return god_ray_uniforms(v.view_projection, v.camera.eye, v.daylight.sun_direction, v.daylight.sun_color)


def god_rays(f: FrameInputs):
    targets = f.gpu.targets
    hdr = targets.get(tone_map_source(f.view.settings)).colors[0]
    targets.god_rays.draw(f.gpu.programs, hdr, _god_ray_uniforms(f)["u_sun_screen"])


def tone_map(f: FrameInputs):
    rays = f.view.settings.god_rays
    program = f.gpu.programs.get("frame/tonemap.glsl", {"GOD_RAYS": rays})
    source = f.gpu.targets.get(tone_map_source(f.view.settings)).colors[0]
    bind_textures(program, {"u_hdr": source, **({"u_god_rays_image": f.gpu.targets.god_rays.image} if rays else {})})
    if rays:
        set_uniforms(program, **_god_ray_uniforms(f))
    draw_fullscreen(program)


def id_ground(f: FrameInputs):
    draw_ground(f, {"ID_PASS": True})


def id_trees(f: FrameInputs):
    draw_trees(f, ids=True)


# -- the frame --------------------------------------------------------------------------------------

CITY = ("city geometry", "building records")
ROOM_TEXTURES = ("room textures", "facade texture", "sprites", "curtain", "environment")
SHADING = ("shadow maps",)
OFF = GLState(depth_test=False)


def frame_passes(settings: RenderSettings) -> list[Pass]:
    """The passes of one frame, in the order they run."""
    shadows = SHADING if settings.shadows else ()
    grammar = ("grammar textures",)
    passes = []
    black = (0.0, 0.0, 0.0, 1.0)
    if settings.shadows:
        # cascaded shadow maps of buildings and trees, each cascade at its own rate (SpeedTree §4.3.2)
        passes.append(Pass("shadows", shadow_pass, (*CITY, "trees"), "shadow maps"))
    if settings.culling == "gpu":
        # the big buildings in the frustum into the depth buffer (back faces culled, as in the
        # buildings pass), its max-depth pyramid, then every building against frustum and pyramid
        # into draw commands (render/_visibility.py)
        passes.append(
            Pass("occluders", occluder_pass, CITY, "hdr", GLState(colour_write=False, cull=True), clear=black)
        )
        passes.append(Pass("hi-z", hiz_pass, ("hdr",), "depth pyramid", OFF))
        passes.append(Pass("cull", cull_pass, (*CITY, "depth pyramid"), "building draws", OFF))
    if settings.grammar_deferred:
        # Krecklau §4: a G-buffer, then one full-screen grammar evaluation per pixel, shadowed
        passes.append(
            Pass("grammar g-buffer", grammar_gbuffer, (*CITY, *grammar), "grammar_gbuffer", clear=(0.0, 0.0, 0.0, 0.0))
        )
        if settings.grammar_cache:
            # the pages the G-buffer names, evaluated once per texel into the cache's atlas
            passes.append(
                Pass("grammar cache update", grammar_cache_update, ("grammar_gbuffer", *grammar), "grammar cache", OFF)
            )
        passes.append(
            Pass(
                "grammar evaluation",
                grammar_evaluation,
                ("grammar_gbuffer", *grammar, *shadows),
                "grammar_result",
                OFF,
                clear=(0.0, 0.0, 0.0, 0.0),
            )
        )
    facade_inputs = (
        *CITY,
        *ROOM_TEXTURES,
        *grammar,
        "relief maps",
        *shadows,
        *(("grammar_result",) if settings.grammar_deferred else ()),
    )
    if settings.polygonised_interiors:
        # interior-mapping §3.1's baseline: exteriors with the glass cut out, real floors, ceilings
        # and walls (a floor and the ceiling below it share a plane: back faces culled), then the
        # glass's reflection blended over them
        passes.append(Pass("exteriors", polygonised_exteriors, facade_inputs, "hdr", GLState(cull=True), clear=black))
        room_depth = "<"
        if settings.depth_prepass:  # the rooms' own z-cull: each visible room pixel shaded once
            passes.append(
                Pass(
                    "room depth prepass",
                    draw_interior_depth,
                    ("room geometry",),
                    "hdr",
                    GLState(colour_write=False, cull=True),
                )
            )
            room_depth = "<="
        passes.append(
            Pass(
                "rooms",
                polygonised_rooms,
                ("room geometry", *ROOM_TEXTURES),
                "hdr",
                GLState(depth_func=room_depth, cull=True),
            )
        )
        passes.append(
            Pass(
                "window glass",
                polygonised_glass,
                facade_inputs,
                "hdr",
                GLState(depth_write=False, cull=True, blend=(moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA)),
            )
        )
    elif settings.depth_prepass:
        # interior-mapping §3.1 "z-cull": the buildings into the z-buffer first, so the buildings
        # pass shades only the visible surface (back faces culled, as there). Not the ground: flat,
        # it hides no building, and drawn after them it meets their depth anyway
        passes.append(
            Pass("depth prepass", depth_prepass, CITY, "hdr", GLState(colour_write=False, cull=True), clear=black)
        )
        if settings.relief:
            # the farthest prepass depth of each pixel, for the buildings that write their relief's
            # depth: a rasteriser tests such a fragment's depth after shading it (llvmpipe does), so
            # the buildings pass rejects it itself where it lies behind that
            passes.append(Pass("prepass farthest", farthest_pass, ("hdr",), "farthest depth", OFF))
            facade_inputs = (*facade_inputs, "farthest depth")
    # "<=" with the prepass (a surface must pass its own depth) and without, so that where two
    # surfaces meet at one depth the one drawn last wins either way and the prepass changes no pixel
    shading_depth = "<" if settings.polygonised_interiors else "<="
    # facades; behind the glass, interior-mapped rooms. The buildings are closed and wound
    # counter-clockwise seen from outside: their back faces are culled, which a program writing
    # gl_FragDepth would shade before its depth test, and whose depth (the pixel centre's, for every
    # sample) can beat the front face's at a silhouette
    if not settings.polygonised_interiors:
        passes.append(
            Pass(
                "buildings",
                draw_buildings,
                facade_inputs,
                "hdr",
                GLState(depth_func=shading_depth, cull=True),
                clear=None if settings.depth_prepass else black,
            )
        )
    # streets, pavements, parks; they receive the shadows
    passes.append(
        Pass("ground", draw_ground, (*CITY, "environment", *shadows), "hdr", GLState(depth_func=shading_depth))
    )
    if settings.trees:
        # trunks, fins, leaf cards, fronds with alpha to coverage (render/_trees.py sets cull per part)
        passes.append(
            Pass("trees", trees, ("trees", "tree textures", "environment", *shadows), "hdr", GLState(depth_func="<="))
        )
    passes.append(Pass("sky", draw_sky, ("environment",), "hdr", GLState(depth_func="<=")))  # where nothing was drawn
    passes.append(Pass("resolve", resolve, ("hdr",), "resolved", OFF))  # multisampled HDR -> single-sample HDR
    if settings.ssao:
        # screen-space ambient occlusion from the resolved depth (Krecklau §4's pipeline)
        passes.append(Pass("ssao", ssao, ("resolved",), "occluded", OFF))
    # god rays around the sun (SpeedTree §4.5), then HDR -> sRGB 8-bit
    tone_map_reads = (tone_map_source(settings),)
    if settings.god_rays:
        passes.append(Pass("god rays", god_rays, tone_map_reads, "god_rays", OFF))
        tone_map_reads += ("god_rays",)
    passes.append(Pass("tone map", tone_map, tone_map_reads, "display", OFF))
    return passes


def id_passes(settings: RenderSettings, room_state: bool = False, windows: bool = False) -> list[Pass]:
    """The id AOV: per pixel (face, room id, building index + 1, grammar label) as uint32, trees as
    (FACE_TRUNK or FACE_FOLIAGE, 0, 0, 0); with `room_state` the fourth channel is the room seen
    instead (1 | lit << 1 | variant << 2, 0: none), with `windows` the window it is seen through
    (a key per window of its building, 0: none)."""

    def id_buildings(f: FrameInputs):
        draw_buildings(
            f,
            {
                "ID_PASS": True,
                "ID_ROOM_STATE": room_state,
                "ID_WINDOW": windows,
                "INTERIOR_LOD": False,
                "BUILDING_LOD": False,
            },
        )

    inputs = (*CITY, "grammar textures", "relief maps")
    passes = [
        Pass("building ids", id_buildings, inputs, "ids", clear=(0.0, 0.0, 0.0, 0.0)),
        Pass("ground ids", id_ground, CITY, "ids"),
    ]
    if settings.trees:
        # trunks and fins FACE_TRUNK, leaf cards and fronds FACE_FOLIAGE, alpha-tested
        passes.append(Pass("tree ids", id_trees, ("trees", "tree textures"), "ids", GLState(depth_func="<=")))
    return passes


def run_passes(f: FrameInputs, passes: list[Pass], times: dict[str, float] | None = None):
    """Runs the passes in order. With `times`, each pass's wall time in seconds is stored under its
    name, measured with ctx.finish() before and after it."""
    f.write_frame_blocks()
    for p in passes:
        if times is not None:
            f.gpu.ctx.finish()
            start = time.perf_counter()
        target = f.gpu.targets.get(p.writes)
        if target is not None:
            target.use()
            if p.clear is not None:
                f.gpu.ctx.color_mask, f.gpu.ctx.depth_mask = (True,) * 4, True  # a clear writes only through the masks
                target.fbo.clear(*p.clear, depth=1.0)
        p.state.apply(f.gpu.ctx)
        p.draw(f)
        if times is not None:
            f.gpu.ctx.finish()
            times[p.name] = time.perf_counter() - start
