// Relief facades drawn one instance per facade: the traced volume's faces facing the eye are
// rasterised (the front quad and the side quads), each fragment casts its ray with the tracer
// and codec picked by the defines (trace.glsl, maps.glsl) and writes colour, ids and hit point.
// Outputs: 0 colour, 1 (material + 1 or 0 on a miss, face, steps, 0), 2 hit point in map space.
// The depth stays that of the rasterised face (no gl_FragDepth), so a DEPTH_ONLY prepass of the
// same quads lets early depth testing skip the rays of hidden facades (paper §7).

#include "relief/frame.glsl"

#if defined VERTEX_SHADER
in vec3 in_position;  // map space
in int in_face;
in vec3 in_origin;    // per instance: the facade's frame
in vec3 in_along;
in vec3 in_out;
uniform mat4 u_view_proj;
out vec3 vPosition;
flat out int vFace;
flat out vec3 vEye;    // map space
flat out vec3 vOrigin;
flat out vec3 vAlong;
flat out vec3 vOut;
// A boundary face of the traced volume that faces away from the eye is never where a ray enters.
bool faces_eye(int face, vec3 eye, vec3 p) {
    if (face == FACE_NEG_X) return eye.x < p.x;
    if (face == FACE_POS_X) return eye.x > p.x;
    if (face == FACE_NEG_Y) return eye.y < p.y;
    if (face == FACE_POS_Y) return eye.y > p.y;
    return eye.z < p.z;
}

void main() {
    FacadeFrame f = FacadeFrame(in_origin, in_along, in_out);
    vPosition = in_position;
    vFace = in_face;
    vEye = world_to_map(f, u_camera);
    vOrigin = in_origin;
    vAlong = in_along;
    vOut = in_out;
    gl_Position = u_view_proj * vec4(facade_to_world(f, in_position), 1.0);
    if (!faces_eye(in_face, vEye, in_position)) gl_Position = vec4(0.0, 0.0, 2.0, 1.0);  // all corners alike: culled
}
#endif

#if defined FRAGMENT_SHADER && defined DEPTH_ONLY
void main() {}
#elif defined FRAGMENT_SHADER
#include "relief/maps.glsl"
#include "relief/trace.glsl"
#include "relief/materials.glsl"

#if defined EARLY_DEPTH
// After a DEPTH_ONLY prepass: test depth before the ray is cast even though misses discard
// (llvmpipe otherwise tests after the shader). Depth writes must be off in this pass.
layout(early_fragment_tests) in;
#endif

in vec3 vPosition;
flat in int vFace;
flat in vec3 vEye;
flat in vec3 vOrigin;
flat in vec3 vAlong;
flat in vec3 vOut;
layout(location = 0) out vec4 outColor;
layout(location = 1) out uvec4 outIds;
layout(location = 2) out vec4 outPoint;

void main() {
    FacadeFrame f = FacadeFrame(vOrigin, vAlong, vOut);
    ReliefHit h = relief_trace(vPosition, vPosition - vEye, vFace);
    if (!h.hit) discard;
    vec3 albedo = relief_albedo(h.material, h.point.xy * u_map_scale.xy, h.face);
    float light = 0.35 + 0.65 * max(dot(relief_normal(h.face), world_to_facade_dir(f, normalize(u_sun_dir))), 0.0);
    outColor = vec4(albedo * light, 1.0);
    outIds = uvec4(h.material + 1u, uint(h.face), uint(h.steps), 0u);
    outPoint = vec4(h.point, 1.0);
}
#endif
