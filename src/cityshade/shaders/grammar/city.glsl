// The deferred grammar path's cheap first pass (Krecklau §4) in the city's frame: facade uv, scope
// size, seed, the face's level (facade.level) and normal per pixel, for grammar/deferred.glsl to
// evaluate over the screen (it reads the start rule from the building's record).
#include "common/buildings.glsl"
#include "common/building_vertex.glsl"

#if defined FRAGMENT_SHADER
#include "grammar/building.glsl"
#if defined GRAMMAR_CACHE
#include "grammar/cache.glsl"
#endif

in vec3 v_normal;
in vec2 v_facade;
flat in vec2 v_spacing;
flat in vec4 v_face;
flat in ivec4 v_ids;

layout(location = 0) out vec4 out_scope;   // uv, scope size (metres)
layout(location = 1) out vec4 out_rule;    // seed vector, facade.level, building index + 1 (0: a roof)
layout(location = 2) out vec4 out_normal;  // world normal, the face's storeys (building.levels)
#if defined GRAMMAR_CACHE
layout(location = 3) out uvec4 out_page;   // the cache page the pixel needs (grammar/cache.glsl), 0: none
#endif

void main() {
    Building b = buildings[v_ids.x];
    vec3 n = building_rotation(b) * normalize(v_normal);  // world; buildings turn about +y only
    vec2 uv = vec2(0.0), size = vec2(1.0), seed = vec2(0.0);
    float facade = 0.0, levels = 0.0, level = 0.0;
    vec2 facade_dx = dFdx(v_facade), facade_dy = dFdy(v_facade);  // before branching
    if (v_ids.y == SURFACE_WALL && has_grammar_facade(b)) {  // not roofs, nor plain walls
        grammar_scope(b, v_ids.z, v_facade, v_face, uv, size, seed);
        levels = grammar_levels(v_face, v_spacing.y);
        level = grammar_face_level(b, v_face, v_spacing.y);
        facade = 1.0;
    }
    out_scope = vec4(uv, size);
    out_rule = vec4(seed, level, facade * float(v_ids.x + 1));  // exact in 32-bit floats
    out_normal = vec4(n, levels);
#if defined GRAMMAR_CACHE
    // pages hold faces at their building's first level (a dome's rings above its first are evaluated per pixel)
    bool cacheable = facade > 0.0 && level == float(building_first_level(b));
    out_page = cacheable ? grammar_cache_page(v_ids.x, v_ids.z, levels, uv, size, facade_dx, facade_dy) : uvec4(0u);
#endif
}
#endif
