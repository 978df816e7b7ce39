// Relief facades on the city's buildings (included by city/building.glsl after grammar/building.glsl).
// One atlas of detail maps, factorised with BMF and traced with facade displacement mapping
// (cityshade/relief/_city.py): region 0 is the window bay that repeats across the walls of the
// relief-bay buildings (record facade.x = FACADE_RELIEF; one bay wide, one floor high, so its
// windows sit in the interior-mapped rooms); region 1 the textured window bay's window (style 0,
// stretched over its glass rectangle: city/building.glsl window_bay_relief); the other regions are the window openings of the
// grammar styles, one per glazed terminal or hole (a SkipMask's cut), each fitted to the window the
// grammar puts there, so the relief's windows are the flat grammar's windows, recessed.
// RELIEF_OFF: no relief anywhere (relief-bay buildings draw the window bay).
#ifndef RELIEF_BUILDING_GLSL
#define RELIEF_BUILDING_GLSL

#define CODEC_BMF
#define TRACER_FDM
#define RELIEF_REGIONS
#include "common/buildings.glsl"
#include "common/facade.glsl"
#include "common/srgb.glsl"
#include "relief/maps.glsl"
#include "relief/trace.glsl"
#include "relief/materials.glsl"
#include "relief/openings.glsl"

uniform float u_relief_depth_unit;  // metres per depth step
uniform ivec4 u_relief_bay;         // the window bay's region (first row, columns, rows, 1: repeats)
uniform ivec4 u_relief_window_bay;  // the textured window bay's opening (first row, columns, rows, 0)
uniform vec3 u_relief_colours[2 * RELIEF_MAX_OPENINGS];  // per opening: sRGB frame, reveal (the flat grammar's)
uniform ivec2 u_relief_profile;     // an opening's columns and rows, the ring of wall texels included
uniform float u_relief_range;       // metres: openings are traced nearer than this, flat grammar beyond

bool has_relief_facade(Building b) {
#if defined RELIEF_OFF
    return false;
#else
    return b.facade.x == FACADE_RELIEF;
#endif
}

// start: the wall point in map space; scale: map units per metre along (mesh u, up, into the wall).
// The result's point is where the ray meets the relief (the room behind recessed glass shows from
// there); no specular.
FacadeResult relief_traced(Building b, vec3 n, vec3 wall, vec3 start, vec3 scale, vec3 d, out uint material) {
    vec3 up = vec3(0.0, 1.0, 0.0);
    vec3 along = normalize(cross(n, up));  // the direction mesh u grows (right to left seen from outside)
    ReliefHit h = relief_trace(start, vec3(dot(d, along), d.y, -dot(d, n)) * scale, FACE_FRONT);
    vec3 offset = (h.point - start) / scale;
    vec3 normal = h.face == FACE_NEG_X ? -along : h.face == FACE_POS_X ? along
                : h.face == FACE_NEG_Y ? -up : h.face == FACE_POS_Y ? up : n;
    material = h.material;
    vec3 albedo = srgb_to_linear(relief_albedo(h.material, h.point.xy / scale.xy, h.face));
    return FacadeResult(albedo * building_tint(b), normal, vec2(0.0), h.hit && h.material == RELIEF_GLASS ? 1.0 : 0.0,
                        wall + along * offset.x + up * offset.y - n * offset.z, 0u);
}

// The window bay: n the wall's object-space normal, wall the rasterised wall point (object space),
// facade the mesh's (u, v above the face's base) and spacing its (bay width, storey height), in
// metres, so the bay repeats once per room; d the unit view ray (object space).
FacadeResult relief_building(Building b, vec3 n, vec3 wall, vec2 facade, vec2 spacing, vec3 d) {
    relief_region = u_relief_bay;
    vec3 scale = vec3(vec2(u_relief_bay.yz) / spacing, 1.0 / u_relief_depth_unit);  // map units per metre
    uint material;
    return relief_traced(b, n, wall, vec3(facade, 0.0) * scale, scale, d, material);
}

// The opening at atlas region `region` (its ring of wall texels included) stretched over the window
// rectangle `rect` (facade coordinates: u0, v0, u1, v1, as `facade`) and traced from the wall point.
FacadeResult opening_traced(Building b, vec3 n, vec3 wall, vec2 facade, vec4 rect, ivec4 region, vec3 d,
                            out uint material) {
    relief_region = region;
    vec3 scale = vec3(vec2(region.yz - 2) / (rect.zw - rect.xy), 1.0 / u_relief_depth_unit);
    vec3 start = vec3(1.0 + (facade - rect.xy) * scale.xy, 0.0);
    return relief_traced(b, n, wall, start, scale, d, material);
}

#if defined GRAMMAR_DEFERRED && !defined ID_PASS
// the deferred pass's opening scopes (grammar/_frame_pass.py; an image: the samplers are all taken)
layout(rgba32f, binding = BINDING_GRAMMAR_DEFERRED_OPENING) readonly uniform image2D u_grammar_deferred_opening;

