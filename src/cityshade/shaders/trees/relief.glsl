// Relief mapping of the bark (§4.2): the bark is a layer of height u_relief_depth above the
// mesh. A view ray entering the layer's top is traced down through the height map with a
// linear search and refined with a binary search (Policarpo 2004).
#ifndef TREES_RELIEF_GLSL
#define TREES_RELIEF_GLSL

#include "trees/bark.glsl"

#define RELIEF_LINEAR_STEPS 12
#define RELIEF_BINARY_STEPS 5

uniform float u_relief_depth;  // metres
uniform float u_bark_tile;     // metres of bark per uv unit

// uv at which the view ray meets the bark; view_ts is the eye-to-surface direction in tangent
// space (z < 0 on front faces). The entry offset is clamped so grazing rays stay bounded.
vec2 relief_trace(vec2 uv, vec3 view_ts) {
    float depth = u_relief_depth / u_bark_tile;       // layer height in uv units
    vec2 slope = view_ts.xy / max(-view_ts.z, 0.2);   // uv per unit of descent
    vec2 entry = uv - slope * depth;                  // where the ray crosses the layer's top
    vec2 delta = slope * depth / float(RELIEF_LINEAR_STEPS);
    float ray = 1.0, step = 1.0 / float(RELIEF_LINEAR_STEPS);
    vec2 p = entry;
    for (int i = 0; i < RELIEF_LINEAR_STEPS; i++) {
        if (bark_height(p) >= ray) break;
        p += delta;
        ray -= step;
    }
    for (int i = 0; i < RELIEF_BINARY_STEPS; i++) {
        delta *= 0.5;
        step *= 0.5;
        if (bark_height(p) >= ray) { p -= delta; ray += step; }
        else { p += delta; ray -= step; }
    }
    return p;
}

#endif
