// Screen-space ambient occlusion (Krecklau & Kobbelt's deferred pipeline, §4) from the depth buffer
// alone, applied to the resolved HDR colour before tone mapping. Samples a fixed disc around each
// pixel and counts the neighbours that stand in front of it within a world-sized radius; darkens
// by at most SSAO_STRENGTH, never brightens, and leaves the sky (depth 1) untouched.

#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
uniform sampler2D u_color;
uniform sampler2D u_depth;
uniform vec2 u_near_far;
uniform float u_pixels_per_metre;  // at one metre distance: viewport height / (2 tan(fov / 2))

layout(location = 0) out vec4 out_color;

#define SSAO_SAMPLES 8
#define SSAO_RADIUS 1.2
#define SSAO_STRENGTH 0.6

float linear_depth(float d) {
    float z = d * 2.0 - 1.0;
    return 2.0 * u_near_far.x * u_near_far.y / (u_near_far.y + u_near_far.x - z * (u_near_far.y - u_near_far.x));
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 color = texelFetch(u_color, pixel, 0);
    float raw = texelFetch(u_depth, pixel, 0).r;
    if (raw >= 1.0) {
        out_color = color;
        return;
    }
    float z = linear_depth(raw);
    float radius_px = clamp(SSAO_RADIUS * u_pixels_per_metre / z, 2.0, 40.0);
    ivec2 size = textureSize(u_depth, 0);
    float angle = fract(sin(dot(vec2(pixel), vec2(12.9898, 78.233))) * 43758.5453) * 6.2831853;
    float occlusion = 0.0;
    for (int i = 0; i < SSAO_SAMPLES; ++i) {
        float a = angle + float(i) * 2.3999632;  // golden-angle spiral
        float r = radius_px * sqrt((float(i) + 0.5) / float(SSAO_SAMPLES));
        ivec2 q = clamp(pixel + ivec2(vec2(cos(a), sin(a)) * r), ivec2(0), size - 1);
        float dz = z - linear_depth(texelFetch(u_depth, q, 0).r);
        occlusion += (dz > 0.05 && dz < SSAO_RADIUS * 2.0) ? 1.0 - dz / (SSAO_RADIUS * 2.0) : 0.0;
    }
    out_color = vec4(color.rgb * (1.0 - SSAO_STRENGTH * occlusion / float(SSAO_SAMPLES)), color.a);
}
#endif
