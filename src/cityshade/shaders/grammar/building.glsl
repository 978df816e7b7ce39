// Grammar facades on the city's buildings (included by city/building.glsl and the deferred pass).
// The record's facade field: x = 1 for a grammar facade, y = start rule, zw = seed in 1/8 m.
#ifndef GRAMMAR_BUILDING_GLSL
#define GRAMMAR_BUILDING_GLSL

#include "common/buildings.glsl"
#include "common/facade.glsl"
#include "common/hash.glsl"
#include "common/srgb.glsl"
#include "grammar/eval.glsl"

bool has_grammar_facade(Building b) {
    return b.facade.x == FACADE_GRAMMAR;
}

// The facade frame seen from outside: right, up (+y) and out (n), object space.
vec3 grammar_right(vec3 n) {
    return normalize(cross(vec3(0.0, 1.0, 0.0), n));
}

// Scope and texture coordinates of a wall point: the grammar runs in the true size of the face it
// is on (facade: u, v; face: width, base, top, room depth; cityshade/scene/_wall_faces.py).
// Mesh u runs right to left seen from outside, so it is mirrored. Each face has its own seed (the
// building's, hashed with the face's index: its first room column, 0 for the first face and for a
// round mass), so the faces of a building make independent random choices, each the same in every
// frame, and a curved run of many walls keeps one stream.
void grammar_scope(Building b, int face_index, vec2 facade, vec4 face, out vec2 uv, out vec2 size, out vec2 seed) {
    size = vec2(face.x, face.z - face.y);
    uv = vec2(face.x - facade.x, facade.y - face.y);
    seed = vec2(grammar_facade_cells(b.facade.zw, face_index)) / GRAMMAR_NOISE_DENSITY;
}

// The storeys of a face: its height over its storey height, rounded.
float grammar_levels(vec4 face, float storey) { return floor((face.z - face.y) / storey + 0.5); }

// facade.level, the storey the face's bottom sits at: its mass's first level, plus for a dome's ring
// the storeys below it up the arc (cityshade/scene/_face_levels.py face_levels).
float grammar_face_level(Building b, vec4 face, float storey) {
    return float(building_first_level(b)) + (b.ids.w == SHAPE_DOME ? floor(face.y / storey + 0.5) : 0.0);
}

// building.levels (the face's storeys), .style, .use and .height and facade.level for conditions
// (the use code: building_use, common/buildings.glsl), and the building's own seed for choices made
// once per building.
void grammar_set_building(Building b, float levels, float level) {
    grammar_building = vec4(levels, float(b.ids.y), float(building_use(b)), b.extent.y);
    grammar_level = level;
    grammar_building_seed = vec2(b.facade.zw) / GRAMMAR_NOISE_DENSITY;
}

// The rectangle (u0, v0, u1, v1, facade coordinates) of the grammar scope that decided a pixel
// (GrammarResult.scope, in grammar uv: u mirrored, v from the face's base): the window that a
// glass pixel belongs to, for the room behind it.
vec4 grammar_window(vec4 scope, vec4 face) {
    return vec4(face.x - scope.x - scope.z, face.y + scope.y, face.x - scope.x, face.y + scope.y + scope.w);
}

// Evaluates a grammar at facade point uv; d is the unit view ray and n the wall normal (in one
// frame whose up is +y: object or world space), duv_dx/duv_dy the screen derivatives of uv.
GrammarResult grammar_facade_at(int start, vec2 uv, vec2 size, vec2 seed, vec3 n, vec3 d, vec2 duv_dx, vec2 duv_dy) {
    vec3 right = grammar_right(n);
    vec3 ray = vec3(dot(d, right), d.y, -dot(d, n));  // tangent space, z into the wall
    return grammar_evaluate(start, uv, size, seed, ray, duv_dx, duv_dy);
}

// The building's grammar at a wall point (object space; facade uv, storey height, face and the
// derivatives of the facade uv from the mesh).
GrammarResult grammar_facade(Building b, vec3 n, int face_index, vec2 facade, float storey, vec4 face, vec3 d, vec2 duv_dx,
                             vec2 duv_dy) {
    vec2 uv, size, seed;
    grammar_scope(b, face_index, facade, face, uv, size, seed);
    grammar_set_building(b, grammar_levels(face, storey), grammar_face_level(b, face, storey));
    return grammar_facade_at(b.facade.y, uv, size, seed, n, d, vec2(-duv_dx.x, duv_dx.y), vec2(-duv_dy.x, duv_dy.y));
}

// The grammar's tangent-space normal in object space.
vec3 grammar_normal(vec3 tangent_normal, vec3 n) {
    return normalize(grammar_right(n) * tangent_normal.x + vec3(0.0, tangent_normal.y, 0.0) + n * tangent_normal.z);
}

