// A building's grammar facade baked into a texture atlas: one canvas per draw, its viewport the
// canvas' rectangle in the atlas. Each texel is evaluated head-on at its centre, unlit, as the
// renderer evaluates the wall point there (shaders/grammar/building.glsl: mesh u is mirrored).
// The numpy twin is cityshade.export._bake.bake_reference.
#include "grammar/eval.glsl"

#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
uniform vec2 canvas_origin;  // pixels: the canvas' lower-left corner in the atlas
uniform vec2 facade_origin;  // mesh facade coordinates (u along the wall, v up from the face's base) at that corner, metres
uniform float texel;         // metres per texel
uniform vec2 facade_size;    // the grammar's scope: the face's width and height
uniform vec2 facade_seed;
uniform vec2 building_seed;  // entry 0 of the random-seed stack: choices made once per building
uniform vec4 building_values;  // building.levels (the face's storeys), .style, .use, .height for conditions
uniform int start_rule;
uniform float facade_level;  // facade.level: the storey the building's walls start at

layout(location = 0) out vec4 out_color;    // sRGB colour, specular intensity
layout(location = 1) out vec4 out_normal;   // tangent-space normal (x right, y up, z out), shininess / 128
layout(location = 2) out uvec4 out_ids;     // terminal + 1, label, glass, 0

void main() {
    vec2 mesh_uv = facade_origin + (gl_FragCoord.xy - canvas_origin) * texel;
    vec2 uv = vec2(facade_size.x - mesh_uv.x, mesh_uv.y);
    grammar_building = building_values;
    grammar_building_seed = building_seed;
    grammar_level = facade_level;
    GrammarResult g = grammar_evaluate(start_rule, uv, facade_size, facade_seed, vec3(0.0, 0.0, 1.0),
                                       vec2(-texel, 0.0), vec2(0.0, texel));
    out_color = vec4(g.color, g.specular.x);
    out_normal = vec4(g.normal, g.specular.y);
    out_ids = uvec4(uint(g.terminal + 1), uint(g.label), g.glass ? 1u : 0u, 0u);
}
#endif
