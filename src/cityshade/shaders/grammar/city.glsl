// Grammar facades over a whole city, the two paths of the facade benchmark (§4, §5):
//   DEPTH_ONLY  z prepass
//   FORWARD     after the prepass: evaluate the grammar where the depth test passes (once per pixel)
//   GBUFFER     the paper's cheap first pass: facade uv, scope size, seed, start rule, normal
// The deferred path then runs grammar/deferred.glsl over the screen. Roofs get a flat material.
#include "common/buildings.glsl"
#include "common/building_vertex.glsl"

#if defined FRAGMENT_SHADER
#if defined DEPTH_ONLY
void main() {}
#else
#include "grammar/building.glsl"

in vec3 v_local;
in vec3 v_normal;
in vec2 v_facade;
flat in vec2 v_spacing;
flat in vec4 v_face;
flat in ivec4 v_ids;

const vec3 ROOF_COLOR = vec3(0.32, 0.31, 0.30);

#if defined GBUFFER
layout(location = 0) out vec4 out_scope;   // uv, scope size (metres)
layout(location = 1) out vec4 out_rule;    // seed vector, start rule, building index + 1 (0: a roof)
layout(location = 2) out vec4 out_normal;  // world normal, the face's storeys (building.levels)
#else
layout(location = 0) out vec4 out_color;
#endif

void main() {
    Building b = buildings[v_ids.x];
    vec3 n = building_rotation(b) * normalize(v_normal);  // world; buildings turn about +y only
#if defined GBUFFER
    vec2 uv = vec2(0.0), size = vec2(1.0), seed = vec2(0.0);
    float facade = 0.0, levels = 0.0;
    if (v_ids.y == SURFACE_WALL && has_grammar_facade(b)) {  // not roofs, nor plain walls
        grammar_scope(b, v_ids.z, v_facade, v_face, uv, size, seed);
        levels = grammar_levels(v_face, v_spacing.y);
        facade = 1.0;
    }
    out_scope = vec4(uv, size);
    out_rule = vec4(seed, float(b.facade.y), facade * float(v_ids.x + 1));  // exact in 32-bit floats
    out_normal = vec4(n, levels);
#else
    if (v_ids.y == SURFACE_ROOF) {
        out_color = vec4(lit_surface(ROOF_COLOR, n, 1.0), 1.0);
        return;
    }
    mat3 rot = building_rotation(b);
    vec3 d = normalize(v_local - transpose(rot) * (u_camera - b.origin_yaw.xyz));  // object space
    vec3 wall_normal = normalize(v_normal);  // object space
    GrammarResult g = grammar_facade(b, wall_normal, v_ids.z, v_facade, v_spacing.y, v_face, d, dFdx(v_facade), dFdy(v_facade));
    out_color = vec4(facade_light(grammar_facade_result(g, wall_normal, v_local), rot, d, 1.0), 1.0);
#endif
}
#endif
#endif
