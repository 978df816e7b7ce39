// Per-tree instance placement and wind sway, shared by every tree program and by the shadow pass
// so that a swaying tree and its shadow move together.
#ifndef TREES_INSTANCE_GLSL
#define TREES_INSTANCE_GLSL

in vec4 in_place;   // world xyz of the trunk base, yaw (radians)
in vec4 in_params;  // scale, LOD fade alpha, wind phase, unused

uniform vec3 u_wind;  // direction * strength (metres of sway at weight 1)

vec3 tree_dir_to_world(vec3 d) {
    float c = cos(in_place.w), s = sin(in_place.w);
    return vec3(c * d.x + s * d.z, d.y, -s * d.x + c * d.z);
}

vec3 tree_to_world(vec3 p) {
    return in_place.xyz + tree_dir_to_world(p) * in_params.x;
}

// Sway grows with the vertex's wind weight (0 at the trunk base); two detuned sines per tree.
vec3 wind_offset(vec3 world, float weight) {
    float phase = in_params.z + dot(world.xz, vec2(0.07, 0.05));
    float sway = 0.7 * sin(u_time * 1.3 + phase) + 0.3 * sin(u_time * 2.9 + 1.7 * phase);
    return u_wind * (weight * sway) + vec3(0.0, -0.15 * abs(sway) * weight * length(u_wind), 0.0);
}

#endif
