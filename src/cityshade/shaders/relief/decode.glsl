// Decodes every texel of a facade's maps with the codec picked by the defines (maps.glsl):
// drawn over a target the size of the map, one fragment per texel, out (D, M, A, 0).

#if defined VERTEX_SHADER
void main() {
    vec2 corner = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);  // one triangle covering the target
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
#include "relief/maps.glsl"
layout(location = 0) out uvec4 outMaps;
void main() {
    ivec2 cell = ivec2(gl_FragCoord.xy);
    outMaps = uvec4(relief_fetch(MAP_DEPTH, cell), relief_fetch(MAP_MATERIAL, cell), relief_fetch(MAP_BOXES, cell), 0u);
}
#endif