// The opening the deferred pass found at this pixel (grammar/deferred.glsl), the flat grammar's
// glass there and its colour (sRGB, to 8 bits); false where it passed none on (a pixel the page
// cache answered, or one it did not evaluate) or found it on another face than this fragment's
// (face_key: grammar_face_key): the caller evaluates the grammar then.
bool grammar_deferred_opening(uint face_key, out GrammarOpening o, out bool glass, out vec3 color) {
    uvec4 ids = texelFetch(u_grammar_deferred_ids, ivec2(gl_FragCoord.xy), 0);
    o = GrammarOpening(int(ids.x >> GRAMMAR_DEFERRED_OPENING_SHIFT & 0xFFu) - 1, (ids.x & GRAMMAR_DEFERRED_HOLE_OPENING) != 0u,
                       imageLoad(u_grammar_deferred_opening, ivec2(gl_FragCoord.xy)));
    glass = (ids.x & GRAMMAR_DEFERRED_GLASS) != 0u;
    color = unpackUnorm4x8(ids.y).rgb;
    return (ids.x & GRAMMAR_DEFERRED_OPENING) != 0u && (ids.x >> GRAMMAR_DEFERRED_FACE_SHIFT & 0xFFFFu) == face_key;
}
#endif

// A grammar facade's window, recessed: where the flat grammar (facade result f, its window
// `opening`) shows a glazed terminal with an opening, the opening's profile is stretched over the
// window's rectangle (facade coordinates, as the grammar fits its tile there) and traced; f and
// opening become the relief's (the rectangle: the room behind is the window's). Where it shows what
// a hole lets through (GrammarResult.hole: dusk's rooms), the hole's profile is stretched over the
// hole's scope and traced; through its bottom, the grammar seen through that hole from where the ray
// meets it (the hole's room, entered from the recessed point). building: b's index; s: the
// distance; hole_seen: the flat grammar shows a hole here (grammar_building_facade). With
// GRAMMAR_DEFERRED the deferred pass found the opening (grammar_deferred_opening), else it is
// evaluated here. Returns whether the relief was traced.
bool grammar_relief(Building b, int building, vec3 n, int face_index, vec3 wall, vec2 facade, float storey, vec4 face, vec3 d,
                    float s, bool hole_seen, inout FacadeResult f, inout vec4 opening) {
#if defined RELIEF_OFF
    return false;
#else
    if (s > u_relief_range || (f.glass <= 0.0 && f.label != uint(GRAMMAR_WINDOW_LABEL) && !hole_seen)) return false;
    vec2 duv_dx = dFdx(facade), duv_dy = dFdy(facade);
    GrammarOpening o;
    bool glass;  // the flat grammar's, at the wall point
    vec3 color;  // sRGB
#if defined GRAMMAR_DEFERRED && !defined ID_PASS
    uint key = grammar_face_key(building, grammar_facade_cells(b.facade.zw, face_index));
    bool found = grammar_deferred_opening(key, o, glass, color);
#else
    bool found = false;
#endif
    if (!found) {
        GrammarResult g = grammar_facade(b, n, face_index, facade, storey, face, d, duv_dx, duv_dy);
        o = grammar_opening(g);
        glass = g.glass;
        color = g.color;
    }
    if (o.index < 0) return false;
    vec4 rect = grammar_window(o.scope, face);
    uint material;
    f = opening_traced(b, n, wall, facade, rect, ivec4(u_relief_terminals[o.index].y, u_relief_profile, 0), d, material);
    opening = rect;
    if (o.hole && material == RELIEF_GLASS) {
        vec3 offset = f.point - wall;
        grammar_through = u_relief_terminals[o.index].x;  // the hole's SkipMask
        GrammarResult behind = grammar_facade(b, n, face_index, facade + vec2(dot(offset, normalize(cross(n, vec3(0.0, 1.0, 0.0)))), offset.y),
                                              storey, face, d, duv_dx, duv_dy);
        f = grammar_facade_result(behind, n, f.point);
        if (behind.glass) opening = grammar_window(behind.scope, face);
        return true;
    }
    // the frame and the reveal in the flat grammar's colours (the grammar's own, untinted): the
    // tile's own colour where the wall point is on the frame too, else the frame's mean colour
    if (material == RELIEF_FRAME) f.albedo = srgb_to_linear(glass ? u_relief_colours[2 * o.index] : color);
    else if (material == RELIEF_WALL) f.albedo = srgb_to_linear(u_relief_colours[2 * o.index + 1]);
    f.label = f.glass > 0.0 ? uint(GRAMMAR_ROOM_LABEL) : uint(GRAMMAR_WINDOW_LABEL);
    return true;
#endif
}

#endif
