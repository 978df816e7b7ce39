// Tree trunks and branches: generalised cylinders, relief-mapped bark (§4.2).
// Defines: RELIEF (relief mapping; off = normal-mapped bark), SHADOW_PASS (depth only),
// NO_SHADOWS, ALPHA_TO_COVERAGE (the LOD cross-fade alpha goes to coverage; off: fizzle, §4.6.2),
// ID_PASS (the id AOV: FACE_TRUNK; the relief shifts only the bark's texture, not the outline),
// BAKE (albedo and normal into an impostor view, trees/bake.glsl; no relief, no fade).

#if defined VERTEX_SHADER
#include "trees/instance.glsl"
uniform mat4 u_view_proj;
#include "trees/branch_inputs.glsl"
out vec3 v_world;
out vec3 v_normal;
out vec3 v_tangent;
out vec2 v_uv;
out float v_fade;
void main() {
    vec3 world = tree_to_world(in_position);
    world += wind_offset(world, in_wind);
    v_world = world;
    v_normal = tree_dir_to_world(in_normal);
    v_tangent = tree_dir_to_world(in_tangent);
    v_uv = in_uv;
    v_fade = in_params.y;
    gl_Position = u_view_proj * vec4(world, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
in vec3 v_world;
in vec3 v_normal;
in vec3 v_tangent;
in vec2 v_uv;
in float v_fade;
#include "trees/fade.glsl"
#if defined SHADOW_PASS
void main() {}
#elif defined ID_PASS
layout(location = 0) out uvec4 out_ids;
void main() {
    if (fizzled(v_fade)) discard;
    out_ids = uvec4(uint(FACE_TRUNK), 0u, 0u, 0u);
}
#else
#include "trees/relief.glsl"
#if defined BAKE
#include "trees/bake.glsl"
void main() {
    mat3 frame = bark_frame(v_normal, v_tangent);
    write_bake(bark_albedo(v_uv), bark_normal(v_uv, frame[0], frame[1], frame[2]), 0.0);
}
#else
layout(location = 0) out vec4 out_color;
void main() {
    mat3 frame = bark_frame(v_normal, v_tangent);
    vec3 t = frame[0], b = frame[1], n = frame[2];
#if !defined ALPHA_TO_COVERAGE
    if (fizzled(v_fade)) discard;
#endif
    vec2 uv = v_uv;
#if defined RELIEF
    vec3 view = normalize(v_world - u_camera);
    uv = relief_trace(uv, vec3(dot(view, t), dot(view, b), dot(view, n)));
#endif
    out_color = vec4(shade_bark(uv, t, b, n, v_world), v_fade);
}
#endif
#endif
#endif
