// The geometry baseline: a facade's relief as instanced triangles (cityshade.relief._mesh), shaded
// with the same materials and light as the traced facades, with the same outputs as facade.glsl.

#include "relief/frame.glsl"

#if defined VERTEX_SHADER
in vec3 in_position;  // map space
in int in_face;
in int in_material;
in vec3 in_origin;    // per instance: the facade's frame
in vec3 in_along;
in vec3 in_out;
uniform mat4 u_view_proj;
out vec3 vPosition;
flat out int vFace;
flat out int vMaterial;
flat out vec3 vSun;   // facade space
void main() {
    FacadeFrame f = FacadeFrame(in_origin, in_along, in_out);
    vPosition = in_position;
    vFace = in_face;
    vMaterial = in_material;
    vSun = world_to_facade_dir(f, normalize(u_sun_dir));
    gl_Position = u_view_proj * vec4(facade_to_world(f, in_position), 1.0);
}
#endif

#if defined FRAGMENT_SHADER
#include "relief/materials.glsl"
in vec3 vPosition;
flat in int vFace;
flat in int vMaterial;
flat in vec3 vSun;
layout(location = 0) out vec4 outColor;
layout(location = 1) out uvec4 outIds;
layout(location = 2) out vec4 outPoint;
void main() {
    vec3 albedo = relief_albedo(uint(vMaterial), vPosition.xy * u_map_scale.xy, vFace);
    float light = 0.35 + 0.65 * max(dot(relief_normal(vFace), vSun), 0.0);
    outColor = vec4(albedo * light, 1.0);
    outIds = uvec4(uint(vMaterial) + 1u, uint(vFace), 0u, 0u);
    outPoint = vec4(vPosition, 1.0);
}
#endif
