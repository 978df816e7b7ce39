// Cascaded shadow maps (§4.3.2): the cascades are fetched with 3x3 PCF and mixed, each fading
// out toward its map's border ("fetch from every cascade and mix them", the option the chapter
// chose). Going from the finest out, a cascade only contributes the share its finer ones left,
// so the fetches stop once a cascade covers the point fully. Define NO_SHADOWS to compile out.
#ifndef SHADOW_CSM_GLSL
#define SHADOW_CSM_GLSL

#define CASCADES 3
uniform sampler2DShadow u_shadow_map0, u_shadow_map1, u_shadow_map2;
uniform mat4 u_shadow_matrix[CASCADES];  // world -> shadow-map texture space [0, 1]^3
uniform float u_shadow_bias[CASCADES];   // depth bias per cascade, texture-depth units

float pcf(sampler2DShadow map, vec3 coord, float bias) {
    vec2 texel = 1.0 / vec2(textureSize(map, 0));
    float sum = 0.0;
    for (int y = -1; y <= 1; y++)
        for (int x = -1; x <= 1; x++)
            sum += texture(map, vec3(coord.xy + vec2(x, y) * texel, coord.z - bias));
    return sum / 9.0;
}

// Separate samplers, not an array: an array of shadow samplers read behind a geometry shader
// crashed Mesa 22.3 llvmpipe.
float cascade_pcf(int i, vec3 coord) {
    if (i == 0) return pcf(u_shadow_map0, coord, u_shadow_bias[0]);
    if (i == 1) return pcf(u_shadow_map1, coord, u_shadow_bias[1]);
    return pcf(u_shadow_map2, coord, u_shadow_bias[2]);
}

// 1 = sunlit, 0 = in shadow.
float shadow_factor(vec3 world) {
#if defined NO_SHADOWS
    return 1.0;
#else
    float lit = 0.0, remaining = 1.0;  // remaining: share not yet decided by a finer cascade
    for (int i = 0; i < CASCADES && remaining > 0.0; i++) {
        vec3 coord = (u_shadow_matrix[i] * vec4(world, 1.0)).xyz;
        vec3 edge = min(coord, 1.0 - coord);
        float inside = min(min(edge.x, edge.y), edge.z);
        if (inside <= 0.0) continue;
        float weight = clamp(inside * 20.0, 0.0, 1.0) * remaining;  // fade over the outer 5% of the map
        lit += weight * cascade_pcf(i, coord);
        remaining -= weight;
    }
    return lit + remaining;  // beyond every cascade: sunlit
#endif
}

#endif
