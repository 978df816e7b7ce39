// Grammar facades on the city's buildings (included by city/building.glsl and the deferred pass).
// The record's facade field: x = 1 for a grammar facade, y = start rule, zw = seed in 1/8 m.
#ifndef GRAMMAR_BUILDING_GLSL
#define GRAMMAR_BUILDING_GLSL

#include "common/buildings.glsl"
#include "common/lighting.glsl"
#include "common/srgb.glsl"
#include "grammar/eval.glsl"

bool has_grammar_facade(Building b) {
    return b.facade.x == FACADE_GRAMMAR;
}

// The facade frame seen from outside: right, up (+y) and out (n), object space.
vec3 grammar_right(vec3 n) {
    return normalize(cross(vec3(0.0, 1.0, 0.0), n));
}

// The facade index of a wall (cityshade.grammar._random.facade_index): the direction its object-space
// normal n faces, in GRAMMAR_FACADE_SECTORS steps (a box's sides are 0, 4, 8, 12); a round mass is one facade.
int grammar_facade_index(Building b, vec3 n) {
    if (b.ids.w == SHAPE_CYLINDER) return 0;
    const float sectors = float(GRAMMAR_FACADE_SECTORS);
    int k = int(floor(atan(n.z, n.x) * (sectors / 6.28318531) + 0.5));
    return ((k % GRAMMAR_FACADE_SECTORS) + GRAMMAR_FACADE_SECTORS) % GRAMMAR_FACADE_SECTORS;
}

// Scope and texture coordinates of a wall point. Mesh u runs right to left seen from outside,
// so it is mirrored. Each facade has its own seed (the building's, hashed with the facade index),
// so the sides of a building make independent random choices, each the same in every frame.
void grammar_scope(Building b, vec3 n, vec2 facade_uv, out vec2 uv, out vec2 size, out vec2 seed) {
    bool round_mass = b.ids.w == SHAPE_CYLINDER;
    float width = round_mass ? 3.14159265 * b.extent.x : (abs(n.z) > abs(n.x) ? b.extent.x : b.extent.z);
    size = vec2(width, b.extent.y);
    uv = vec2(width - facade_uv.x, facade_uv.y);
    seed = vec2(grammar_facade_cells(b.facade.zw, grammar_facade_index(b, n))) / GRAMMAR_NOISE_DENSITY;
}

// building.levels (storeys: the height over the room height, rounded), .style, .use and .height
// for conditions (the use is kept in the flags word from bit FLAG_USE_SHIFT), and the building's
// own seed for choices made once per building.
void grammar_set_building(Building b) {
    grammar_building = vec4(floor(b.extent.y / b.room.y + 0.5), float(b.ids.y), float((b.ids.z >> FLAG_USE_SHIFT) & 15),
                            b.extent.y);
    grammar_building_seed = vec2(b.facade.zw) / GRAMMAR_NOISE_DENSITY;
}

// Evaluates a grammar at facade point uv; d is the unit view ray and n the wall normal (in one
// frame whose up is +y: object or world space), duv_dx/duv_dy the screen derivatives of uv.
GrammarResult grammar_facade_at(int start, vec2 uv, vec2 size, vec2 seed, vec3 n, vec3 d, vec2 duv_dx, vec2 duv_dy) {
    vec3 right = grammar_right(n);
    vec3 ray = vec3(dot(d, right), d.y, -dot(d, n));  // tangent space, z into the wall
    return grammar_evaluate(start, uv, size, seed, ray, duv_dx, duv_dy);
}

// The building's grammar at a wall point (object space; facade_uv and its derivatives from the mesh).
GrammarResult grammar_facade(Building b, vec3 n, vec2 facade_uv, vec3 d, vec2 duv_dx, vec2 duv_dy) {
    vec2 uv, size, seed;
    grammar_scope(b, n, facade_uv, uv, size, seed);
    grammar_set_building(b);
    return grammar_facade_at(b.facade.y, uv, size, seed, n, d, vec2(-duv_dx.x, duv_dx.y), vec2(-duv_dy.x, duv_dy.y));
}

// The grammar's tangent-space normal in object space.
vec3 grammar_normal(vec3 tangent_normal, vec3 n) {
    return normalize(grammar_right(n) * tangent_normal.x + vec3(0.0, tangent_normal.y, 0.0) + n * tangent_normal.z);
}

// Sun and sky on the grammar's material: diffuse from its colour (tiles are sRGB), Phong specular.
// `shadow`: 1 where the sun reaches the facade (shadow/csm.glsl), 0 in shadow.
vec3 grammar_lit(GrammarResult g, vec3 n, mat3 rot, vec3 d, float shadow) {
    vec3 n_world = rot * grammar_normal(g.normal, n);
    vec3 albedo = srgb_to_linear(g.color);
    vec3 half_vector = normalize(u_sun_dir - rot * d);
    float shininess = 1.0 + 128.0 * g.specular.y;
    float highlight = g.specular.x * pow(max(dot(n_world, half_vector), 0.0), shininess) * max(dot(n_world, u_sun_dir), 0.0);
    return lit_surface(albedo, n_world, shadow) + shadow * highlight * u_sun_color;
}

// The grammar facade at a building fragment: lit colour, glass (rooms show through it) and label.
// Evaluated here (forward), or, with GRAMMAR_DEFERRED, fetched from the deferred pass's
// full-screen evaluation of this pixel (cityshade/grammar/_frame_pass.py). The id pass always
// evaluates, so ids stay exact.
#if defined GRAMMAR_DEFERRED && !defined ID_PASS
uniform sampler2D u_grammar_deferred_color;
uniform usampler2D u_grammar_deferred_ids;
#endif

vec3 grammar_building_color(Building b, vec3 n, vec2 facade_uv, vec3 d, mat3 rot, float shadow, out float glass,
                            out uint label) {
#if defined GRAMMAR_DEFERRED && !defined ID_PASS
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    uvec4 ids = texelFetch(u_grammar_deferred_ids, pixel, 0);
    glass = float(ids.x);
    label = ids.x == 1u ? uint(GRAMMAR_ROOM_LABEL) : ids.y;
    return texelFetch(u_grammar_deferred_color, pixel, 0).rgb;
#else
    GrammarResult g = grammar_facade(b, n, facade_uv, d, dFdx(facade_uv), dFdy(facade_uv));
    glass = g.glass ? 1.0 : 0.0;
    label = uint(g.glass ? GRAMMAR_ROOM_LABEL : g.label);
    return grammar_lit(g, n, rot, d, shadow);
#endif
}

#endif
