// Buildings: one draw call for the whole city. Exterior bay texture whose alpha marks the glass
// (interior-mapping §2.3); behind the glass, rooms ray-cast per pixel (interior/interior.glsl).
// Defines: DEPTH_ONLY (z prepass; with RELIEF_DEPTH_BOUND the deepest depth the relief may give,
// relief/depth.glsl), PREPASS_FARTHEST (after the prepass: a fragment behind it is discarded unshaded), ID_PASS (face/room/building ids; the fourth channel is the grammar
// label, or with ID_ROOM_STATE the room seen, or with ID_WINDOW the window it is seen through), INTERIOR_MAPPING (off: the
// reflective-only windows baseline), IM_SINGLE_ATLAS, INTERIOR_LOD, BUILDING_LOD (city/lod.glsl); the polygonised-interiors
// baseline draws the buildings twice: POLYGONISED_EXTERIOR (glass cut out) before its real rooms,
// POLYGONISED_WINDOWS (only the glass's reflection, alpha = Fresnel, for blending) after them.

#include "common/building_vertex.glsl"

#if defined FRAGMENT_SHADER
#include "common/buildings.glsl"
// Where a relief is traced the fragment takes its depth; the prepass writes the deepest it may be.
// (The polygonised baseline's rooms and glass are real geometry at the wall: it keeps the wall's.)
// RELIEF_FAR (common/building_vertex.glsl) draws only buildings no relief is traced on: the depth stays.
#if (defined DEPTH_ONLY && defined RELIEF_DEPTH_BOUND) || \
    (!defined DEPTH_ONLY && !defined RELIEF_OFF && !defined RELIEF_FAR && !defined POLYGONISED_EXTERIOR && \
     !defined POLYGONISED_WINDOWS)
#define RELIEF_DEPTH
#endif
#include "relief/depth.glsl"
#if defined DEPTH_ONLY && defined RELIEF_DEPTH_BOUND
in vec3 v_world;
in vec3 v_normal;
flat in ivec4 v_ids;
void main() { gl_FragDepth = relief_depth_bound(buildings[v_ids.x], v_world, normalize(v_normal), v_ids.y); }
#elif defined DEPTH_ONLY
void main() {}
#else
#include "common/hash.glsl"
#include "generated/ShadingBlock.glsl"
#include "common/lighting.glsl"
#include "common/facade.glsl"
#include "shadow/csm.glsl"
#if defined INTERIOR_MAPPING
#include "interior/interior.glsl"
#endif
#include "grammar/building.glsl"
#include "relief/building.glsl"
#include "city/roof.glsl"
#include "city/doors.glsl"
#include "city/street_lights.glsl"
#include "city/lod.glsl"
const float STREET_LIT_ALBEDO = 0.35;  // facades and roofs as one grey under the lamps
const vec3 NO_ROOM_PANE = vec3(0.02, 0.022, 0.025);  // an outbuilding's pane: dark glass, nothing behind it
const float NO_ROOM_PANE_F0 = 0.15;                 // dusty glass in front of a dark space

uniform sampler2D u_facade;     // one window bay; alpha 0 = glass
#if defined PREPASS_FARTHEST
// the farthest depth of each pixel's samples after the prepass (an image: the samplers are all taken)
layout(r32f, binding = BINDING_PREPASS_FARTHEST) readonly uniform image2D u_prepass_farthest;
const float PREPASS_MARGIN = 2.0 / 16777216.0;  // two steps of the 24-bit depth buffer
#endif

in vec3 v_world;
in vec3 v_local;
in vec3 v_normal;
in vec2 v_facade;
flat in vec2 v_spacing;
flat in vec4 v_face;
flat in ivec4 v_ids;

#if defined ID_PASS
layout(location = 0) out uvec4 out_ids;   // face, room, building + 1, grammar label (0: none)
#else
layout(location = 0) out vec4 out_color;
#endif

