// GPU-driven visibility of the city's buildings (render/_visibility.py; frame/_gpu_culling.py's numpy twin makes the
// same decision): one invocation per building tests its bounding box against the view's frustum
// planes (frame/cull_tests.glsl) and writes the building's DrawArraysIndirectCommand (count,
// instanceCount 1 or 0, first, 0) for a multi-draw, COMMAND_WORDS apart (moderngl's render_indirect
// draws with a 20-byte stride). The boxes, and so the commands, are in vertex-buffer order, so the
// drawn triangles arrive in the same order as in one plain draw of everything, and the picture is
// the same (where two buildings meet at one depth, the later one wins either way).
// Defines: COMMAND_WORDS (the command stride in words), OCCLUDERS (only the boxes that look big:
// the occluders drawn into the hierarchical depth), HIZ (also drop the boxes hidden behind the
// hierarchical depth of the occluders, frame/hiz.glsl).
#if defined COMPUTE_SHADER
layout(local_size_x = 64) in;

layout(std430, binding = BINDING_DRAWS) readonly buffer Draws { uvec4 draws[]; };  // vertex count, first vertex, building
layout(std430, binding = BINDING_COMMANDS) writeonly buffer Commands { uint commands[]; };
// per building: its box's low and high corner (xyz, world): the buffer the buildings' vertex stage
// reads too (render/_visibility.py building_bounds)
layout(std430, binding = BINDING_BUILDING_BOUNDS) readonly buffer BuildingBounds { vec4 bounds[]; };

uniform uint u_box_count;
#if defined OCCLUDERS
uniform float u_occluder_size;  // half diagonal over distance from the eye
#endif
#include "frame/cull_tests.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_box_count) return;
    uvec4 draw = draws[i];
    vec3 lo = bounds[2u * draw.z].xyz, hi = bounds[2u * draw.z + 1u].xyz;
    bool drawn = in_frustum(lo, hi);
#if defined OCCLUDERS
    vec3 centre = 0.5 * (lo + hi);
    drawn = drawn && 0.5 * length(hi - lo) >= u_occluder_size * distance(u_camera, centre);
#elif defined HIZ
    drawn = drawn && !hidden(lo, hi);
#endif
    commands[uint(COMMAND_WORDS) * i] = draw.x;
    commands[uint(COMMAND_WORDS) * i + 1u] = drawn ? 1u : 0u;
    commands[uint(COMMAND_WORDS) * i + 2u] = draw.y;
    commands[uint(COMMAND_WORDS) * i + 3u] = 0u;
}
#endif
