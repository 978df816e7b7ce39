// The box tests of the cull passes (frame/cull.glsl for buildings, trees/cull.glsl for tree
// instances; frame/_gpu_culling.py holds their numpy twin): against the view's frustum planes and,
// with HIZ, against the max-depth pyramid of frame/hiz.glsl.
#ifndef FRAME_CULL_TESTS_GLSL
#define FRAME_CULL_TESTS_GLSL

uniform vec4 u_planes[6];  // inside where dot(plane.xyz, p) + plane.w >= 0
#if defined HIZ
uniform mat4 u_cull_view_proj;
uniform sampler2D u_hiz;
uniform ivec2 u_viewport;
uniform int u_hiz_top;         // the 1x1 level
uniform float u_depth_margin;  // depth units a box must lie beyond the pyramid to be hidden
#endif

bool in_frustum(vec3 lo, vec3 hi) {
    for (int i = 0; i < 6; ++i) {
        vec3 corner = mix(lo, hi, greaterThanEqual(u_planes[i].xyz, vec3(0.0)));  // farthest along the normal
        if (dot(corner, u_planes[i].xyz) + u_planes[i].w < 0.0) return false;
    }
    return true;
}

#if defined HIZ
bool hidden(vec3 lo, vec3 hi) {
    vec2 window_lo = vec2(1e30), window_hi = vec2(-1e30);
    float nearest = 1.0;
    for (int i = 0; i < 8; ++i) {
        vec3 corner = vec3((i & 1) != 0 ? hi.x : lo.x, (i & 2) != 0 ? hi.y : lo.y, (i & 4) != 0 ? hi.z : lo.z);
        vec4 clip = u_cull_view_proj * vec4(corner, 1.0);
        if (clip.w <= 0.0) return false;  // the box reaches behind the eye
        vec3 ndc = clip.xyz / clip.w;
        vec2 window = (ndc.xy * 0.5 + 0.5) * vec2(u_viewport);
        window_lo = min(window_lo, window);
        window_hi = max(window_hi, window);
        nearest = min(nearest, ndc.z * 0.5 + 0.5);
    }
    ivec2 first = clamp(ivec2(floor(window_lo)), ivec2(0), u_viewport - 1);
    ivec2 last = clamp(ivec2(floor(window_hi)), ivec2(0), u_viewport - 1);
    // the finest level where the covered pixels fall into at most 2x2 texels
    int level = 0;
    ivec2 a = first, b = last;
    while (level < u_hiz_top && any(greaterThan(b - a, ivec2(1)))) {
        ++level;
        ivec2 top = max(u_viewport >> level, ivec2(1)) - 1;  // the level's last texel (GL's mip sizes)
        a = min(first >> level, top);
        b = min(last >> level, top);
    }
    float farthest = 0.0;
    for (int y = a.y; y <= b.y; ++y) {
        for (int x = a.x; x <= b.x; ++x) farthest = max(farthest, texelFetch(u_hiz, ivec2(x, y), level).r);
    }
    return nearest > farthest + u_depth_margin;
}
#endif

#endif
