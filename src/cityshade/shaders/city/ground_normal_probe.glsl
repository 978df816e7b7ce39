// ground_face_normal() of each pixel of a drawn ground mesh, with the triangle it belongs to, for
// the comparison with its numpy twin (cityshade/terrain/_normals.py face_normals).
#if defined VERTEX_SHADER
uniform mat4 u_view_proj;
in vec3 in_position;
out vec3 v_world;
void main() {
    gl_Position = u_view_proj * vec4(in_position, 1.0);
    v_world = in_position;
}
#endif

#if defined FRAGMENT_SHADER
#include "city/ground_normal.glsl"
in vec3 v_world;
layout(location = 0) out vec4 out_normal;  // xyz: the normal, w: the triangle's index + 1
void main() {
    out_normal = vec4(ground_face_normal(v_world), float(gl_PrimitiveID + 1));
}
#endif
