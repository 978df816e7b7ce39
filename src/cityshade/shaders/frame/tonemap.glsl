// HDR -> display: god rays (define GOD_RAYS), exposure, ACES filmic curve (Narkowicz fit), sRGB encoding.
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "common/srgb.glsl"
uniform sampler2D u_hdr;
#if defined GOD_RAYS
uniform sampler2D u_god_rays_image;  // post/godrays.glsl's last step, half resolution
uniform vec2 u_sun_screen;           // the sun's position in texture coordinates (may be off screen)
uniform float u_god_rays;            // strength; 0 when the sun is behind the camera

// the rays, fading with the distance to the sun on screen so they stay around it
vec3 god_rays(vec2 uv) {
    float falloff = 1.0 - smoothstep(0.2, 0.9, length((uv - u_sun_screen) * vec2(1.6, 1.0)));
    return texture(u_god_rays_image, uv).rgb * u_god_rays * falloff;
}
#endif
in vec2 v_uv;
layout(location = 0) out vec4 out_color;

vec3 aces(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}


void main() {
    vec3 hdr = texture(u_hdr, v_uv).rgb;
#if defined GOD_RAYS
    hdr += god_rays(v_uv);
#endif
    hdr *= u_exposure;
    out_color = vec4(linear_to_srgb(aces(hdr)), 1.0);
}
#endif
