// A frame drawn at a lower internal resolution, stretched bilinearly over the window
// (render/_upscale.py; its numpy twin upscale_reference). Texels are fetched and blended here, so
// the source texture's own filter setting does not matter.
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
uniform sampler2D u_frame;
uniform ivec2 u_output_size;  // the window's pixels
layout(location = 0) out vec4 out_color;

void main() {
    ivec2 size = textureSize(u_frame, 0);
    vec2 scale = vec2(size) / vec2(u_output_size);
    vec2 at = max(gl_FragCoord.xy * scale - 0.5, vec2(0.0));  // source texel centres at (i + 0.5)
    ivec2 low = min(ivec2(floor(at)), size - 1);
    ivec2 high = min(low + 1, size - 1);
    vec2 t = at - vec2(low);
    vec4 bottom = mix(texelFetch(u_frame, low, 0), texelFetch(u_frame, ivec2(high.x, low.y), 0), t.x);
    vec4 top = mix(texelFetch(u_frame, ivec2(low.x, high.y), 0), texelFetch(u_frame, high, 0), t.x);
    out_color = mix(bottom, top, t.y);
}
#endif
