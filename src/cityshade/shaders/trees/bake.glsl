// What the BAKE variants of the tree programs write into an impostor's views (trees/_impostor_bake.py):
// albedo and coverage, the model-space normal and the orthographic depth, and the foliage flag.
#ifndef TREES_BAKE_GLSL
#define TREES_BAKE_GLSL

layout(location = 0) out vec4 out_albedo;   // linear albedo, 1 where the tree is
layout(location = 1) out vec4 out_normal;   // unit normal (the baked instance is the model), depth 0..1
layout(location = 2) out vec4 out_foliage;  // 1 on leaves and fronds, 0 on bark

void write_bake(vec3 albedo, vec3 normal, float foliage) {
    out_albedo = vec4(albedo, 1.0);
    out_normal = vec4(normal, gl_FragCoord.z);
    out_foliage = vec4(foliage, 0.0, 0.0, 1.0);
}

#endif