#if defined INTERIOR_MAPPING
// Which window of its face a glass pixel belongs to, for counting windows that show more than one
// room (cityshade.interior.windows_straddling_rooms): the grammar's window by its rectangle, a
// window bay by its bay and storey; never 0.
uint window_id(vec4 opening, WallFace f) {
    bool point = all(equal(opening.xy, opening.zw));
    vec2 centre = 0.5 * (opening.xy + opening.zw);
    ivec2 cell = point ? ivec2(floor(vec2(centre.x / f.bay, (centre.y - f.base) / f.storey)))
                       : ivec2(round(centre * 8.0));
    return max(hash3(ivec3(cell, f.columns.x * 65536 + f.columns.y), 0x57u), 1u);
}
#endif

// The window bay (interior mapping §2.3): one bay texture repeated across the face, one bay per
// room and storey, its alpha marking the glass, behind which the rooms are ray-cast (below).
FacadeResult window_bay(Building b, vec3 n, vec3 wall, vec2 bay_uv) {
#if defined ID_PASS
    // the exact texel decides glass, as in the numpy twin
    ivec2 texel = ivec2(fract(bay_uv) * vec2(textureSize(u_facade, 0)));
    float glass = texelFetch(u_facade, texel, 0).a < 0.5 ? 1.0 : 0.0;
    return FacadeResult(vec3(0.0), n, vec2(0.0), glass, wall, 0u);
#else
    vec4 exterior = textureGrad(u_facade, bay_uv, dFdx(bay_uv), dFdy(bay_uv));
    return FacadeResult(exterior.rgb * building_tint(b), n, vec2(0.0), 1.0 - exterior.a, wall, 0u);
#endif
}

// The window bay's window recessed near the eye (style 0, as the grammar windows: relief/building.glsl),
// on flat walls (relief.RELIEF_SHAPES; curved walls keep the flat bay):
// where the flat bay shows glass (the exact texel, as window_bay's id pass), the bay's opening is
// stretched over that bay's glass rectangle and traced, so the glass stays where the flat bay has it;
// the reveal in the bay's frame colour (the texel below the glass's centre). facade: (u, v above the
// face's base); s: the distance. Returns whether it traced; f becomes the relief's.
bool window_bay_relief(Building b, vec3 n, vec3 wall, vec2 facade, vec2 spacing, vec3 d, float s,
                       inout FacadeResult f) {
#if defined RELIEF_OFF || defined POLYGONISED_EXTERIOR || defined POLYGONISED_WINDOWS
    return false;
#else
    vec2 bay_uv = facade / spacing;
    ivec2 size = textureSize(u_facade, 0);
    if (b.ids.w != SHAPE_PRISM || s > u_relief_range || texelFetch(u_facade, ivec2(fract(bay_uv) * vec2(size)), 0).a >= 0.5) return false;
    vec2 cell = floor(bay_uv);
    vec4 rect = vec4((cell + u_glass_rect.xy) * spacing, (cell + u_glass_rect.zw) * spacing);
    uint material;
    f = opening_traced(b, n, wall, facade, rect, u_relief_window_bay, d, material);
    if (material != RELIEF_GLASS) {
        vec2 frame = vec2(0.5 * (u_glass_rect.x + u_glass_rect.z), u_glass_rect.y - 0.5 / float(size.y));
        f.albedo = texelFetch(u_facade, ivec2(frame * vec2(size)), 0).rgb * building_tint(b);
    }
    return true;
#endif
}

