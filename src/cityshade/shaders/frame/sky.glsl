// The sky: a full-screen triangle at the far plane looking up the environment map.
#if defined VERTEX_SHADER
out vec2 v_ndc;
void main() {
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    v_ndc = p;
    gl_Position = vec4(p, 1.0, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
#include "common/lighting.glsl"
#include "frame/stars.glsl"
uniform mat4 u_inv_view_proj;
uniform vec3 u_camera;
in vec2 v_ndc;
layout(location = 0) out vec4 out_color;
void main() {
    vec4 far_point = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far_point.xyz / far_point.w - u_camera);
    out_color = vec4(environment(dir) + stars(dir), 1.0);
}
#endif
