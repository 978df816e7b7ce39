// The buildings' vertex stage (the batched mesh of cityshade/scene/_meshes.py, held on the GPU as
// cityshade/scene/_face_table.py lays it out), shared by every program that draws the city's buildings.
#if defined VERTEX_SHADER
uniform mat4 u_view_proj;
in vec3 in_local;
in vec2 in_facade;  // u along the face, v up
in uint in_face_row;
// FACE_WORDS words a row, in FACE_DTYPE's order: normal, bay width and storey height, face, ids
layout(std430, binding = FACES_BINDING) readonly buffer BuildingFaces { uint face_words[]; };
// per building: cos and sin of its yaw, its origin's world x and z (PLACEMENT_DTYPE)
layout(std430, binding = PLACEMENTS_BINDING) readonly buffer BuildingPlacements { dvec4 placements[]; };
out vec3 v_world;  // for the shadow look-up
out vec3 v_local;
out vec3 v_normal;
out vec2 v_facade;  // u along the face, v up
flat out vec2 v_spacing;  // bay width, storey height: flat, so that every pixel of a face reads them alike
flat out vec4 v_face;  // the face's width, base, top, room depth (constant over a triangle)
flat out ivec4 v_ids;  // building, surface kind, room columns of the face's first and last bay
invariant gl_Position;  // the z prepass and the shading pass must produce identical depths

uvec4 face_row(uint first) {
    uint w = in_face_row * FACE_WORDS + first;
    return uvec4(face_words[w], face_words[w + 1u], face_words[w + 2u], face_words[w + 3u]);
}

// scene.world_positions in float64, term by term in its order (precise: no fused multiply-add),
// rounded to float32: the very floats the mesh was made with
vec3 world_position(dvec4 placement) {
    double x = double(in_local.x), z = double(in_local.z);
    precise double along = placement.x * x + placement.y * z + placement.z;
    precise double across = placement.x * z - placement.y * x + placement.w;
    return vec3(float(along), in_local.y, float(across));
}

void main() {
    v_ids = ivec4(face_row(9u));
    v_world = world_position(placements[v_ids.x]);
    gl_Position = u_view_proj * vec4(v_world, 1.0);
    v_local = in_local;
    v_facade = in_facade;
    v_normal = uintBitsToFloat(face_row(0u).xyz);
    v_spacing = uintBitsToFloat(face_row(3u).xy);
    v_face = uintBitsToFloat(face_row(5u));
}
#endif
