// The buildings' vertex stage (the batched mesh of cityshade/scene/_meshes.py), shared by every
// program that draws the city's buildings.
#if defined VERTEX_SHADER
uniform mat4 u_view_proj;
in vec3 in_position;
in vec3 in_local;
in vec3 in_normal;
in vec3 in_facade;
in ivec2 in_ids;
out vec3 v_world;  // for the shadow look-up
out vec3 v_local;
out vec3 v_normal;
out vec3 v_facade;
flat out ivec2 v_ids;
invariant gl_Position;  // the z prepass and the shading pass must produce identical depths
void main() {
    gl_Position = u_view_proj * vec4(in_position, 1.0);
    v_world = in_position;
    v_local = in_local;
    v_normal = in_normal;
    v_facade = in_facade;
    v_ids = in_ids;
}
#endif
