"""The frame: an ordered list of passes, built from the settings (docs/frame.md lists them).

Each pass (cityshade.frame.Pass) has a name, declares the targets it writes and reads, and sets
every piece of GL state it relies on (GLState) before it draws, so no pass depends on what an
earlier one left. `frame_passes` below reads top to bottom in the order the passes run;
cityshade.frame.run_passes makes the targets they declare and runs them. The techniques' own
passes come from their packages (trees, interior, grammar).

`id_passes` render the id AOV (face, room, building, label) used by tests and datasets.
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..frame import HDR, IDS, Frame, GLState, Pass, RenderSettings, Target
from ..gl import FRAME_BLOCK, MAX_USES, SHADING_BLOCK, bind_textures, draw_fullscreen, set_uniforms
from ..grammar import grammar_passes
from ..interior import ROOM_TEXTURES, room_passes
from ..scene import FLAG_CURTAINS, FLAG_FURNITURE, FLAG_ROOM_VARIATION, lit_shares
from ..trees import TREE_ID_PASS, tree_pass
from ._building_lod import bay_mean, lod_distances, relief_mean
from ._buildings import depth_prepass, draw_buildings
from ._godrays import GOD_RAY_STEPS, GOD_RAYS, draw_god_rays, god_ray_uniforms
from ._night_sky import night_amount
from ._shadows import shadow_pass
from ._sky_discs import sky_disc_uniforms
from ._textures import CityTextures
from ._visibility import cull_pass, farthest_pass, hiz_pass, occluder_pass

ROOM_LIGHT = np.array([1.0, 0.78, 0.52]) * 1.1
ROOM_DARK = np.array([0.018, 0.02, 0.03])
WINDOW_TINT = np.array([0.02, 0.025, 0.03])  # the glass where no room is drawn behind it

RESOLVED = Target("resolved")  # the HDR colour and depth, single-sample
OCCLUDED = Target("occluded")  # the resolve with ambient occlusion
DISPLAY = Target("display", (("f1", 4),))  # the 8-bit sRGB image


def write_frame_blocks(f: Frame, textures: CityTextures):
    """The values programs share, once per frame: camera, sun and sky for every program
    (cityshade.gl.FRAME_BLOCK), rooms, windows and lamps for the city's (SHADING_BLOCK)."""
    s, d, t = f.view.settings, f.view.daylight, textures
    FRAME_BLOCK.write(
        f.ctx,
        u_inv_view_proj=np.linalg.inv(f.view.view_projection),
        u_camera=f.view.camera.eye,
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
        f.ctx,
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
        u_building_lod=lod_distances(s.building_lod_pixels, f.view.size[1], f.view.camera.fov_y),
        u_atlas_layout=(layout["tile"], layout["padding"], t.atlas.width, t.atlas.height),
    )


# -- what the passes draw ---------------------------------------------------------------------------


def polygonised_exteriors(f: Frame):
    """The polygonised-interiors baseline (interior-mapping §3.1), with what a competent
    implementation has (back faces culled throughout, a depth prepass for the rooms), starts with
    the exterior walls, the glass cut out: they hide most of the rooms' geometry."""
    draw_buildings(f, {"INTERIOR_MAPPING": False, "POLYGONISED_EXTERIOR": True})


def polygonised_glass(f: Frame):
    draw_buildings(f, {"INTERIOR_MAPPING": False, "POLYGONISED_WINDOWS": True})


def draw_ground(f: Frame, defines: dict | None = None):
    program = f.programs.get("city/ground.glsl", {"NO_SHADOWS": f.shadows is None, **(defines or {})})
    bind_textures(program, {"u_env": f.env})
    set_uniforms(program, u_view_proj=f.view.view_projection)
    if f.shadows is not None:
        f.shadows.bind(program)
    f.city.street_lights.bind(program)
    f.city.draw_ground(program)


def draw_sky(f: Frame):
    program = f.programs.get("frame/sky.glsl")
    bind_textures(program, {"u_env": f.sky})
    v = f.view
    set_uniforms(
        program,
        u_stars=night_amount(v.daylight.sun_elevation),
        **sky_disc_uniforms(v.daylight, v.size[1], v.camera.fov_y),
    )
    draw_fullscreen(program)


def resolve(f: Frame):
    f.ctx.copy_framebuffer(f.targets[RESOLVED.name].fbo, f.targets[HDR.name].fbo)


def ssao(f: Frame):
    """Ambient occlusion from the resolved depth (resolve blits depth with colour)."""
    program = f.programs.get("frame/ssao.glsl")
    resolved, camera = f.targets[RESOLVED.name], f.view.camera
    bind_textures(program, {"u_color": resolved.colors[0], "u_depth": resolved.depth})
    set_uniforms(
        program,
        u_near_far=(camera.near, camera.far),
        u_pixels_per_metre=f.view.size[1] / (2 * np.tan(np.radians(camera.fov_y) / 2)),
    )
    draw_fullscreen(program)


def tone_map_source(settings: RenderSettings) -> Target:
    return OCCLUDED if settings.ssao else RESOLVED


def _god_ray_uniforms(f: Frame) -> dict:
    v = f.view
    return god_ray_uniforms(v.view_projection, v.camera.eye, v.daylight.sun_direction, v.daylight.sun_color)


def god_rays(f: Frame):
    hdr = f.targets[tone_map_source(f.view.settings).name].colors[0]
    steps = (f.targets[GOD_RAY_STEPS.name], f.targets[GOD_RAYS.name])
    draw_god_rays(f.programs, hdr, _god_ray_uniforms(f)["u_sun_screen"], steps)