// The grammar's material at a wall point (n: its normal, point: the point) as a facade result:
// colour from sRGB tiles, its normal in the wall's space, Phong specular, glass labelled as room.
FacadeResult grammar_facade_result(GrammarResult g, vec3 n, vec3 point) {
    return FacadeResult(srgb_to_linear(g.color), grammar_normal(g.normal, n), g.specular, g.glass ? 1.0 : 0.0,
                        point, uint(g.glass ? GRAMMAR_ROOM_LABEL : g.label));
}

// The grammar facade at a building fragment (object space), the window the pixel belongs to
// (grammar_window: its rectangle picks the room behind it) and whether it shows what a hole lets
// through (GrammarResult.hole: relief/building.glsl recesses the hole). With GRAMMAR_DEFERRED it was evaluated
// and lit (with facade_light) by the deferred pass's full-screen evaluation of this pixel
// (cityshade/grammar/_frame_pass.py), which keeps the window's centre: only glass, label and window
// come back here, and grammar_deferred_color gives the lit colour (the relief's window opening comes
// back too: relief/building.glsl grammar_deferred_opening). The id pass always evaluates, so
// ids stay exact.

// The deferred pass's first id channel: glass, a hole seen (where the page cache did not answer),
// or the mark on a pixel it left to the cheapest level of detail (city/lod.glsl), so both passes
// agree on the pixel's level; where the page cache did not answer and relief is on, also the
// window opening it found for the relief (relief/openings.glsl: found, a hole's, its index + 1
// from bit GRAMMAR_DEFERRED_OPENING_SHIFT, the face's key from bit GRAMMAR_DEFERRED_FACE_SHIFT).
// The second: the flat grammar's sRGB colour in 8 bits per channel (packUnorm4x8) and its label
// in the top byte.
const uint GRAMMAR_DEFERRED_GLASS = 1u;
const uint GRAMMAR_DEFERRED_SKIPPED = 2u;
const uint GRAMMAR_DEFERRED_HOLE = 4u;
const uint GRAMMAR_DEFERRED_OPENING = 8u;
const uint GRAMMAR_DEFERRED_HOLE_OPENING = 16u;
const uint GRAMMAR_DEFERRED_OPENING_SHIFT = 8u;
const uint GRAMMAR_DEFERRED_FACE_SHIFT = 16u;
const uint GRAMMAR_DEFERRED_LABEL_SHIFT = 24u;

// 16 bits naming the face a pixel is on: its building's index and its seed cells (grammar_scope:
// one per face), so the buildings pass can tell the deferred pass's pixel from another surface's
// fragment in it (an edge's under multisampling, a hidden one) and evaluate such a fragment itself.
uint grammar_face_key(int building, ivec2 cells) {
    return hash3(ivec3(building, cells), 0x46u) >> 16u;
}

#if defined GRAMMAR_DEFERRED && !defined ID_PASS
uniform sampler2D u_grammar_deferred_color;
uniform usampler2D u_grammar_deferred_ids;

vec3 grammar_deferred_color() { return texelFetch(u_grammar_deferred_color, ivec2(gl_FragCoord.xy), 0).rgb; }

// whether the deferred pass left this pixel to the cheapest level of detail (below)
bool grammar_deferred_skipped() {
    return texelFetch(u_grammar_deferred_ids, ivec2(gl_FragCoord.xy), 0).x == GRAMMAR_DEFERRED_SKIPPED;
}
#endif

FacadeResult grammar_building_facade(Building b, vec3 n, int face_index, vec3 wall, vec2 facade, float storey,
                                     vec4 face, vec3 d, out vec4 window, out bool hole) {
#if defined GRAMMAR_DEFERRED && !defined ID_PASS
    uvec4 ids = texelFetch(u_grammar_deferred_ids, ivec2(gl_FragCoord.xy), 0);
    bool glass = (ids.x & GRAMMAR_DEFERRED_GLASS) != 0u;
    hole = (ids.x & GRAMMAR_DEFERRED_HOLE) != 0u;
    window = grammar_window(vec4(uintBitsToFloat(ids.zw), 0.0, 0.0), face);  // the window's centre
    uint label = ids.y >> GRAMMAR_DEFERRED_LABEL_SHIFT;
    return FacadeResult(vec3(0.0), n, vec2(0.0), glass ? 1.0 : 0.0, wall, glass ? uint(GRAMMAR_ROOM_LABEL) : label);
#else
    GrammarResult g = grammar_facade(b, n, face_index, facade, storey, face, d, dFdx(facade), dFdy(facade));
    window = grammar_window(g.scope, face);
    hole = g.hole >= 0;
    return grammar_facade_result(g, n, wall);
#endif
}

#endif
