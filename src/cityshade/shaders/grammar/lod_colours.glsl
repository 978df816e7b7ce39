// The cheap level's colours (cityshade/render/_lod_colours.py): every grammar building's sample
// face evaluated at the same jittered points as the numpy reference (render/_building_lod.py),
// one tile of LOD_SAMPLES_X x LOD_SAMPLES_Y pixels per building, at the tiles' coarsest mipmap
// (what the full level samples where the cheap level takes over). Each pixel writes
// (linear colour, 1) on the wall and 0 on glass; the tile's mean is (mean colour x wall share, wall share).
#include "grammar/eval.glsl"
#include "common/srgb.glsl"

#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
struct SampleFace {
    vec4 size_start_face;  // width, height (metres), start rule, face index
    vec4 building;         // building.levels, .style, .use, .height
    vec4 seed;             // xy: the building's seed vector, z: facade.level
};
layout(std430, binding = BINDING_SAMPLE_FACES) readonly buffer SampleFaces { SampleFace faces[]; };
uniform sampler2D u_unit_samples;  // RG32F, LOD_SAMPLES_X x LOD_SAMPLES_Y: the points over the unit square
uniform int u_first;               // the face of the tile at the bottom left
uniform int u_tiles_across;
uniform int u_face_count;

out vec4 out_colour;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 tile = pixel / ivec2(LOD_SAMPLES_X, LOD_SAMPLES_Y);
    int index = u_first + tile.y * u_tiles_across + tile.x;
    if (index >= u_face_count) {
        out_colour = vec4(0.0);
        return;
    }
    SampleFace f = faces[index];
    vec2 size = f.size_start_face.xy;
    vec2 uv = texelFetch(u_unit_samples, pixel % ivec2(LOD_SAMPLES_X, LOD_SAMPLES_Y), 0).xy * size;
    grammar_building = f.building;
    grammar_level = f.seed.z;
    grammar_building_seed = f.seed.xy;
    int face = int(f.size_start_face.w);
    ivec2 cells = ivec2(round(f.seed.xy * GRAMMAR_NOISE_DENSITY));
    vec2 seed = face == 0 ? f.seed.xy : vec2(grammar_facade_cells(cells, face)) / GRAMMAR_NOISE_DENSITY;
    vec2 coarsest = vec2(size.x + size.y) * 1e3;  // derivatives past any tile: its last mipmap, one mean texel
    GrammarResult g = grammar_evaluate(int(f.size_start_face.z), uv, size, seed, vec3(0.0, 0.0, 1.0), coarsest,
                                       coarsest);
    // a hole cut into the wall (a room of the grammar's own behind it) is a window as glass is
    out_colour = g.glass || g.hole >= 0 ? vec4(0.0) : vec4(srgb_to_linear(g.color), 1.0);
}
#endif
