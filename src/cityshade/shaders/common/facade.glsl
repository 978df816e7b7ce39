// What a facade technique (window bay with interior mapping, grammar, relief) says about the wall
// point a fragment sees: each technique fills a FacadeResult, and facade_light lights every one,
// so all facades share one lighting (city/building.glsl; the grammar's own paths in grammar/).
#ifndef COMMON_FACADE_GLSL
#define COMMON_FACADE_GLSL

#include "common/buildings.glsl"
#include "common/hash.glsl"
#include "common/lighting.glsl"

struct FacadeResult {
    vec3 albedo;    // linear diffuse colour
    vec3 normal;    // unit; object space (world space where the rotation given to facade_light is 1)
    vec2 specular;  // Phong intensity, shininess / 128; (0, 0): none
    float glass;    // 1 where the room behind shows through (a fraction at filtered pane edges)
    vec3 point;     // object space: the surface seen, the wall point moved by the technique's depth offset
    uint label;     // grammar label for the id AOV (0: none)
};

// Sun and sky on a facade's material, plus the sun's Phong highlight where it is specular. rot
// turns the result's space into world space, d is the unit view ray in the result's space and
// shadow is 1 where the sun reaches the point (shadow/csm.glsl), 0 in shadow.
vec3 facade_light(FacadeResult f, mat3 rot, vec3 d, float shadow) {
    vec3 n_world = rot * f.normal;
    vec3 color = lit_surface(f.albedo, n_world, shadow);
    if (f.specular.x > 0.0) {
        vec3 half_vector = normalize(u_sun_dir - rot * d);
        float shininess = 1.0 + 128.0 * f.specular.y;
        float highlight = f.specular.x * pow(max(dot(n_world, half_vector), 0.0), shininess)
                        * max(dot(n_world, u_sun_dir), 0.0);
        color += shadow * highlight * u_sun_color;
    }
    return color;
}

// The building's colour over the (grey) window-bay and relief textures: a tagged colour or
// material, else a small random variation per building.
vec3 building_tint(Building b) {
    if (b.tint.w > 0.0) return b.tint.rgb * TINT_GAIN;
    uint h = pcg_hash(uint(b.ids.x) ^ 0x9E37u);
    return vec3(0.8) + 0.35 * vec3(float(h & 255u), float((h >> 8u) & 255u), float((h >> 16u) & 255u)) / 255.0 - 0.17;
}

#endif
