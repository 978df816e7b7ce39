// One relief facade on its own: the traced volume's faces facing the eye are rasterised (the front
// quad and the side quads), each fragment casts its ray with the tracer and codec picked by the
// defines (see trace.glsl and maps.glsl) and writes colour, ids and the hit point.
// Outputs: 0 colour, 1 (material + 1 or 0 on a miss, face, steps, 0), 2 hit point in map space.

#if defined VERTEX_SHADER
in vec3 in_position;  // map space
in int in_face;
uniform mat4 uMapToClip;
out vec3 vPosition;
flat out int vFace;
void main() {
    vPosition = in_position;
    vFace = in_face;
    gl_Position = uMapToClip * vec4(in_position, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
#include "relief/maps.glsl"
#include "relief/trace.glsl"
#include "relief/materials.glsl"

in vec3 vPosition;
flat in int vFace;
uniform mat4 uMapToClip;
uniform vec3 uEye;          // map space
uniform vec3 uMapScale;     // metres per map unit (texel, texel, depth unit)
uniform vec3 uSunDir;       // facade space (x right, y up, z out of the wall), towards the sun
layout(location = 0) out vec4 outColor;
layout(location = 1) out uvec4 outIds;
layout(location = 2) out vec4 outPoint;

void main() {
    ReliefHit h = relief_trace(vPosition, vPosition - uEye, vFace);
    if (!h.hit) discard;
    vec3 n = relief_normal(h.face);
    vec3 albedo = relief_albedo(h.material, h.point.xy * uMapScale.xy, h.face);
    float light = 0.35 + 0.65 * max(dot(n, normalize(uSunDir)), 0.0);
    outColor = vec4(albedo * light, 1.0);
    outIds = uvec4(h.material + 1u, uint(h.face), uint(h.steps), 0u);
    outPoint = vec4(h.point, 1.0);
    vec4 clip = uMapToClip * vec4(h.point, 1.0);
    gl_FragDepth = 0.5 + 0.5 * clip.z / clip.w;
}
#endif
