// One facade, evaluated per pixel on a full-screen triangle (`cityshade grammar render`, tests).
// The view: a camera at distance max(w, h) in front of the facade's centre, as
// cityshade.grammar._reference.facade_view computes it.
// GRAMMAR_HOLES: the ids are the hole the pixel shows (GrammarResult.hole + 1) and what that hole
// shows u_hole_shift metres further along (grammar_through: terminal + 1, label, glass), as the
// city's recessed holes evaluate it from the hole's bottom (relief/building.glsl).
#include "grammar/eval.glsl"

#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
uniform vec2 u_facade_size;     // metres
uniform vec2 u_viewport_size;   // pixels
uniform vec2 u_facade_seed;     // the building's seed vector (on the 1/8 m noise grid)
uniform int u_facade_index;     // which facade of the building: each has its own seed
uniform float u_facade_level;   // facade.level: the storey the facade starts at
uniform int u_start_rule;
uniform vec4 u_facade_building; // building.levels, .style, .use, .height
uniform vec3 u_light_dir;       // towards the light; tangent space with z out of the wall (as normals)
uniform vec2 u_hole_shift;      // GRAMMAR_HOLES: metres from the pixel to where its hole is seen through

layout(location = 0) out vec4 out_color;
layout(location = 1) out uvec4 out_ids;  // terminal + 1, label, tile + 1, glass

void main() {
    vec2 uv = gl_FragCoord.xy / u_viewport_size * u_facade_size;
    vec3 ray = normalize(vec3(uv - u_facade_size * 0.5, max(u_facade_size.x, u_facade_size.y)));
    grammar_building = u_facade_building;
    grammar_level = u_facade_level;
    grammar_building_seed = u_facade_seed;
    ivec2 cells = ivec2(round(u_facade_seed * GRAMMAR_NOISE_DENSITY));
    vec2 seed = u_facade_index == 0 ? u_facade_seed
                                    : vec2(grammar_facade_cells(cells, u_facade_index)) / GRAMMAR_NOISE_DENSITY;
    GrammarResult g = grammar_evaluate(u_start_rule, uv, u_facade_size, seed, ray, dFdx(uv), dFdy(uv));
    float diffuse = max(dot(g.normal, u_light_dir), 0.0);
    vec3 half_vector = normalize(u_light_dir + vec3(-ray.xy, ray.z));  // the ray's z points into the wall
    float specular = g.specular.x * pow(max(dot(g.normal, half_vector), 0.0), 1.0 + 128.0 * g.specular.y);
    out_color = vec4(g.color * (0.35 + 0.65 * diffuse) + specular, 1.0);
#if defined GRAMMAR_HOLES
    grammar_through = g.hole;
    GrammarResult behind = grammar_evaluate(u_start_rule, uv + u_hole_shift, u_facade_size, seed, ray, dFdx(uv), dFdy(uv));
    out_ids = uvec4(uint(g.hole + 1), uint(behind.terminal + 1), uint(behind.label), behind.glass ? 1u : 0u);
#else
    out_ids = uvec4(uint(g.terminal + 1), uint(g.label), uint(g.tile + 1), g.glass ? 1u : 0u);
#endif
}
#endif
