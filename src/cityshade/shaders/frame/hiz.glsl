// The hierarchical depth buffer (render/_visibility.py): level 0 is the farthest depth of each
// pixel's samples, each further level the farthest of the 2x2 texels below it (3 wide or tall where
// the level below has an odd size, so the last row and column are never dropped). A box whose
// nearest depth lies beyond the level's value is hidden in every pixel the texel covers.
// Defines: FROM_DEPTH (level 0 from u_depth), MULTISAMPLED (u_depth has samples).
#if defined COMPUTE_SHADER
layout(local_size_x = 8, local_size_y = 8) in;
layout(r32f, binding = BINDING_LEVEL) writeonly uniform image2D u_level;
#if defined FROM_DEPTH
#if defined MULTISAMPLED
uniform sampler2DMS u_depth;
uniform int u_samples;
#else
uniform sampler2D u_depth;
#endif
#else
layout(r32f, binding = BINDING_FINER) readonly uniform image2D u_finer;
#endif

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(u_level);
    if (any(greaterThanEqual(texel, size))) return;
    float farthest = 0.0;
#if defined FROM_DEPTH
#if defined MULTISAMPLED
    for (int s = 0; s < u_samples; ++s) farthest = max(farthest, texelFetch(u_depth, texel, s).r);
#else
    farthest = texelFetch(u_depth, texel, 0).r;
#endif
#else
    ivec2 finer = imageSize(u_finer);
    // the last texel of a row or column also takes the odd one left over below it
    ivec2 last = 2 * texel + 1;
    if (texel.x == size.x - 1) last.x = finer.x - 1;
    if (texel.y == size.y - 1) last.y = finer.y - 1;
    for (int y = 2 * texel.y; y <= last.y; ++y) {
        for (int x = 2 * texel.x; x <= last.x; ++x) farthest = max(farthest, imageLoad(u_finer, ivec2(x, y)).r);
    }
#endif
    imageStore(u_level, texel, vec4(farthest));
}
#endif
