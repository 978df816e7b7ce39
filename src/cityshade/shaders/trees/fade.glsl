// LOD cross-fade without alpha to coverage: the reference "fizzle" (§4.6.2), a per-pixel noise
// threshold that lets a growing share of the pixels through as the fade alpha rises.
#ifndef TREES_FADE_GLSL
#define TREES_FADE_GLSL

bool fizzled(float fade) {
    float noise = fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715))));
    return noise >= fade;
}

#endif
