// The leaf atlas's coverage at a pixel. Mip averaging thins needles and leaf tips away; the alpha
// is scaled back up per mip level. Shared by the shaded leaves and the id AOV's alpha test.
#ifndef TREES_LEAF_ALPHA_GLSL
#define TREES_LEAF_ALPHA_GLSL

float leaf_alpha(vec2 uv) {
    return texture(u_leaf_color, uv).a * (1.0 + 0.4 * max(textureQueryLod(u_leaf_color, uv).x, 0.0));
}

#endif