void main() {
#if defined PREPASS_FARTHEST
    // after the depth prepass (render/_frame.py): the depth this fragment writes is never nearer
    // than its own (relief/depth.glsl), so beyond the farthest of its pixel's samples (and the
    // rounding of the written depth) it fails every sample's test; rejected before it is shaded
    if (gl_FragCoord.z > imageLoad(u_prepass_farthest, ivec2(gl_FragCoord.xy)).r + PREPASS_MARGIN) discard;
#endif
    Building b = buildings[v_ids.x];
    mat3 rot = building_rotation(b);
    vec3 n = normalize(v_normal);
    vec3 n_world = rot * n;
    vec3 camera = transpose(rot) * (u_camera - b.origin_yaw.xyz);
    vec3 to_surface = v_local - camera;
    float s = length(to_surface);
    vec3 d = to_surface / s;

    int face = FACE_EXTERIOR;
    uint room = 0u;
    uint label = 0u;
    uint room_state = 0u;  // the room seen: 1 | lit << 1 | variant << 2
    uint window_key = 0u;  // the window a room is seen through (window_id), 0: none
    vec3 color;
    vec3 surface = v_local;  // where a ray through the glass enters the building
    bool cheap = false;      // the cheapest level of detail (city/lod.glsl): no grammar, relief nor rooms traced
    bool traced = false;     // a grammar window's relief was traced (relief/building.glsl)
    bool recessed = false;   // any relief was traced: surface lies on the ray behind the wall point
    if (v_ids.y == SURFACE_ROOF) {
        face = FACE_ROOF;
#if defined POLYGONISED_WINDOWS
        discard;
#endif
        color = roof_color(b, v_ids.z, v_local, n, n_world, rot * d, shadow_factor(v_world));
    } else {
        // each facade technique fills one FacadeResult; facade_light lights them all
        FacadeResult f;
        vec4 opening = vec4(v_facade, v_facade);  // the glass's rectangle: a point in the pixel's bay, or the grammar's window
        vec2 door_uv;
        int door;
        bool at_door = door_at(b, v_local, n, door_uv, door);  // a mapped or guessed door, in front of any facade
        // plain walls (too narrow for a grammar) and dormer fronts (one window bay) keep to their own
        // NEAR_GRAMMAR / NEAR_OTHER (common/building_vertex.glsl): which kind of building this program
        // draws is known here, so the other kind's facade code is compiled out
#if defined NEAR_GRAMMAR
        bool grammar = !at_door && v_ids.y == SURFACE_WALL;
        bool relief = false;
#elif defined NEAR_OTHER
        bool grammar = false;
        bool relief = v_ids.y == SURFACE_WALL && has_relief_facade(b);
#else
        bool grammar = !at_door && v_ids.y == SURFACE_WALL && has_grammar_facade(b);
        bool relief = v_ids.y == SURFACE_WALL && has_relief_facade(b);
#endif
#if defined BUILDING_LOD
        // far away: the style's mean colour (the deferred pass decided for grammar pixels)
#if defined GRAMMAR_DEFERRED && !defined ID_PASS
        cheap = grammar ? grammar_deferred_skipped() : lod_cheap(s);
#else
        cheap = lod_cheap_facade(s, grammar, v_ids.x);
#endif
#endif
        if (at_door) f = FacadeResult(door_albedo(b, door, door_uv), n, vec2(0.0), 0.0, v_local, GRAMMAR_DOOR_LABEL);
        else if (v_ids.y == SURFACE_PLAIN_WALL)  // a face too narrow for its grammar (cityshade/render/_facades.py):
            f = FacadeResult(u_bay_mean.rgb * building_tint(b), n, vec2(0.0), 0.0, v_local, 0u);  // the wall's colour
#if defined BUILDING_LOD
        else if (cheap) f = lod_facade(b, v_ids.x, n, v_local, (v_facade - vec2(0.0, v_face.y)) / v_spacing, grammar, relief);
        else if (relief && lod_relief_flat(s))  // parallax under a pixel: traced straight into the wall
            f = relief_building(b, n, v_local, v_facade - vec2(0.0, v_face.y), v_spacing, -n);
#endif
        else if (grammar) {
            bool hole;
            f = grammar_building_facade(b, n, v_ids.z, v_local, v_facade, v_spacing.y, v_face, d, opening, hole);
            traced = grammar_relief(b, v_ids.x, n, v_ids.z, v_local, v_facade, v_spacing.y, v_face, d, s, hole, f, opening);
            recessed = traced;
        }
        else if (relief) {
            f = relief_building(b, n, v_local, v_facade - vec2(0.0, v_face.y), v_spacing, d);
            recessed = true;
        }
        else if (v_ids.y == SURFACE_WALL  // dormer fronts keep the flat bay
                 && window_bay_relief(b, n, v_local, v_facade - vec2(0.0, v_face.y), v_spacing, d, s, f))
            recessed = true;
        else f = window_bay(b, n, v_local, (v_facade - vec2(0.0, v_face.y)) / v_spacing);
        float glass = f.glass;
        label = f.label;
        surface = f.point;  // recessed relief glass: the room shows from the hit point
#if !defined ID_PASS
        color = facade_light(f, rot, d, shadow_factor(v_world));  // where it is glass, the room shows (below)
#if defined GRAMMAR_DEFERRED
        if (grammar && !cheap && !traced) color = grammar_deferred_color();  // lit by the deferred pass
#endif
#endif
#if defined POLYGONISED_EXTERIOR
        if (glass >= 0.5) discard;  // the real rooms behind show through the hole
        glass = 0.0;                // and the rest is frame: no reflective-window mix at its edge
#elif defined POLYGONISED_WINDOWS
        if (glass < 0.5) discard;
        out_color = vec4(environment(reflect(rot * d, n_world)), fresnel(max(-dot(n, d), 0.0), 0.06));
        return;
#endif
        if (glass > 0.0) {
            float cos_view = max(-dot(n, d), 0.0);
            vec3 window;
            vec3 inside = vec3(0.0);
            float reflectance;
            if ((b.ids.z & FLAG_NO_INTERIOR) != 0) {
                // an outbuilding: no room behind its panes (the id AOV keeps the exterior face)
                inside = NO_ROOM_PANE;
                reflectance = fresnel(cos_view, NO_ROOM_PANE_F0);
            } else {
#if defined INTERIOR_MAPPING
            float interior_weight = cheap ? 0.0 : 1.0;
#if defined INTERIOR_LOD
            interior_weight *= 1.0 - smoothstep(u_lod_range.x, u_lod_range.y, s);
#endif
            // the room's frame: the face's (u, v, metres into the building)
            WallFace wall = wall_face(v_spacing, v_face, v_ids);
            mat3 to_face = face_frame(n);
            vec3 entry = vec3(v_facade, 0.0) + to_face * (surface - v_local);
            if (interior_weight > 0.0) {
                InteriorHit hit = interior_trace(entry, to_face * d, opening, wall, b, to_face * dFdx(v_local),
                                                 to_face * dFdy(v_local), s);
                face = hit.face;
                room = hit.room;
                room_state = 1u | (hit.lit ? 2u : 0u) | (uint(hit.variant) << 2u);
                window_key = window_id(opening, wall);
                inside = hit.color;
            }
#if defined INTERIOR_LOD || defined BUILDING_LOD
            if (interior_weight < 1.0) {
                // far away: each window glows with its room's mean colour (no ray cast)
                Room r = find_room(opening, wall, b);
                inside = mix(room_mean_color(r) * room_radiance(r), inside, interior_weight);
                if (interior_weight <= 0.0) room = r.id;
            }
#endif
            reflectance = fresnel(cos_view, 0.06);
#else
            inside = u_window_tint;
            reflectance = fresnel(cos_view, 0.5);
#endif
            }
#if !defined ID_PASS
            window = mix(inside, environment(reflect(rot * d, n_world)), reflectance);
            color = mix(color, window, glass);
#endif
        }
    }
#if defined RELIEF_DEPTH
    // a hit on the wall itself keeps the rasterised depth exactly (no rounding to break ties at edges)
    bool moved = recessed && any(notEqual(surface, v_local));
    gl_FragDepth = moved ? relief_depth(v_world + rot * (surface - v_local)) : gl_FragCoord.z;
#endif
#if defined ID_PASS && defined ID_ROOM_STATE
    out_ids = uvec4(uint(face), room, uint(v_ids.x + 1), room_state);
#elif defined ID_PASS && defined ID_WINDOW
    out_ids = uvec4(uint(face), room, uint(v_ids.x + 1), window_key);
#elif defined ID_PASS
    out_ids = uvec4(uint(face), room, uint(v_ids.x + 1), label);
#else
    out_color = vec4(color + STREET_LIT_ALBEDO * street_light(v_world, n_world), 1.0);
#endif
}
#endif
#endif
