// roof_pattern() of one roof part's material and one normal at a grid of object-space points, one
// per pixel, times the part's albedo, for the comparison with its numpy twins
// (cityshade/scene/_materials.py roof_pattern, roof_part_material).
#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "city/roof.glsl"

uniform int u_material;
uniform int u_part;
uniform vec3 u_colour;  // the roof's linear colour
uniform vec3 u_normal;  // unit length
uniform vec2 u_origin;  // object-space x, z of pixel (0, 0)
uniform float u_step;   // metres between pixels

out vec4 out_pattern;

void main() {
    vec2 xz = u_origin + floor(gl_FragCoord.xy) * u_step;
    vec4 material = roof_part_material(u_part, vec4(u_colour, float(u_material)));
    out_pattern = roof_pattern(int(material.w), vec3(xz.x, 0.0, xz.y), u_normal);
    out_pattern.rgb *= material.rgb;
}
#endif
