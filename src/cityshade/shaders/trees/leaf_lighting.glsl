// Two-sided leaf lighting (§4.4.1) and specular (§4.4.2).
// Looking toward the sun through the leaves, the colour is lerped toward a yellowed
// transmitted colour and the specular is reduced; specular also fades with distance.
#ifndef TREES_LEAF_LIGHTING_GLSL
#define TREES_LEAF_LIGHTING_GLSL

#include "common/lighting.glsl"

uniform vec2 u_specular_fade;  // specular falls from full to zero between these distances

// How much the view looks into the sun: 0 away from it, 1 straight into it.
float backlight(vec3 view) {
    return smoothstep(0.0, 0.9, dot(view, u_sun_dir));
}

// albedo: leaf texture colour; n: leaf normal facing the viewer; view: eye -> point, unit.
vec3 shade_leaf(vec3 albedo, vec3 n, vec3 view, float shadow, float dist) {
    float mu = backlight(view);
#if defined TWO_SIDED
    vec3 transmitted = vec3(albedo.g * 0.9, albedo.g * 1.0, albedo.g * 0.2);
    vec3 color = mix(albedo, transmitted, mu);
    // Lit from behind the light arrives through the leaf: use the back side's cosine.
    float diffuse = mix(max(dot(n, u_sun_dir), 0.0), max(-dot(n, u_sun_dir), 0.0) * 1.2, mu);
    float spec_scale = 1.0 - mu;
#else
    vec3 color = albedo;
    float diffuse = max(dot(n, u_sun_dir), 0.0);
    float spec_scale = 1.0;
#endif
    vec3 h = normalize(u_sun_dir - view);
    float spec = pow(max(dot(n, h), 0.0), 12.0) * 0.25 * spec_scale;
    spec *= 1.0 - smoothstep(u_specular_fade.x, u_specular_fade.y, dist);
    return color * (u_sun_color * diffuse * shadow + ambient_light(n)) + u_sun_color * spec * shadow;
}

#endif
