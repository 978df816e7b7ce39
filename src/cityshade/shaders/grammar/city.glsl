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
in vec3 v_facade;
flat in ivec2 v_ids;

const vec3 ROOF_COLOR = vec3(0.32, 0.31, 0.30);

#if defined GBUFFER
layout(location = 0) out vec4 out_scope;   // uv, scope size (metres)
layout(location = 1) out vec4 out_rule;    // seed vector, start rule, building index + 1 (0: a roof)
layout(location = 2) out vec4 out_normal;  // world normal
#else
layout(location = 0) out vec4 out_color;
#endif

void main() {
    Building b = buildings[v_ids.x];
    vec3 n = building_rotation(b) * normalize(v_normal);  // world; buildings turn about +y only
#if defined GBUFFER
    vec2 uv = vec2(0.0), size = vec2(1.0), seed = vec2(0.0);
    float facade = 0.0;
    if (v_ids.y != SURFACE_ROOF && has_grammar_facade(b)) {
        grammar_scope(b, normalize(v_normal), v_facade.xy, uv, size, seed);
        facade = 1.0;
    }
    out_scope = vec4(uv, size);
    out_rule = vec4(seed, float(b.facade.y), facade * float(v_ids.x + 1));  // exact in 32-bit floats
    out_normal = vec4(n, 0.0);
#else
    if (v_ids.y == SURFACE_ROOF) {
        out_color = vec4(lit_surface(ROOF_COLOR, n, 1.0), 1.0);
        return;
    }
    mat3 rot = building_rotation(b);
    vec3 d = normalize(v_local - transpose(rot) * (u_camera - b.origin_yaw.xyz));  // object space
    GrammarResult g = grammar_facade(b, normalize(v_normal), v_facade.xy, d, dFdx(v_facade.xy), dFdy(v_facade.xy));
    out_color = vec4(grammar_lit(g, normalize(v_normal), rot, d, 1.0), 1.0);
#endif
}
#endif
#endif
