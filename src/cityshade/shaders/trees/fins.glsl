// Silhouette fins (§4.2.1-4.2.3, §4.6.3). The vertex shader computes N.V per vertex; the
// geometry shader finds where it changes sign along the triangle's edges and emits a fin of
// two triangles there, extruded along the (view-perpendicular) normal by the bark relief height,
// which falls to zero across a distance band. The fragment shader height-traces the bark along
// the view ray and discards the fin where the ray misses; near misses fade out through alpha to
// coverage, measured against the per-pixel change of the fin's height coordinate. ID_PASS: the id
// AOV's FACE_TRUNK where the alpha-tested fin is kept.

#if defined VERTEX_SHADER
#include "trees/instance.glsl"
#include "trees/branch_inputs.glsl"
out vec3 vs_world;
out vec3 vs_normal;
out vec3 vs_tangent;
out vec2 vs_uv;
out float vs_radius;
out float vs_facing;  // N.V
void main() {
    vec3 world = tree_to_world(in_position);
    world += wind_offset(world, in_wind);
    vs_world = world;
    vs_normal = normalize(tree_dir_to_world(in_normal));
    vs_tangent = tree_dir_to_world(in_tangent);
    vs_uv = in_uv;
    vs_radius = in_radius * in_params.x;
    vs_facing = dot(vs_normal, normalize(u_camera - world));
}
#endif

#if defined GEOMETRY_SHADER
layout(triangles) in;
layout(triangle_strip, max_vertices = 4) out;
uniform mat4 u_view_proj;
uniform float u_relief_depth;  // fin width near the camera, metres
uniform vec2 u_fin_fade;       // fin width falls from full to zero between these distances
in vec3 vs_world[];
in vec3 vs_normal[];
in vec3 vs_tangent[];
in vec2 vs_uv[];
in float vs_radius[];
in float vs_facing[];
out vec3 g_world;
out vec3 g_normal;
out vec3 g_tangent;
out vec2 g_uv;
out float g_radius;
out float g_width;
out float g_w;  // 0 on the silhouette, 1 on the fin's outer edge (fig. 4-19)

vec3 p[2], n[2], tg[2];
vec2 uv[2];
float rad[2];

void emit(int k, float w, float width) {
    vec3 world = p[k] + n[k] * (width * w);
    g_world = world;
    g_normal = n[k];
    g_tangent = tg[k];
    g_uv = uv[k];
    g_radius = rad[k];
    g_width = width;
    g_w = w;
    gl_Position = u_view_proj * vec4(world, 1.0);
    EmitVertex();
}

void main() {
    int count = 0;
    for (int e = 0; e < 3; e++) {
        int a = e, b = (e + 1) % 3;
        if ((vs_facing[a] > 0.0) == (vs_facing[b] > 0.0)) continue;
        if (count == 2) break;
        float t = vs_facing[a] / (vs_facing[a] - vs_facing[b]);  // where the interpolated N.V is zero
        p[count] = mix(vs_world[a], vs_world[b], t);
        n[count] = normalize(mix(vs_normal[a], vs_normal[b], t));
        tg[count] = mix(vs_tangent[a], vs_tangent[b], t);
        uv[count] = mix(vs_uv[a], vs_uv[b], t);
        rad[count] = mix(vs_radius[a], vs_radius[b], t);
        count++;
    }
    if (count < 2 || distance(p[0], p[1]) < 1e-6) return;  // no sign change, or degenerate
    float width0 = u_relief_depth * (1.0 - smoothstep(u_fin_fade.x, u_fin_fade.y, distance(p[0], u_camera)));
    float width1 = u_relief_depth * (1.0 - smoothstep(u_fin_fade.x, u_fin_fade.y, distance(p[1], u_camera)));
    if (max(width0, width1) <= 0.0) return;
    // V0, V3, V1, V2 as a strip: V2 takes V1's attributes and V3 takes V0's (§4.2.2).
    emit(0, 0.0, width0);
    emit(0, 1.0, width0);
    emit(1, 0.0, width1);
    emit(1, 1.0, width1);
    EndPrimitive();
}
#endif

#if defined FRAGMENT_SHADER
#include "trees/bark.glsl"
#define FIN_LINEAR_STEPS 16
#define FIN_BINARY_STEPS 4
uniform float u_bark_tile;
uniform float u_fin_reach;  // clamp of the traced distance along the view ray, metres
in vec3 g_world;
in vec3 g_normal;
in vec3 g_tangent;
in vec2 g_uv;
in float g_radius;
in float g_width;
in float g_w;
#if defined ID_PASS
layout(location = 0) out uvec4 out_ids;
#else
layout(location = 0) out vec4 out_color;
#endif

void main() {
    mat3 frame = bark_frame(g_normal, g_tangent);
    vec3 t = frame[0], b = frame[1], n = frame[2];
    vec3 view = normalize(g_world - u_camera);
    vec2 along = vec2(dot(view, t), dot(view, b));
    along /= max(length(along), 1e-4);
    float height = g_w * g_width;  // this pixel's height above the mesh
    // The ray passes the curved surface closest here and rises s^2 / 2r either side of it; it
    // leaves the bark layer after sqrt(2 r (width - height)), clamped to u_fin_reach (fig. 4-5).
    float reach = min(sqrt(2.0 * g_radius * max(g_width - height, 0.0)), u_fin_reach);
    float ds = 2.0 * reach / float(FIN_LINEAR_STEPS);
    float s = -reach, min_miss = 1e9;
    bool hit = false;
    for (int i = 0; i <= FIN_LINEAR_STEPS; i++) {
        float miss = height + s * s / (2.0 * g_radius) - bark_height(g_uv + along * (s / u_bark_tile)) * g_width;
        min_miss = min(min_miss, miss);
        if (miss <= 0.0) { hit = true; break; }
        s += ds;
    }
    if (hit) {
        for (int i = 0; i < FIN_BINARY_STEPS; i++) {
            ds *= 0.5;
            float miss = height + s * s / (2.0 * g_radius) - bark_height(g_uv + along * (s / u_bark_tile)) * g_width;
            s += miss <= 0.0 ? -ds : ds;
        }
    }
    // Anti-aliasing (§4.6.3): opaque on a hit; otherwise fade over 1.5 pixels of height.
    float footprint = max(fwidth(g_w) * g_width, 1e-6);
    float alpha = hit ? 1.0 : 1.0 - clamp(min_miss / (1.5 * footprint), 0.0, 1.0);
#if !defined ALPHA_TO_COVERAGE
    alpha = alpha >= 0.5 ? 1.0 : 0.0;
#endif
    if (alpha <= 0.0) discard;
#if defined ID_PASS
    out_ids = uvec4(uint(FACE_TRUNK), 0u, 0u, 0u);
#else
    vec2 uv = g_uv + along * (s / u_bark_tile);
    out_color = vec4(shade_bark(uv, t, b, n, g_world), alpha);
#endif
}
#endif
