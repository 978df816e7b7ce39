// The sky: a full-screen triangle at the far plane looking up the sky's cube map, with the sun's
// and the moon's discs drawn per pixel (cityshade/render/_sky_discs.py, whose sky_discs_reference
// is the numpy twin): round at any size on screen, where the cube map's texels would show squares.
#define FULLSCREEN_AT_FAR
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "common/lighting.glsl"
#include "frame/stars.glsl"
#define SKY_DISCS 2
uniform vec4 u_discs[SKY_DISCS];            // unit direction, angular radius (radians)
uniform vec3 u_disc_radiance[SKY_DISCS];    // linear HDR; zero: not in the sky
uniform float u_pixel_angle;                // radians a pixel spans: the discs' edges are antialiased over it
in vec2 v_ndc;
layout(location = 0) out vec4 out_color;
void main() {
    vec4 far_point = u_inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far_point.xyz / far_point.w - u_camera);
    vec3 color = environment(dir) + stars(dir);
    for (int i = 0; i < SKY_DISCS; i++) {  // in front of the stars
        float angle = acos(clamp(dot(dir, u_discs[i].xyz), -1.0, 1.0));
        float cover = dir.y >= 0.0 ? clamp((u_discs[i].w - angle) / u_pixel_angle + 0.5, 0.0, 1.0) : 0.0;
        color = mix(color, u_disc_radiance[i], cover);
    }
    out_color = vec4(color, 1.0);
}
#endif
