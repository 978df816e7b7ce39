// HDR -> display: god rays (define GOD_RAYS), exposure, ACES filmic curve (Narkowicz fit), sRGB encoding.
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "common/srgb.glsl"
uniform sampler2D u_hdr;
#if defined GOD_RAYS
#include "post/godrays.glsl"
#endif
in vec2 v_uv;
layout(location = 0) out vec4 out_color;

vec3 aces(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}


void main() {
    vec3 hdr = texture(u_hdr, v_uv).rgb;
#if defined GOD_RAYS
    hdr += god_rays(u_hdr, v_uv);
#endif
    hdr *= u_exposure;
    out_color = vec4(linear_to_srgb(aces(hdr)), 1.0);
}
#endif
