// The buildings' vertex stage (the batched mesh of cityshade/scene/_meshes.py, held on the GPU as
// cityshade/scene/_face_table.py lays it out), shared by every program that draws the city's buildings.
// RELIEF_NEAR / RELIEF_FAR: the buildings pass in two draws (render/_frame.py draw_buildings), the
// buildings whose relief may be traced (relief-bay buildings, and those whose box comes within the
// switch distance of the eye) by the program that writes the relief's depth, the others by one
// that does not, so that their fragments keep the depth test before shading; each program puts the
// other's buildings outside the clip volume. The near part's shading draw is split once more:
// NEAR_GRAMMAR draws its grammar buildings, NEAR_OTHER the rest, so that each program holds only
// its own facades' code (llvmpipe runs every branch that any pixel of a group takes).
// included here, outside the stages: a file is pasted once per program, and both stages need it
#include "common/buildings.glsl"
#if defined VERTEX_SHADER
uniform mat4 u_view_proj;
in vec3 in_local;
in vec2 in_facade;  // u along the face, v up
in uint in_face_row;
// FACE_WORDS words a row, in FACE_DTYPE's order: normal, bay width and storey height, face, ids
layout(std430, binding = BINDING_BUILDING_FACES) readonly buffer BuildingFaces { uint face_words[]; };
// per building: cos and sin of its yaw, its origin's world x and z (PLACEMENT_DTYPE)
layout(std430, binding = BINDING_BUILDING_PLACEMENTS) readonly buffer BuildingPlacements { dvec4 placements[]; };
out vec3 v_world;  // for the shadow look-up
out vec3 v_local;
out vec3 v_normal;
out vec2 v_facade;  // u along the face, v up
flat out vec2 v_spacing;  // bay width, storey height: flat, so that every pixel of a face reads them alike
flat out vec4 v_face;  // the face's width, base, top, room depth (constant over a triangle)
flat out ivec4 v_ids;  // building, surface kind, room columns of the face's first and last bay
invariant gl_Position;  // the z prepass and the shading pass must produce identical depths

#if defined RELIEF_NEAR || defined RELIEF_FAR
// per building: its box's low and high corner, world (render/_visibility.py building_bounds)
layout(std430, binding = BINDING_BUILDING_BOUNDS) readonly buffer BuildingBounds { vec4 bounds[]; };
uniform float u_relief_range;  // metres: openings are traced nearer than this (relief/building.glsl)

// Whether a fragment of the building may trace a relief: a relief bay (traced at every distance), or
// a point of its box within the switch distance, with a margin over the fragment's own distance (an
// edge pixel's centre may lie a little off its triangle).
bool relief_near(int building) {
    vec3 nearest = clamp(u_camera, bounds[2 * building].xyz, bounds[2 * building + 1].xyz);
    return buildings[building].facade.x == FACADE_RELIEF || distance(u_camera, nearest) <= u_relief_range * 1.01 + 1.0;
}
#endif

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
#if defined RELIEF_NEAR || defined RELIEF_FAR
#if defined RELIEF_NEAR
    bool other = !relief_near(v_ids.x);
#else
    bool other = relief_near(v_ids.x);
#endif
#if defined NEAR_GRAMMAR
    other = other || buildings[v_ids.x].facade.x != FACADE_GRAMMAR;
#elif defined NEAR_OTHER
    other = other || buildings[v_ids.x].facade.x == FACADE_GRAMMAR;
#endif
    if (other) gl_Position = vec4(0.0, 0.0, 2.0, 1.0);  // beyond the far plane: every triangle of it clipped
#endif
    v_local = in_local;
    v_facade = in_facade;
    v_normal = uintBitsToFloat(face_row(0u).xyz);
    v_spacing = uintBitsToFloat(face_row(3u).xy);
    v_face = uintBitsToFloat(face_row(5u));
}
#endif
