// Street lamps as point lights, clustered on a 2D grid (render/_street_lights.py): a surface
// point reads only the lamps listed for its grid cell.
#ifndef CITY_STREET_LIGHTS_GLSL
#define CITY_STREET_LIGHTS_GLSL

layout(std430, binding = BINDING_STREET_LAMPS) readonly buffer StreetLamps { vec4 lamps[]; };  // bulb x, y, z; reach (m)
layout(std430, binding = BINDING_LAMP_CELL_STARTS) readonly buffer LampCellStarts { uint lamp_cell_start[]; };
layout(std430, binding = BINDING_LAMP_CELL_INDICES) readonly buffer LampCellIndices { uint lamp_index[]; };
uniform vec2 u_lamp_origin;
uniform ivec2 u_lamp_cells;
uniform float u_lamp_cell_size;
#include "generated/ShadingBlock.glsl"

const vec3 LAMP_COLOR = vec3(1.0, 0.72, 0.42);  // sodium-warm white
const float LAMP_INTENSITY = 14.0;  // radiant intensity: irradiance about 0.4 six metres below

// The grid cell of a point, -1 outside; float32 arithmetic as in LightGrid.cell_of.
int lamp_cell(vec3 world) {
    ivec2 c = ivec2(floor((world.xz - u_lamp_origin) / u_lamp_cell_size));
    if (any(lessThan(c, ivec2(0))) || any(greaterThanEqual(c, u_lamp_cells))) return -1;
    return c.y * u_lamp_cells.x + c.x;
}

uint lamps_listed(vec3 world) {
    int cell = lamp_cell(world);
    return cell < 0 ? 0u : lamp_cell_start[cell + 1] - lamp_cell_start[cell];
}

// Irradiance from the lamps at a point with normal n: inverse square, windowed to zero at the reach.
vec3 street_light(vec3 world, vec3 n) {
    int cell = lamp_cell(world);
    if (u_street_lights <= 0.0 || cell < 0) return vec3(0.0);
    vec3 sum = vec3(0.0);
    for (uint i = lamp_cell_start[cell]; i < lamp_cell_start[cell + 1]; ++i) {
        vec4 lamp = lamps[lamp_index[i]];
        vec3 l = lamp.xyz - world;
        float d2 = dot(l, l);
        float window = clamp(1.0 - d2 * d2 / (lamp.w * lamp.w * lamp.w * lamp.w), 0.0, 1.0);
        sum += max(dot(n, l * inversesqrt(d2)), 0.0) * window * window / (d2 + 1.0);
    }
    return sum * LAMP_COLOR * LAMP_INTENSITY * u_street_lights;
}

#endif
