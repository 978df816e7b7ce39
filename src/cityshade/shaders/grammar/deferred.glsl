// The deferred grammar pass (§4): one full-screen evaluation per pixel from the G-buffer that
// grammar/city.glsl wrote, with the same lighting as the forward path. The building pass picks the
// result up (lit colour, and glass + label so rooms still show through the glass, and the window
// opening the relief recesses there); other pixels are left alone.
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "grammar/building.glsl"
#include "shadow/csm.glsl"
#if defined GRAMMAR_CACHE
#define GRAMMAR_CACHE_READ
#include "grammar/cache.glsl"
uniform usampler2D u_page;  // the G-buffer's page per pixel
#endif
#if defined BUILDING_LOD
#include "city/lod.glsl"
#endif
#if !defined RELIEF_OFF
#include "relief/openings.glsl"
#endif

uniform sampler2D u_scope;
uniform sampler2D u_rule;
uniform sampler2D u_normal;
uniform sampler2D u_depth;
uniform vec2 u_viewport;

layout(location = 0) out vec4 out_color;
// flags and the relief's opening, colour and label, the window's centre (grammar uv, float bits):
// grammar/building.glsl GRAMMAR_DEFERRED_*
layout(location = 1) out uvec4 out_ids;
layout(location = 2) out vec4 out_opening;  // the relief's opening's scope (relief/openings.glsl), grammar uv

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    float depth = texelFetch(u_depth, pixel, 0).r;
    if (depth >= 1.0) discard;  // sky: nothing was drawn
    vec4 scope = texelFetch(u_scope, pixel, 0);
    vec4 rule = texelFetch(u_rule, pixel, 0);
    vec4 normal_levels = texelFetch(u_normal, pixel, 0);
    vec3 n = normalize(normal_levels.xyz);
    if (rule.w == 0.0) discard;  // roofs and the other facade techniques are shaded by the building pass
    vec4 clip = vec4(gl_FragCoord.xy / u_viewport * 2.0 - 1.0, depth * 2.0 - 1.0, 1.0);
    vec4 world = u_inv_view_proj * clip;
    vec3 d = normalize(world.xyz / world.w - u_camera);
#if defined BUILDING_LOD
    // far, its colour evaluated: the building pass draws the style's mean
    if (lod_cheap_facade(distance(world.xyz / world.w, u_camera), true, int(rule.w) - 1)) {
        out_color = vec4(0.0);
        out_ids = uvec4(GRAMMAR_DEFERRED_SKIPPED, 0u, 0u, 0u);
        return;
    }
#endif
    // texture footprints from the neighbouring pixels' facade coordinates
    vec2 duv_dx = texelFetch(u_scope, pixel + ivec2(1, 0), 0).xy - scope.xy;
    vec2 duv_dy = texelFetch(u_scope, pixel + ivec2(0, 1), 0).xy - scope.xy;
    GrammarResult g;
    vec2 centre;  // the centre of the window the pixel belongs to (grammar_window)
    bool cached = false;
#if defined GRAMMAR_CACHE
    uvec4 page = texelFetch(u_page, pixel, 0);
    // a pixel whose neighbours lie on another face (or the sky) has a far larger footprint here than
    // its page's level: evaluated per pixel, with the filtering it always had
    float footprint = max(length(duv_dx), length(duv_dy));
    cached = page.x != 0u && footprint < 4.0 * grammar_cache_filter(page)
             && grammar_cache_read(page, scope.xy, g, centre);
#endif
    if (!cached) {  // not cached: evaluated here, as without the cache
        Building b = buildings[int(rule.w) - 1];
        grammar_set_building(b, normal_levels.w, rule.z);  // its attributes, facade.level and seed
        g = grammar_facade_at(b.facade.y, scope.xy, scope.zw, rule.xy, n, d, duv_dx, duv_dy);
        centre = g.scope.xy + 0.5 * g.scope.zw;
    }
    vec3 point = world.xyz / world.w;
    out_color = vec4(facade_light(grammar_facade_result(g, n, point), mat3(1.0), d, shadow_factor(point)), 1.0);
    uint seen = (g.glass ? GRAMMAR_DEFERRED_GLASS : 0u) | (!cached && g.hole >= 0 ? GRAMMAR_DEFERRED_HOLE : 0u);
    out_opening = vec4(0.0);
#if !defined RELIEF_OFF
    if (!cached) {  // found here once, so the buildings pass need not evaluate the grammar for its relief
        GrammarOpening o = grammar_opening(g);
        seen |= GRAMMAR_DEFERRED_OPENING | (o.hole ? GRAMMAR_DEFERRED_HOLE_OPENING : 0u)
              | uint(o.index + 1) << GRAMMAR_DEFERRED_OPENING_SHIFT
              | grammar_face_key(int(rule.w) - 1, ivec2(round(rule.xy * GRAMMAR_NOISE_DENSITY))) << GRAMMAR_DEFERRED_FACE_SHIFT;
        out_opening = o.scope;
    }
#endif
    uint color_label = packUnorm4x8(vec4(g.color, 0.0)) | uint(g.label) << GRAMMAR_DEFERRED_LABEL_SHIFT;
    out_ids = uvec4(seen, color_label, floatBitsToUint(centre));
}
#endif
