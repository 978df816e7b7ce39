// The sky: a full-screen triangle at the far plane looking up the environment map.
#define FULLSCREEN_AT_FAR
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "common/lighting.glsl"
in vec2 v_ndc;
layout(location = 0) out vec4 out_color;
void main() {
    vec4 far_point = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far_point.xyz / far_point.w - u_camera);
    out_color = vec4(environment(dir), 1.0);
}
#endif
