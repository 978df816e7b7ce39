// The depth of the city's relief (included by city/building.glsl). Where a relief is traced, the
// fragment's depth is the surface the ray meets behind the wall, not the wall's plane, so what is
// drawn after it (ground, trees, SSAO from the resolved depth) meets the recessed surface.
// Relief depths are measured into the wall (relief/trace.glsl), so a traced depth is never nearer
// than the rasterised one: gl_FragDepth is declared depth_greater, which lets a GPU keep its early
// depth rejection (the test against the stored depth cannot pass later if it fails now).
// The depth prepass (and the occluders of GPU culling) write an upper bound instead, the wall
// point pushed along the ray by the deepest recess the wall may have (RELIEF_DEPTH_BOUND): the
// buildings pass, testing "<=", then passes wherever its traced depth lies, and the final depth is
// the nearest surface's traced depth whatever the drawing order.
// Everything here only where RELIEF_DEPTH is defined (the includer decides).
#if defined RELIEF_DEPTH && !defined RELIEF_DEPTH_GLSL
#define RELIEF_DEPTH_GLSL

layout(depth_greater) out float gl_FragDepth;

uniform mat4 u_view_proj;

// The window-space depth of a world point on the fragment's ray, never nearer than the fragment.
float relief_depth(vec3 world) {
    vec4 clip = u_view_proj * vec4(world, 1.0);
    return clamp(0.5 * clip.z / clip.w + 0.5, gl_FragCoord.z, 1.0);  // glDepthRange(0, 1)
}

#if defined RELIEF_DEPTH_BOUND
uniform float u_relief_range;   // metres: grammar and window-bay openings are traced nearer than this
uniform vec2 u_relief_depths;   // metres: the deepest point of the relief bay, of the openings
const float RELIEF_DEPTH_MARGIN = 16.0 / 16777216.0;  // 16 steps of a 24-bit depth buffer

// The deepest the relief of a wall may put this fragment's surface: its world point `world`, its
// object-space normal n (b's), the relief-bay buildings traced at every distance, openings nearer
// than the switch; elsewhere the rasterised depth.
float relief_depth_bound(Building b, vec3 world, vec3 n, int surface) {
    vec3 to_surface = world - u_camera;
    float s = length(to_surface);
    float range = u_relief_range * 1.001 + 0.01;  // a margin over the shading pass's rounding of s
    float deepest = surface != SURFACE_WALL ? 0.0
                  : b.facade.x == FACADE_RELIEF ? u_relief_depths.x
                  : s <= range ? u_relief_depths.y : 0.0;
    if (deepest <= 0.0) return gl_FragCoord.z;
    vec3 d = to_surface / s;
    float facing = -dot(building_rotation(b) * n, d);
    if (facing <= deepest / 1e4) return 1.0;  // grazing: the recess may reach any depth
    // the pane lies at the deepest depth: a centimetre and a few depth steps more, so that rounding
    // never puts the traced depth behind its bound
    return min(relief_depth(world + d * ((deepest + 0.01) / facing)) + RELIEF_DEPTH_MARGIN, 1.0);
}
#endif

#endif
