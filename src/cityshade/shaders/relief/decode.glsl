// Decodes every texel of a facade's maps with the codec picked by the defines (maps.glsl):
// drawn over a target the size of the map, one fragment per texel, out (D, M, A, 0).

#include "common/fullscreen.glsl"

#if defined FRAGMENT_SHADER
#include "relief/maps.glsl"
layout(location = 0) out uvec4 outMaps;
void main() {
    ivec2 cell = ivec2(gl_FragCoord.xy);
    outMaps = uvec4(relief_fetch(MAP_DEPTH, cell), relief_fetch(MAP_MATERIAL, cell), relief_fetch(MAP_BOXES, cell), 0u);
}
#endif
