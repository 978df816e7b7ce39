// The grammar cache update (cityshade/grammar/_cache.py): one quad per page into its slot of the
// atlas, the grammar evaluated once per texel at the texel's centre, its tiles filtered at the
// page's filter level.
// Texels past the face's edges repeat its edge; the border texels past the page's edges hold the
// grammar there, so a bilinear read at a page border sees the neighbouring page's content.
#include "grammar/cache.glsl"

struct GrammarPageRecord {
    uvec4 key;   // key x, key y, face width and height (float bits)
    uvec4 slot;  // x: the slot
};
layout(std430, binding = BINDING_GRAMMAR_PAGE_RECORDS) readonly buffer GrammarPageRecords { GrammarPageRecord grammar_page_records[]; };

#if defined VERTEX_SHADER
flat out uvec4 v_key;
flat out vec2 v_origin;
void main() {
    GrammarPageRecord r = grammar_page_records[gl_InstanceID];
    const vec2 corners[6] = vec2[6](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(0, 1), vec2(1, 0), vec2(1, 1));
    v_origin = grammar_cache_origin(int(r.slot.x));
    vec2 texel = v_origin + corners[gl_VertexID] * float(GRAMMAR_CACHE_PAGE);
    gl_Position = vec4(texel / u_cache_atlas_size * 2.0 - 1.0, 0.0, 1.0);
    v_key = r.key;
}
#endif

#if defined FRAGMENT_SHADER
#include "grammar/building.glsl"

flat in uvec4 v_key;
flat in vec2 v_origin;

layout(location = 0) out vec4 out_color;   // sRGB colour, specular intensity
layout(location = 1) out vec4 out_normal;  // tangent-space normal, shininess
layout(location = 2) out uvec4 out_ids;    // glass | view-dependent << 1 | label << 2, window centre (float bits),
                                           // the winning Mat (terminal + 1 | tile + 1 << 16)

void main() {
    int level = grammar_cache_level(v_key);
    float texel = grammar_cache_texel(level);
    vec2 size = uintBitsToFloat(v_key.zw);
    vec2 local = gl_FragCoord.xy - v_origin;  // i + 0.5
    vec2 page = vec2(grammar_cache_page_xy(v_key));
    vec2 uv = clamp((page * float(GRAMMAR_CACHE_CONTENT) + local - float(GRAMMAR_CACHE_BORDER)) * texel, vec2(0.0), size);
    Building b = buildings[grammar_cache_building(v_key)];
    grammar_set_building(b, grammar_cache_levels(v_key), float(building_first_level(b)));  // cached faces: city.glsl
    vec2 seed = vec2(grammar_facade_cells(b.facade.zw, grammar_cache_face(v_key))) / GRAMMAR_NOISE_DENSITY;
    // the ray matters only to Intrusion, whose texels are marked view-dependent
    float filter_size = grammar_cache_filter(v_key);
    GrammarResult g = grammar_evaluate(b.facade.y, uv, size, seed, vec3(0.0, 0.0, 1.0), vec2(filter_size, 0.0), vec2(0.0, filter_size));
    out_color = vec4(g.color, g.specular.x);
    out_normal = vec4(g.normal, g.specular.y);
    uint flags = (g.glass ? 1u : 0u) | (g.view_dependent ? 2u : 0u) | (uint(g.label) << 2);
    out_ids = uvec4(flags, floatBitsToUint(g.scope.xy + 0.5 * g.scope.zw), uint(g.terminal + 1) | (uint(g.tile + 1) << 16));
}
#endif
