// God rays (SpeedTree §4.5): a radial blur of the frame's bright pixels toward the sun's position
// on screen, added to the HDR colour before tone mapping (frame/tonemap.glsl). Leaves and trunks in
// front of the sun block the bright sky pixels, so the rays come out as shafts between them.
//
// Drawn at half resolution in steps (cityshade/render/_godrays.py, whose god_rays_reference is the
// numpy twin): BRIGHT_PASS keeps the part of each frame pixel over u_bright, a 2x2 block's mean;
// then each blur step sums GOD_RAY_TAPS taps toward the sun, u_spacing apart (a fraction of the way
// to it), on the previous step's result. Three steps with spacings 1/64, 1/8 and 1 of the longest
// add up to 512 evenly spaced taps without noise, where one step of 16 jittered taps was grainy.
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
in vec2 v_uv;
layout(location = 0) out vec4 out_color;

#if defined BRIGHT_PASS
uniform sampler2D u_hdr;    // the frame, full resolution
uniform float u_bright;     // luminance above which a pixel feeds the rays

vec3 bright_part(vec3 c) {
    float luma = dot(c, vec3(0.2126, 0.7152, 0.0722));
    return c * (max(luma - u_bright, 0.0) / max(luma, 1e-4));
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy) * 2;
    ivec2 last = textureSize(u_hdr, 0) - 1;
    vec3 sum = vec3(0.0);
    for (int i = 0; i < 4; i++) {
        sum += bright_part(texelFetch(u_hdr, min(p + ivec2(i & 1, i >> 1), last), 0).rgb);
    }
    out_color = vec4(0.25 * sum, 1.0);
}
#else
#define GOD_RAY_TAPS 8

uniform sampler2D u_rays;    // the previous step, half resolution, filtered linearly
uniform vec2 u_sun_screen;   // the sun's position in texture coordinates (may be off screen)
uniform float u_spacing;     // between taps: this fraction of the way to the sun
uniform float u_decay;       // the taps' weight falls as exp(-u_decay * fraction of the way)

void main() {
    vec2 step = (u_sun_screen - v_uv) * u_spacing;
    float weight = exp(-u_decay * u_spacing);
    vec3 sum = vec3(0.0);
    float w = 1.0;
    vec2 p = v_uv;
    for (int i = 0; i < GOD_RAY_TAPS; i++) {
        if (any(lessThan(p, vec2(0.0))) || any(greaterThan(p, vec2(1.0)))) break;  // off screen: nothing
        sum += w * textureLod(u_rays, p, 0.0).rgb;
        w *= weight;
        p += step;
    }
    out_color = vec4(sum / float(GOD_RAY_TAPS), 1.0);
}
#endif
#endif
