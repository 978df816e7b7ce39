// Leaf cards (§4.3.1) and, with FRONDS, conifer frond ribbons, both alpha-textured from the leaf
// atlas. Cards face the camera in the main pass; in the shadow pass the same code makes them face
// the light and shifts them toward it by half their height (fig. 4-10), through u_card_right,
// u_card_up and u_card_shift. Defines: FRONDS, SHADOW_PASS, ALPHA_TO_COVERAGE (off: alpha test),
// LEAF_SELF_SHADOW (shadow look-up moved along the view by the per-leaf depth offset, listing
// 4-1), TWO_SIDED, NO_SHADOWS, ID_PASS (the id AOV's FACE_FOLIAGE where the alpha-tested leaf is),
// BAKE (albedo and normal of the alpha-tested leaf into an impostor view, trees/bake.glsl).

#define ATLAS_CELLS 2.0
#define FROND_CELL 3.0

#if defined VERTEX_SHADER
#include "trees/instance.glsl"
uniform mat4 u_view_proj;
#if defined FRONDS
in vec3 in_position;
in vec3 in_normal;
in vec2 in_uv;
in float in_wind;
#else
uniform vec3 u_card_right;  // world axes the cards span: the camera's, or the light's
uniform vec3 u_card_up;
uniform vec3 u_card_shift;  // shift per metre of card half-size (toward the light when casting)
in vec3 in_center;
in vec2 in_corner;
in float in_size;
in float in_cell;
in float in_wind;
in float in_spin;
#endif
out vec3 v_world;
out vec3 v_normal;
out vec3 v_right;
out vec3 v_up;
out vec2 v_uv;
out float v_fade;
out float v_size;

vec2 atlas_uv(float cell, vec2 local) {
    vec2 origin = vec2(mod(cell, ATLAS_CELLS), floor(cell / ATLAS_CELLS));
    return (origin + local) / ATLAS_CELLS;
}

void main() {
#if defined FRONDS
    vec3 world = tree_to_world(in_position);
    world += wind_offset(world, in_wind);
    v_normal = tree_dir_to_world(in_normal);
    v_right = vec3(0.0);
    v_up = vec3(0.0);
    v_uv = atlas_uv(FROND_CELL, vec2(in_uv.x, 1.0 - in_uv.y));
    v_size = 0.5;
#else
    vec3 center = tree_to_world(in_center);
    center += wind_offset(center, in_wind);
    float size = in_size * in_params.x;
    float c = cos(in_spin), s = sin(in_spin);
    vec3 right = c * u_card_right + s * u_card_up;
    vec3 up = -s * u_card_right + c * u_card_up;
    vec3 world = center + (right * in_corner.x + up * in_corner.y) * size + u_card_shift * size;
    v_normal = cross(u_card_right, u_card_up);
    v_right = right;
    v_up = up;
    v_uv = atlas_uv(in_cell, in_corner * 0.5 + 0.5);
    v_size = size;
#endif
    v_world = world;
    v_fade = in_params.y;
    gl_Position = u_view_proj * vec4(world, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_leaf_color;   // rgb colour, a coverage
in vec3 v_world;
in vec3 v_normal;
in vec3 v_right;
in vec3 v_up;
in vec2 v_uv;
in float v_fade;
in float v_size;
#include "trees/fade.glsl"
#include "trees/leaf_alpha.glsl"

#if defined SHADOW_PASS
void main() {
    if (texture(u_leaf_color, v_uv).a < 0.5) discard;
}
#elif defined ID_PASS
layout(location = 0) out uvec4 out_ids;
void main() {
    if (leaf_alpha(v_uv) < 0.5 || fizzled(v_fade)) discard;
    out_ids = uvec4(uint(FACE_FOLIAGE), 0u, 0u, 0u);
}
#else
uniform sampler2D u_leaf_detail;  // rg V-shaped normal, b per-leaf depth offset
uniform float u_normal_bias;      // mip bias of the leaf normal fetch (§4.4.2)

// The leaf's normal from `n`, the card's (or frond's) normal facing the viewer: cards tilt it
// by the V-shaped normal map.
vec3 leaf_normal(vec3 n) {
#if defined FRONDS
    return n;
#else
    vec2 vn = texture(u_leaf_detail, v_uv, u_normal_bias).rg * 2.0 - 1.0;
    return normalize(n + v_right * vn.x + v_up * vn.y);
#endif
}

#if defined BAKE
#include "trees/bake.glsl"
uniform vec3 u_bake_dir;  // toward the view's eye
void main() {
    if (leaf_alpha(v_uv) < 0.5) discard;
    vec3 n = normalize(v_normal);
    if (dot(n, u_bake_dir) < 0.0) n = -n;
    write_bake(texture(u_leaf_color, v_uv).rgb, leaf_normal(n), 1.0);
}
#else
#include "trees/leaf_lighting.glsl"
#include "shadow/csm.glsl"
uniform float u_leaf_depth;       // shift toward the eye at depth offset 1, in card half-sizes
layout(location = 0) out vec4 out_color;

void main() {
    vec4 albedo = vec4(texture(u_leaf_color, v_uv).rgb, leaf_alpha(v_uv));
    float alpha = albedo.a * v_fade;
#if defined ALPHA_TO_COVERAGE
    // Sharpen the coverage edge to about one pixel so the mask does not blur whole leaves.
    alpha = clamp((albedo.a - 0.5) / max(fwidth(albedo.a), 1e-4) + 0.5, 0.0, 1.0) * v_fade;
#else
    if (albedo.a < 0.5 || fizzled(v_fade)) discard;
    alpha = 1.0;
#endif
    if (alpha <= 0.0) discard;
    vec3 view = v_world - u_camera;
    float dist = length(view);
    view /= dist;
    vec3 n = normalize(v_normal);
    if (dot(n, view) > 0.0) n = -n;  // light the side facing the viewer
    vec3 normal = leaf_normal(n);
    vec3 shadow_pos = v_world;
#if defined LEAF_SELF_SHADOW
    shadow_pos -= view * (texture(u_leaf_detail, v_uv).b * u_leaf_depth * v_size);  // toward the eye
#endif
    vec3 color = shade_leaf(albedo.rgb, normal, view, shadow_factor(shadow_pos), dist);
    out_color = vec4(color, alpha);
}
#endif
#endif
#endif
