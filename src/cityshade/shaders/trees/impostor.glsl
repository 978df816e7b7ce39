// Far trees as impostor cards (trees/_impostor_bake.py bakes the atlas; the numpy twin and the
// atlas's layout are trees/_impostor_atlas.py). One card per instance, a 4-vertex triangle strip, faces
// the atlas frame nearest to the direction toward the camera (in the shadow pass, toward the
// sun), so it shows that frame's picture as it was taken. Each pixel is lit from the texel's
// albedo, normal and foliage share: bark as lit_surface, foliage as the leaves' shade_leaf; the
// normal, stored in the frame's axes, is turned into the axes facing the camera itself (as the
// mesh's leaf cards face it); the shadow look-up goes to the texel's depth behind the card. Defines as trees/leaves.glsl:
// SHADOW_PASS, ALPHA_TO_COVERAGE (off: alpha test), TWO_SIDED, NO_SHADOWS, ID_PASS.

uniform float u_frames;           // frames per side of the atlas
uniform vec3 u_impostor_centre;   // model-space centre of the tree's bounding sphere
uniform float u_impostor_radius;  // its radius: the card's half-size at scale 1

#if defined VERTEX_SHADER
#include "trees/instance.glsl"
uniform mat4 u_view_proj;
#if defined SHADOW_PASS
uniform vec3 u_light_dir;  // toward the sun
#endif
out vec3 v_world;
out vec2 v_uv;
out float v_fade;
flat out vec3 v_depth_axis;  // world metres from the card plane at depth 0.5 to depth 0
flat out mat3 v_eye_axes;    // right, up, toward the camera: the stored normals' axes, in the world

// Inverse of hemi_octahedral_direction (trees/_impostor_atlas.py): y clamped to the upper hemisphere.
vec2 hemi_octahedral(vec3 d) {
    d.y = max(d.y, 0.0);
    d /= max(abs(d.x) + d.y + abs(d.z), 1e-9);
    return vec2(d.x + d.z, d.x - d.z) * 0.5 + 0.5;
}

vec3 hemi_octahedral_direction(vec2 uv) {
    vec2 e = uv * 2.0 - 1.0;
    float x = (e.x + e.y) * 0.5, z = (e.x - e.y) * 0.5;
    return normalize(vec3(x, 1.0 - abs(x) - abs(z), z));
}

// (right, up, d) of a card facing direction d: the picture's axes (frame_basis in trees/_impostor_atlas.py).
mat3 card_axes(vec3 d) {
    vec3 ref = abs(d.y) > 0.999 ? vec3(0.0, 0.0, -1.0) : vec3(0.0, 1.0, 0.0);
    vec3 right = normalize(cross(ref, d));
    return mat3(right, cross(d, right), d);
}

void main() {
    float c = cos(in_place.w), s = sin(in_place.w);
    vec3 centre = tree_to_world(u_impostor_centre);
#if defined SHADOW_PASS
    vec3 toward = u_light_dir;
#else
    vec3 toward = u_camera - centre;
#endif
    vec3 local = vec3(c * toward.x - s * toward.z, toward.y, s * toward.x + c * toward.z);  // world -> model
    vec2 frame = clamp(floor(hemi_octahedral(local) * u_frames), 0.0, u_frames - 1.0);
    vec3 d = hemi_octahedral_direction((frame + 0.5) / u_frames);
    mat3 axes = card_axes(d);
    vec3 right = axes[0], up = axes[1];
    vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;
    vec3 world = tree_to_world(u_impostor_centre + (right * corner.x + up * corner.y) * u_impostor_radius);
    v_world = world;
    v_uv = (frame + corner * 0.5 + 0.5) / u_frames;
    v_fade = in_params.y;
    v_depth_axis = tree_dir_to_world(d) * u_impostor_radius * in_params.x;
    v_eye_axes = card_axes(normalize(toward));
    gl_Position = u_view_proj * vec4(world, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
uniform sampler2D u_impostor_color;    // linear albedo rgb, coverage
uniform sampler2D u_impostor_surface;  // octahedral normal rg, depth b (0 nearest), foliage share a
in vec3 v_world;
in vec2 v_uv;
in float v_fade;
flat in vec3 v_depth_axis;
flat in mat3 v_eye_axes;
#include "trees/fade.glsl"

// Mip averaging thins the coverage at the silhouette, as the leaf atlas's: scaled back up per level.
float coverage(vec2 uv) {
    return texture(u_impostor_color, uv).a * (1.0 + 0.4 * max(textureQueryLod(u_impostor_color, uv).x, 0.0));
}

#if defined SHADOW_PASS
void main() {
    if (coverage(v_uv) < 0.5) discard;
}
#elif defined ID_PASS
layout(location = 0) out uvec4 out_ids;
void main() {
    if (coverage(v_uv) < 0.5 || fizzled(v_fade)) discard;
    out_ids = uvec4(uint(texture(u_impostor_surface, v_uv).a >= 0.5 ? FACE_FOLIAGE : FACE_TRUNK), 0u, 0u, 0u);
}
#else
#include "trees/leaf_lighting.glsl"
#include "shadow/csm.glsl"
layout(location = 0) out vec4 out_color;

// Inverse of octahedral_normal (trees/_impostor_atlas.py).
vec3 octahedral_normal_decode(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    float t = max(-n.z, 0.0);
    n.xy += vec2(n.x >= 0.0 ? -t : t, n.y >= 0.0 ? -t : t);
    return normalize(n);
}

void main() {
    float cover = coverage(v_uv);
#if defined ALPHA_TO_COVERAGE
    // as the leaves: the coverage edge sharpened to about a pixel, times the LOD fade
    float alpha = clamp((cover - 0.5) / max(fwidth(cover), 1e-4) + 0.5, 0.0, 1.0) * v_fade;
#else
    if (cover < 0.5 || fizzled(v_fade)) discard;
    float alpha = 1.0;
#endif
    if (alpha <= 0.0) discard;
    vec3 albedo = texture(u_impostor_color, v_uv).rgb;
    vec4 surface = texture(u_impostor_surface, v_uv);
    vec3 normal = v_eye_axes * octahedral_normal_decode(surface.rg * 2.0 - 1.0);
    vec3 view = v_world - u_camera;
    float dist = length(view);
    view /= dist;
    float shadow = shadow_factor(v_world + v_depth_axis * (1.0 - 2.0 * surface.b));
    vec3 bark = lit_surface(albedo, normal, shadow);
    vec3 leaf = shade_leaf(albedo, normal, view, shadow, dist);
    out_color = vec4(mix(bark, leaf, surface.a), alpha);
}
#endif
#endif
