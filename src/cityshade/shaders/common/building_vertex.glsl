// The buildings' vertex stage (the batched mesh of cityshade/scene/_meshes.py), shared by every
// program that draws the city's buildings.
#if defined VERTEX_SHADER
uniform mat4 u_view_proj;
in vec3 in_position;
in vec3 in_local;
in vec3 in_normal;
in vec4 in_facade;
in vec4 in_face;
in ivec4 in_ids;
out vec3 v_world;  // for the shadow look-up
out vec3 v_local;
out vec3 v_normal;
out vec2 v_facade;  // u along the face, v up
flat out vec2 v_spacing;  // bay width, storey height: flat, so that every pixel of a face reads them alike
flat out vec4 v_face;  // the face's width, base, top, room depth (constant over a triangle)
flat out ivec4 v_ids;  // building, surface kind, room columns of the face's first and last bay
invariant gl_Position;  // the z prepass and the shading pass must produce identical depths
void main() {
    gl_Position = u_view_proj * vec4(in_position, 1.0);
    v_world = in_position;
    v_local = in_local;
    v_normal = in_normal;
    v_facade = in_facade.xy;
    v_spacing = in_facade.zw;
    v_face = in_face;
    v_ids = in_ids;
}
#endif
