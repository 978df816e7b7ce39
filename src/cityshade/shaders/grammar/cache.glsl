// The grammar page cache (cityshade/grammar/_cache.py): page keys, slots in the atlas and, with
// the atlas bound, reading a resident page. The GRAMMAR_CACHE_* defines come from cache_defines().
#ifndef GRAMMAR_CACHE_GLSL
#define GRAMMAR_CACHE_GLSL

uniform vec2 u_cache_atlas_size;  // texels
uniform int u_cache_per_row;      // slots per atlas row

// Metres per texel at a level.
float grammar_cache_texel(int level) { return GRAMMAR_CACHE_TEXEL * exp2(float(level)); }

// The lower-left texel of a slot in the atlas.
vec2 grammar_cache_origin(int slot) {
    return vec2(float(slot % u_cache_per_row), float(slot / u_cache_per_row)) * float(GRAMMAR_CACHE_PAGE);
}

// The page a pixel of a face needs (building index, face index, the face's storeys, grammar uv and
// size, the uv's screen derivatives): the level whose texels are no bigger than the pixel's
// smallest footprint, so the cache is never blurrier than the pixel, and the level whose texel
// size its tiles are filtered at, from the pixel's largest footprint, as the per-pixel path's
// isotropic mip selection filters them (kept as the difference, 0..7; rounded down, which
// measured closest to the per-pixel picture). uvec4(0) where it cannot be cached (a
// pixel finer than level 0, or a key out of its bits): the pixel is evaluated per pixel.
// Returns the key (x, y) and the face's width and height as float bits (z, w).
uvec4 grammar_cache_page(int building, int face, float levels, vec2 uv, vec2 size, vec2 duv_dx, vec2 duv_dy) {
    float smallest = min(length(duv_dx), length(duv_dy)) / GRAMMAR_CACHE_TEXEL;
    float largest = max(length(duv_dx), length(duv_dy)) / GRAMMAR_CACHE_TEXEL;
    if (!(smallest >= 1.0)) return uvec4(0u);  // also a NaN footprint
    int level = min(int(floor(log2(smallest))), GRAMMAR_CACHE_LEVELS - 1);
    int filter_steps = clamp(int(floor(log2(largest))) - level, 0, 7);
    float span = grammar_cache_texel(level) * float(GRAMMAR_CACHE_CONTENT);
    ivec2 page = clamp(ivec2(floor(uv / span)), ivec2(0), ivec2(floor(size / span)));
    if (building >= (1 << 21) - 1 || face >= 1024 || levels > 255.0 || page.x >= 1024 || page.y >= 256) return uvec4(0u);
    return uvec4(uint(building + 1) | (uint(filter_steps) << 21) | (uint(levels) << 24),
                 uint(face) | (uint(level) << 10) | (uint(page.x) << 14) | (uint(page.y) << 24), floatBitsToUint(size));
}

int grammar_cache_building(uvec4 key) { return int(key.x & 0x1FFFFFu) - 1; }
float grammar_cache_levels(uvec4 key) { return float(key.x >> 24); }
int grammar_cache_face(uvec4 key) { return int(key.y & 1023u); }
int grammar_cache_level(uvec4 key) { return int((key.y >> 10) & 15u); }
ivec2 grammar_cache_page_xy(uvec4 key) { return ivec2((key.y >> 14) & 1023u, key.y >> 24); }
// The texel size the page's tiles are filtered at.
float grammar_cache_filter(uvec4 key) { return grammar_cache_texel(grammar_cache_level(key) + int((key.x >> 21) & 7u)); }

// Texel coordinates inside a page of a point of its face (texel centres at i + 0.5).
vec2 grammar_cache_local(uvec4 key, vec2 uv) {
    return uv / grammar_cache_texel(grammar_cache_level(key)) - vec2(grammar_cache_page_xy(key)) * float(GRAMMAR_CACHE_CONTENT)
           + float(GRAMMAR_CACHE_BORDER);
}

// The page table's hash (cityshade.grammar._cache.page_hash).
uint grammar_cache_hash(uvec2 key) {
    uint h = (key.x * 0x9E3779B1u) ^ (key.y * 0x85EBCA77u);
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    return h;
}

#if defined GRAMMAR_CACHE_READ
layout(std430, binding = BINDING_GRAMMAR_PAGE_TABLE) readonly buffer GrammarPageTable { uvec4 grammar_page_table[]; };  // key x, key y, slot
uniform int u_cache_table_mask;
uniform int u_cache_probes;
uniform sampler2D u_cache_color;   // sRGB colour, specular intensity
uniform sampler2D u_cache_normal;  // tangent-space normal, shininess
uniform usampler2D u_cache_ids;    // glass | view-dependent << 1 | label << 2, the window's centre (float bits), Mat

// The slot holding a page, -1 if it is not resident.
int grammar_cache_slot(uvec2 key) {
    uint h = grammar_cache_hash(key);
    for (int i = 0; i < GRAMMAR_CACHE_MAX_PROBES && i < u_cache_probes; ++i) {
        uvec4 entry = grammar_page_table[(h + uint(i)) & uint(u_cache_table_mask)];
        if (entry.x == key.x && entry.y == key.y) return int(entry.z);
        if (entry.x == 0u) break;
    }
    return -1;
}

// The cached grammar at a pixel whose page is `key` and grammar uv `uv`: false if the page is not
// resident, or if a texel the pixel reads was decided by the view ray (an Intrusion), which a
// texel evaluated once cannot know, or if the texels around it were decided by different Mats;
// colour, normal and specular filtered bilinearly, glass, label and window (centre: the window's
// centre in grammar uv) those of the four texels.
bool grammar_cache_read(uvec4 key, vec2 uv, out GrammarResult g, out vec2 centre) {
    int slot = grammar_cache_slot(key.xy);
    if (slot < 0) return false;
    vec2 local = clamp(grammar_cache_local(key, uv), vec2(0.5), vec2(float(GRAMMAR_CACHE_PAGE) - 0.5));
    vec2 at = grammar_cache_origin(slot) + local;
    vec2 st = at / u_cache_atlas_size;
    uvec4 flags = textureGather(u_cache_ids, st, 0);
    if (((flags.x | flags.y | flags.z | flags.w) & 2u) != 0u) return false;
    // the four texels must agree on the winning Mat, its scope and glass: a pixel between two
    // decisions (a window's edge) is evaluated per pixel, so it decides exactly as without the cache
    uvec4 ids = texelFetch(u_cache_ids, ivec2(floor(at)), 0);
    if (any(notEqual(flags, uvec4(ids.x))) || any(notEqual(textureGather(u_cache_ids, st, 1), uvec4(ids.y)))
        || any(notEqual(textureGather(u_cache_ids, st, 2), uvec4(ids.z)))
        || any(notEqual(textureGather(u_cache_ids, st, 3), uvec4(ids.w))))
        return false;
    vec4 a = textureLod(u_cache_color, st, 0.0);
    vec4 b = textureLod(u_cache_normal, st, 0.0);
    g.color = a.rgb;
    g.alpha = 1.0;
    g.terminal = -1;  // not kept: the frame needs none of these
    g.tile = -1;
    g.scope = vec4(0.0);
    g.view_dependent = false;
    g.normal = normalize(b.xyz);
    g.specular = vec2(a.w, b.w);
    g.glass = (ids.x & 1u) != 0u;
    g.label = int(ids.x >> 2);
    centre = uintBitsToFloat(ids.yz);
    return true;
}
#endif

#endif