def tone_map(f: Frame):
    rays = f.view.settings.god_rays
    program = f.programs.get("frame/tonemap.glsl", {"GOD_RAYS": rays})
    source = f.targets[tone_map_source(f.view.settings).name].colors[0]
    images = {"u_god_rays_image": f.targets[GOD_RAYS.name].colors[0]} if rays else {}
    bind_textures(program, {"u_hdr": source, **images})
    if rays:
        set_uniforms(program, **_god_ray_uniforms(f))
    draw_fullscreen(program)


def id_ground(f: Frame):
    draw_ground(f, {"ID_PASS": True})


# -- the frame --------------------------------------------------------------------------------------

CITY = ("city geometry", "building records")
SHADING = ("shadow maps",)
OFF = GLState(depth_test=False)
BLACK = (0.0, 0.0, 0.0, 1.0)


def frame_passes(settings: RenderSettings) -> list[Pass]:
    """The passes of one frame, in the order they run."""
    shadows = SHADING if settings.shadows else ()
    grammar = ("grammar textures",)
    passes = []
    if settings.shadows:
        # cascaded shadow maps of buildings and trees, each cascade at its own rate (SpeedTree §4.3.2)
        passes.append(Pass("shadows", shadow_pass, (*CITY, "trees"), "shadow maps"))
    if settings.culling == "gpu":
        # the big buildings in the frustum into the depth buffer (back faces culled, as in the
        # buildings pass), its max-depth pyramid, then every building against frustum and pyramid
        # into draw commands (render/_visibility.py)
        passes.append(Pass("occluders", occluder_pass, CITY, HDR, GLState(colour_write=False, cull=True), clear=BLACK))
        passes.append(Pass("hi-z", hiz_pass, (HDR,), "depth pyramid", OFF))
        passes.append(Pass("cull", cull_pass, (*CITY, "depth pyramid"), "building draws", OFF))
    if settings.grammar_deferred:
        passes += grammar_passes(CITY, settings.grammar_cache, shadows)
    facade_inputs = (
        *CITY,
        *ROOM_TEXTURES,
        *grammar,
        "relief maps",
        *shadows,
        *((passes[-1].writes,) if settings.grammar_deferred else ()),  # the grammar's evaluation
    )
    if settings.polygonised_interiors:
        # interior-mapping §3.1's baseline: exteriors with the glass cut out, real floors, ceilings
        # and walls, then the glass's reflection blended over them
        passes.append(Pass("exteriors", polygonised_exteriors, facade_inputs, HDR, GLState(cull=True), clear=BLACK))
        passes += room_passes(settings.depth_prepass)
        passes.append(
            Pass(
                "window glass",
                polygonised_glass,
                facade_inputs,
                HDR,
                GLState(depth_write=False, cull=True, blend=(moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA)),
            )
        )
    elif settings.depth_prepass:
        # interior-mapping §3.1 "z-cull": the buildings into the z-buffer first, so the buildings
        # pass shades only the visible surface (back faces culled, as there). Not the ground: flat,
        # it hides no building, and drawn after them it meets their depth anyway
        passes.append(
            Pass("depth prepass", depth_prepass, CITY, HDR, GLState(colour_write=False, cull=True), clear=BLACK)
        )
        if settings.relief:
            # the farthest prepass depth of each pixel, for the buildings that write their relief's
            # depth: a rasteriser tests such a fragment's depth after shading it (llvmpipe does), so
            # the buildings pass rejects it itself where it lies behind that
            passes.append(Pass("prepass farthest", farthest_pass, (HDR,), "farthest depth", OFF))
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
                HDR,
                GLState(depth_func=shading_depth, cull=True),
                clear=None if settings.depth_prepass else BLACK,
            )
        )
    # streets, pavements, parks; they receive the shadows
    passes.append(Pass("ground", draw_ground, (*CITY, "environment", *shadows), HDR, GLState(depth_func=shading_depth)))
    if settings.trees:
        passes.append(tree_pass(shadows))
    passes.append(Pass("sky", draw_sky, ("environment",), HDR, GLState(depth_func="<=")))  # where nothing was drawn
    passes.append(Pass("resolve", resolve, (HDR,), RESOLVED, OFF))  # multisampled HDR -> single-sample HDR
    if settings.ssao:
        # screen-space ambient occlusion from the resolved depth (Krecklau §4's pipeline)
        passes.append(Pass("ssao", ssao, (RESOLVED,), OCCLUDED, OFF))
    # god rays around the sun (SpeedTree §4.5), in two half-resolution targets by turns, then HDR -> sRGB 8-bit
    tone_map_reads: tuple[Target, ...] = (tone_map_source(settings),)
    if settings.god_rays:
        passes.append(Pass("god rays", god_rays, tone_map_reads, GOD_RAYS, OFF, scratch=(GOD_RAY_STEPS,)))
        tone_map_reads += (GOD_RAYS,)
    passes.append(Pass("tone map", tone_map, tone_map_reads, DISPLAY, OFF))
    return passes


def id_passes(settings: RenderSettings, room_state: bool = False, windows: bool = False) -> list[Pass]:
    """The id AOV: per pixel (face, room id, building index + 1, grammar label) as uint32, trees as
    (FACE_TRUNK or FACE_FOLIAGE, 0, 0, 0); with `room_state` the fourth channel is the room seen
    instead (1 | lit << 1 | variant << 2, 0: none), with `windows` the window it is seen through
    (a key per window of its building, 0: none)."""

    def id_buildings(f: Frame):
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
        Pass("building ids", id_buildings, inputs, IDS, clear=(0.0, 0.0, 0.0, 0.0)),
        Pass("ground ids", id_ground, CITY, IDS),
    ]
    if settings.trees:
        passes.append(TREE_ID_PASS)
    return passes
