// HDR -> display: god rays (define GOD_RAYS), exposure, ACES filmic curve (Narkowicz fit), sRGB encoding.
#if defined VERTEX_SHADER
out vec2 v_uv;
void main() {
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    v_uv = p * 0.5 + 0.5;
    gl_Position = vec4(p, 0.0, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_hdr;
#if defined GOD_RAYS
#include "post/godrays.glsl"
#endif
uniform float u_exposure;
in vec2 v_uv;
layout(location = 0) out vec4 out_color;

vec3 aces(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 srgb_encode(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main() {
    vec3 hdr = texture(u_hdr, v_uv).rgb;
#if defined GOD_RAYS
    hdr += god_rays(u_hdr, v_uv);
#endif
    hdr *= u_exposure;
    out_color = vec4(srgb_encode(aces(hdr)), 1.0);
}
#endif
