// Roof materials of map buildings: the id in Building.roof.w and the colour in its rgb, or sheet
// metal for rooftop units and dormer cheeks (the part in the vertex's ids.z)
// (cityshade/scene/_materials.py, whose roof_pattern and roof_part_material are the numpy twins here).
// Courses of tiles and slates run across the slope, metal seams down it, gravel is pebbles in
// patches; metal, copper and glass reflect the sky.
#ifndef CITY_ROOF_GLSL
#define CITY_ROOF_GLSL

#include "common/buildings.glsl"
#include "common/lighting.glsl"


// one cell of a pattern: 0 at its lower edge, 1 at its upper one
float roof_course(float metres, float size) {
    return fract(metres / size);
}

// a stone's own shade, 0..1, from its integer cell (an avalanche hash; _stone in _materials.py)
float stone(ivec2 c) {
    uint h = (uint(c.x) * 0x9E3779B1u) ^ (uint(c.y) * 0x85EBCA77u);
    h ^= h >> 15u;
    h *= 0x2C1B3C6Du;
    h ^= h >> 12u;
    return float(h & 255u) / 255.0;
}

// albedo variation and reflectance (f0, 0: none) of a roof material at an object-space point
vec4 roof_pattern(int material, vec3 local, vec3 n) {
    vec2 down = n.xz;
    float slope = length(down);
    down = slope > 1e-3 ? down / slope : vec2(0.0, 1.0);
    float s = dot(local.xz, down) / max(n.y, 0.2);  // metres down the slope
    float t = dot(local.xz, vec2(-down.y, down.x));   // metres across it
    ivec2 c = ivec2(floor(vec2(s, t) / 0.3));
    float cell = float((c.x * 7 + c.y * 13 + 500000) % 5) / 4.0;  // a tile's own shade, 0..1
    if (material == ROOF_TILES) {
        float row = roof_course(s + 0.5 * floor(t / 0.25), 0.33);
        return vec4(vec3(0.7 + 0.3 * smoothstep(0.0, 0.25, row) + 0.08 * (cell - 0.5)), 0.0);
    }
    if (material == ROOF_SLATE) {
        float row = roof_course(s, 0.22);
        return vec4(vec3(0.8 + 0.2 * smoothstep(0.0, 0.15, row) + 0.12 * (cell - 0.5)), 0.04);
    }
    if (material == ROOF_METAL || material == ROOF_COPPER) {
        float seam = smoothstep(0.0, 0.04, abs(roof_course(t, 0.55) - 0.5) - 0.44);
        return vec4(vec3(1.0 - 0.35 * seam), material == ROOF_METAL ? 0.25 : 0.1);
    }
    if (material == ROOF_GLASS) return vec4(vec3(0.6), 0.5);
    if (material == ROOF_GRAVEL) {  // pebbles of about 4 cm, in patches of 13 cm
        float fine = stone(ivec2(floor(vec2(s, t) / 0.04)));
        float coarse = stone(ivec2(floor(vec2(s, t) / 0.13)) + ivec2(7919, 0));
        return vec4(vec3(0.8 + 0.35 * fine + 0.15 * coarse - 0.25), 0.0);
    }
    if (material == ROOF_GRASS || material == ROOF_CONCRETE || material == ROOF_WOOD) {
        return vec4(vec3(0.85 + 0.3 * (cell - 0.5)), 0.0);
    }
    return vec4(1.0, 1.0, 1.0, 0.0);
}

// (linear albedo, pattern id) of a part of a roof whose record is `roof` (rgb, pattern id): its own
// surface, or the sheet metal of rooftop units and dormer cheeks (roof_part_material in _materials.py)
vec4 roof_part_material(int part, vec4 roof) {
    return part == ROOF_PART_SHEET ? vec4(ROOF_SHEET_ALBEDO, float(ROOF_METAL)) : roof;
}

// the lit colour of a roof part seen along `view` (world, unit, toward the surface)
vec3 roof_color(Building b, int part, vec3 local, vec3 n, vec3 n_world, vec3 view, float shadow) {
    vec4 material = roof_part_material(part, b.roof);
    vec4 pattern = roof_pattern(int(material.w), local, n);
    vec3 color = lit_surface(material.rgb * pattern.rgb, n_world, shadow);
    if (pattern.a > 0.0) {
        float reflectance = fresnel(max(-dot(view, n_world), 0.0), pattern.a);
        color = mix(color, environment(reflect(view, n_world)) * mix(vec3(1.0), material.rgb * 2.0, 0.5), reflectance);
    }
    return color;
}

#endif
