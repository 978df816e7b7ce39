"""The buildings as the frame's passes draw them: their shading program's defines and draws
(city/building.glsl), split by relief, and their depth-only programs."""

from __future__ import annotations

from ..frame import Frame
from ..gl import R32F, bind_textures, binding, set_uniforms
from ..grammar import bind_grammar_results
from ..grammar import shader_defines as grammar_defines
from ..relief import switch_distance
from ._textures import CityTextures


def city_textures(f: Frame) -> CityTextures:
    textures = f.technique(CityTextures)
    if textures is None:
        raise RuntimeError("a frame without the city's textures")
    return textures


def building_defines(f: Frame, **extra) -> dict:
    s = f.view.settings
    return {
        "INTERIOR_MAPPING": s.interior_mapping,
        "IM_SINGLE_ATLAS": s.single_atlas,
        "INTERIOR_LOD": s.lod,
        "BUILDING_LOD": s.building_lod,
        "RELIEF_OFF": not s.relief,
        "NO_SHADOWS": f.shadows is None,
        **extra,
    }


def relief_switch(f: Frame) -> float:
    """Metres within which grammar and window-bay openings are traced (relief.switch_distance)."""
    switch = f.view.settings.relief_range
    return switch_distance(f.view.size[1], f.view.camera.fov_y) if switch is None else switch


def relief_parts(f: Frame) -> tuple[dict, ...]:
    """The buildings' draws, as defines: with relief on, two (common/building_vertex.glsl): the
    buildings a relief may be traced on (RELIEF_NEAR: relief-bay buildings, and those within the
    switch distance), by a program that writes the relief's depth, then the others (RELIEF_FAR)
    by one that keeps the rasterised depth, whose fragments a rasteriser can still reject by
    depth before shading them (llvmpipe tests depth after shading in a program that writes
    gl_FragDepth); with relief off, one."""
    return ({"RELIEF_NEAR": True}, {"RELIEF_FAR": True}) if f.view.settings.relief else ({},)


def buildings_depth_programs(f: Frame) -> list:
    """The buildings' depth-only programs for the camera (the depth prepass, GPU culling's
    occluders), one per relief part: a wall that may be recessed writes the deepest depth its
    relief may give (shaders/relief/depth.glsl), so the traced depth passes the buildings pass's
    test; the far part writes the rasterised depth as its shading program does, sample by sample."""
    out = []
    for part in relief_parts(f):
        program = f.programs.get(
            "city/building.glsl", {"DEPTH_ONLY": True, "RELIEF_DEPTH_BOUND": "RELIEF_NEAR" in part, **part}
        )
        set_uniforms(program, u_view_proj=f.view.view_projection)
        if part:
            f.city.relief.bind_depth_bound(program, relief_switch(f))
        out.append(program)
    return out


def depth_prepass(f: Frame):
    for program in buildings_depth_programs(f):
        f.draw_buildings(program)


def draw_buildings(f: Frame, defines: dict | None = None):
    """The buildings' shading program (city/building.glsl), in relief_parts's draws (the
    polygonised baseline's, which write no relief depth, in one)."""
    defines = {**grammar_defines(), "GRAMMAR_DEFERRED": f.view.settings.grammar_deferred, **(defines or {})}
    polygonised = defines.get("POLYGONISED_EXTERIOR") or defines.get("POLYGONISED_WINDOWS")
    after_prepass = f.view.settings.depth_prepass and not defines.get("ID_PASS")
    for part in ({},) if polygonised else relief_parts(f):
        # the part that writes its depth rejects what lies behind the prepass itself (farthest_pass)
        farthest = after_prepass and "RELIEF_NEAR" in part
        # and is drawn in two, its grammar buildings and the others (common/building_vertex.glsl)
        for kind in ({"NEAR_GRAMMAR": True}, {"NEAR_OTHER": True}) if "RELIEF_NEAR" in part else ({},):
            draw_buildings_with(f, {**defines, **part, **kind, "PREPASS_FARTHEST": farthest})


def draw_buildings_with(f: Frame, defines: dict):
    textures = city_textures(f)
    program = f.programs.get("city/building.glsl", building_defines(f, **defines))
    bind_textures(program, {**f.room_textures, "u_env": f.env, "u_facade": textures.facade})
    set_uniforms(program, u_view_proj=f.view.view_projection)
    textures.grammar.bind(program)
    if f.view.settings.grammar_deferred:
        bind_grammar_results(f, program)
    if defines.get("PREPASS_FARTHEST"):
        f.city.visibility.farthest.bind_to_image(binding("u_prepass_farthest"), read=True, write=False, format=R32F)
    f.city.relief.bind(program, relief_switch(f))
    f.city.street_lights.bind(program)
    if defines.get("BUILDING_LOD", f.view.settings.building_lod):
        f.city.bind_lod_colours()
    if f.shadows is not None:
        f.shadows.bind(program)
    f.draw_buildings(program)
