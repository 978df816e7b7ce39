// Stars of the night sky, drawn per pixel over the environment (a cube-map texel is too coarse):
// a sparse hash of fine cells of the view direction, each a soft point.
#ifndef FRAME_STARS_GLSL
#define FRAME_STARS_GLSL
#include "common/hash.glsl"

uniform float u_stars;  // 0 by day, 1 at astronomical night

const float STAR_CELLS = 400.0;  // cells per unit of direction: a cell spans about 0.14 degrees
const float STAR_SHARE = 0.004;

vec3 stars(vec3 dir) {
    if (u_stars <= 0.0 || dir.y <= 0.0) return vec3(0.0);
    vec3 p = dir * STAR_CELLS;
    ivec3 c = ivec3(floor(p));
    float h = unit_float(pcg_hash(uint(c.x) * 73856093u ^ pcg_hash(uint(c.y) * 19349663u ^ pcg_hash(uint(c.z)))));
    if (h >= STAR_SHARE) return vec3(0.0);
    vec3 f = fract(p) - 0.5;
    float brightness = 0.4 + 3.0 * pow(h / STAR_SHARE, 3.0);
    return vec3(0.9, 0.95, 1.0) * exp(-dot(f, f) * 30.0) * brightness * u_stars * smoothstep(0.0, 0.15, dir.y);
}

#endif
