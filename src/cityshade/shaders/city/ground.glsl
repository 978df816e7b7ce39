// Streets, pavements and parks: flat quads with a material id, procedurally textured.
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
    out_ids = uvec4(uint(FACE_GROUND), 0u, 0u, 0u);
#else
    vec3 albedo;
    if (v_material == GROUND_PAVEMENT) {
        vec2 slab = fract(v_world.xz / 1.5);
        float joint = step(0.04, slab.x) * step(0.04, slab.y);
        albedo = vec3(0.42, 0.41, 0.39) * mix(0.7, 1.0, joint) * (0.92 + 0.08 * grain(v_world.xz / 1.5));
    } else if (v_material == GROUND_GRASS) {
        albedo = vec3(0.10, 0.20, 0.06) * (0.8 + 0.4 * grain(v_world.xz * 3.0));
    } else {
        albedo = vec3(0.085, 0.085, 0.09) * (0.85 + 0.3 * grain(v_world.xz * 8.0));
    }
    out_color = vec4(lit_surface(albedo, vec3(0.0, 1.0, 0.0), shadow_factor(v_world)), 1.0);
#endif
}
#endif
#endif
