// Bark shading shared by the trunk mesh and the silhouette fins: colour, tangent-space normal,
// sun + sky light and the cascaded shadow.
#ifndef TREES_BARK_GLSL
#define TREES_BARK_GLSL

#include "common/lighting.glsl"
#include "shadow/csm.glsl"

uniform sampler2DArray u_bark_color;   // rgb colour, a height (1 = outermost)
uniform sampler2DArray u_bark_normal;  // tangent-space normal
uniform float u_bark_layer;

// Orthonormal (tangent, bitangent, normal) from interpolated vertex normal and tangent.
mat3 bark_frame(vec3 normal, vec3 tangent) {
    vec3 n = normalize(normal);
    vec3 t = normalize(tangent - n * dot(tangent, n));
    return mat3(t, cross(n, t), n);
}

float bark_height(vec2 uv) {
    return textureLod(u_bark_color, vec3(uv, u_bark_layer), 0.0).a;
}

vec3 bark_albedo(vec2 uv) {
    return texture(u_bark_color, vec3(uv, u_bark_layer)).rgb;
}

// The normal map's normal in the (t, b, n) frame.
vec3 bark_normal(vec2 uv, vec3 t, vec3 b, vec3 n) {
    vec3 nt = texture(u_bark_normal, vec3(uv, u_bark_layer)).xyz * 2.0 - 1.0;
    return normalize(t * nt.x + b * nt.y + n * nt.z);
}

vec3 shade_bark(vec2 uv, vec3 t, vec3 b, vec3 n, vec3 world) {
    return lit_surface(bark_albedo(uv), bark_normal(uv, t, b, n), shadow_factor(world));
}

#endif
