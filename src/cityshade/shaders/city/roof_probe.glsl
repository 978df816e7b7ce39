// roof_pattern() of one material and normal at a grid of object-space points, one per pixel, for
// the comparison with its numpy twin (cityshade/scene/_materials.py roof_pattern).
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "city/roof.glsl"

uniform int u_material;
uniform vec3 u_normal;  // unit length
uniform vec2 u_origin;  // object-space x, z of pixel (0, 0)
uniform float u_step;   // metres between pixels

out vec4 out_pattern;

void main() {
    vec2 xz = u_origin + floor(gl_FragCoord.xy) * u_step;
    out_pattern = roof_pattern(u_material, vec3(xz.x, 0.0, xz.y), u_normal);
}
#endif
