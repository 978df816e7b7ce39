// Streets, pavements and parks: flat quads with a material id, procedurally textured; for cities
// from maps also water, paint, tracks and lamp posts (city/map_ground.glsl).
// Defines: DEPTH_ONLY, ID_PASS.
#if defined VERTEX_SHADER
uniform mat4 u_view_proj;
in vec3 in_position;
in float in_material;
out vec3 v_world;
flat out int v_material;
invariant gl_Position;
void main() {
    gl_Position = u_view_proj * vec4(in_position, 1.0);
    v_world = in_position;
    v_material = int(in_material);
}
#endif

#if defined FRAGMENT_SHADER
#if defined DEPTH_ONLY
void main() {}
#else
#include "common/lighting.glsl"
#include "common/hash.glsl"
#include "shadow/csm.glsl"
#include "city/map_ground.glsl"
#include "city/ground_normal.glsl"
in vec3 v_world;
flat in int v_material;
#if defined ID_PASS
layout(location = 0) out uvec4 out_ids;
#else
layout(location = 0) out vec4 out_color;
#endif

float lattice(ivec2 c) {
    return unit_float(pcg_hash(uint(c.x * 7919) ^ pcg_hash(uint(c.y))));
}

// Value noise: lattice values blended smoothly, so grass and asphalt show no square cells.
float grain(vec2 p) {
    ivec2 c = ivec2(floor(p));
    vec2 f = fract(p);
    f = f * f * (3.0 - 2.0 * f);
    return mix(mix(lattice(c), lattice(c + ivec2(1, 0)), f.x),
               mix(lattice(c + ivec2(0, 1)), lattice(c + ivec2(1, 1)), f.x), f.y);
}

void main() {
#if defined ID_PASS
    out_ids = uvec4(uint(FACE_GROUND), lamps_listed(v_world), 0u, uint(v_material));  // y: the lamps of its light-grid cell, w: material
#else
    float shadow = shadow_factor(v_world);
    vec3 albedo, color;
    vec3 n = vec3(0.0, 1.0, 0.0);
    vec3 face = ground_face_normal(v_world);  // here, where every pixel of the quad takes derivatives
    if (v_material == GROUND_PAVEMENT) {
        vec2 slab = fract(v_world.xz / 1.5);
        float joint = step(0.04, slab.x) * step(0.04, slab.y);
        albedo = vec3(0.42, 0.41, 0.39) * mix(0.7, 1.0, joint) * (0.92 + 0.08 * grain(v_world.xz / 1.5));
    } else if (v_material == GROUND_GRASS) {
        albedo = vec3(0.10, 0.20, 0.06) * (0.8 + 0.4 * grain(v_world.xz * 3.0));
    } else if (v_material == GROUND_ASPHALT) {
        albedo = vec3(0.085, 0.085, 0.09) * (0.85 + 0.3 * grain(v_world.xz * 8.0));
    } else {
        albedo = map_albedo(v_material, v_world, grain(v_world.xz * 4.0));
        n = v_material == GROUND_TERRAIN ? face : map_normal(v_material, v_world);  // a DEM's slopes
    }
    color = v_material == GROUND_WATER ? water_surface(v_world, shadow)
                                       : lit_surface(albedo, n, shadow) + albedo * street_light(v_world, n);
    out_color = vec4(ground_haze(color + map_emission(v_material), v_world), 1.0);
#endif
}
#endif
#endif
