// Tree instances culled on the GPU (trees/_tree_pass.py; the numpy twin is frame/_gpu_culling.py's box
// test): one invocation per instance of one species at one LOD tests the box around its trunk base
// (the model's height times the instance's scale, plus the wind's sway, every way; as
// TreePass.instance_boxes) and writes, for each of the bucket's three meshes (trunks, leaves,
// fronds), a DrawElementsIndirectCommand (index count, instanceCount 1 or 0, first index 0, base
// vertex 0, base instance = the instance) at commands[mesh * instance count + instance]. One
// instance per command, in instance order, draws what one instanced draw of all of them draws, in
// the same order. Defines: COMMAND_WORDS, HIZ (as frame/cull.glsl).
#if defined COMPUTE_SHADER
layout(local_size_x = 64) in;

struct TreeInstance {
    vec4 place;   // trunk base xyz, yaw
    vec4 params;  // scale, LOD alpha, wind phase, unused
};
layout(std430, binding = BINDING_INSTANCES) readonly buffer Instances { TreeInstance instances[]; };
layout(std430, binding = BINDING_COMMANDS) writeonly buffer Commands { uint commands[]; };

uniform uint u_instance_count;
uniform float u_tree_height;  // the species' model height (metres at scale 1)
uniform float u_sway;         // the wind's reach beyond it
uniform uvec3 u_index_counts; // trunks, leaves, fronds
#include "frame/cull_tests.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= u_instance_count) return;
    TreeInstance tree = instances[i];
    float reach = u_tree_height * tree.params.x + u_sway;
    vec3 lo = tree.place.xyz - vec3(reach), hi = tree.place.xyz + vec3(reach);
    bool drawn = in_frustum(lo, hi);
#if defined HIZ
    drawn = drawn && !hidden(lo, hi);
#endif
    for (uint mesh = 0u; mesh < 3u; ++mesh) {
        uint at = uint(COMMAND_WORDS) * (mesh * u_instance_count + i);
        commands[at] = u_index_counts[mesh];
        commands[at + 1u] = drawn ? 1u : 0u;
        commands[at + 2u] = 0u;
        commands[at + 3u] = 0u;
        commands[at + 4u] = i;
    }
}
#endif
