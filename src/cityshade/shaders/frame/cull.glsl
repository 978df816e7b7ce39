// GPU-driven visibility of the city's buildings (render/_visibility.py, whose numpy twin makes the
// same decision): one invocation per building tests its bounding box against the view's frustum
// planes and writes the building's DrawArraysIndirectCommand (count, instanceCount 1 or 0, first,
// 0) for a multi-draw, 5 words apart (moderngl's render_indirect draws with a 20-byte stride). The commands keep the vertex buffer's order, so the drawn triangles arrive
// in the same order as in one plain draw of everything, and the picture is the same.
// Defines: COMMAND_WORDS (the command stride in words), OCCLUDERS (only the boxes that look big:
// the occluders drawn into the hierarchical depth), HIZ (also drop the boxes hidden behind the
// hierarchical depth of the occluders, frame/hiz.glsl).
#if defined COMPUTE_SHADER
layout(local_size_x = 64) in;

struct BuildingBox {
    vec4 lo;     // xyz: the box's low corner (world)
    vec4 hi;     // xyz: the high corner
    uvec4 draw;  // vertex count, first vertex
};
layout(std430, binding = 1) readonly buffer Boxes { BuildingBox boxes[]; };
layout(std430, binding = 2) writeonly buffer Commands { uint commands[]; };

uniform vec4 u_planes[6];  // inside where dot(plane.xyz, p) + plane.w >= 0
uniform uint u_box_count;
#if defined OCCLUDERS
uniform float u_occluder_size;  // half diagonal over distance from the eye
#endif
#if defined HIZ
uniform mat4 u_cull_view_proj;
uniform sampler2D u_hiz;
uniform ivec2 u_viewport;
uniform int u_hiz_top;         // the 1x1 level
uniform float u_depth_margin;  // depth units a box must lie beyond the pyramid to be hidden
#endif

bool in_frustum(vec3 lo, vec3 hi) {
    for (int i = 0; i < 6; ++i) {
        vec3 corner = mix(lo, hi, greaterThanEqual(u_planes[i].xyz, vec3(0.0)));  // farthest along the normal
        if (dot(corner, u_planes[i].xyz) + u_planes[i].w < 0.0) return false;
    }
    return true;
}

#if defined HIZ
bool hidden(vec3 lo, vec3 hi) {
    vec2 window_lo = vec2(1e30), window_hi = vec2(-1e30);
    float nearest = 1.0;
    for (int i = 0; i < 8; ++i) {
        vec3 corner = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, (i & 4) != 0 ? hi.z : lo.z);
        vec4 clip = u_cull_view_proj * vec4(corner, 1.0);
        if (clip.w <= 0.0) return false;  // the box reaches behind the eye
        vec3 ndc = clip.xyz / clip.w;
        vec2 window = (ndc.xy * 0.5 + 0.5) * vec2(u_viewport);
        window_lo = min(window_lo, window);
        window_hi = max(window_hi, window);
        nearest = min(nearest, ndc.z * 0.5 + 0.5);
    }
    ivec2 first = clamp(ivec2(floor(window_lo)), ivec2(0), u_viewport - 1);
    ivec2 last = clamp(ivec2(floor(window_hi)), ivec2(0), u_viewport - 1);
    // the finest level where the covered pixels fall into at most 2x2 texels
    int level = 0;
    ivec2 a = first, b = last;
    while (level < u_hiz_top && any(greaterThan(b - a, ivec2(1)))) {
        ++level;
        ivec2 top = max(u_viewport >> level, ivec2(1)) - 1;  // the level's last texel (GL's mip sizes)
        a = min(first >> level, top);
        b = min(last >> level, top);
    }
    float farthest = 0.0;
    for (int y = a.y; y <= b.y; ++y) {
        for (int x = a.x; x <= b.x; ++x) farthest = max(farthest, texelFetch(u_hiz, ivec2(x, y), level).r);
    }
    return nearest > farthest + u_depth_margin;
}
#endif

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_box_count) return;
    BuildingBox box = boxes[i];
    bool drawn = in_frustum(box.lo.xyz, box.hi.xyz);
#if defined OCCLUDERS
    vec3 centre = 0.5 * (box.lo.xyz + box.hi.xyz);
    drawn = drawn && 0.5 * length(box.hi.xyz - box.lo.xyz) >= u_occluder_size * distance(u_camera, centre);
#elif defined HIZ
    drawn = drawn && !hidden(box.lo.xyz, box.hi.xyz);
#endif
    commands[uint(COMMAND_WORDS) * i] = box.draw.x;
    commands[uint(COMMAND_WORDS) * i + 1u] = drawn ? 1u : 0u;
    commands[uint(COMMAND_WORDS) * i + 2u] = box.draw.y;
    commands[uint(COMMAND_WORDS) * i + 3u] = 0u;
}
#endif
