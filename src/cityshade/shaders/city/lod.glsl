// Building level of detail (cityshade/render/_building_lod.py sets the bands): far facades drop
// the relief's tracing along the view ray, then grammar, relief, window bay and room ray casting
// for the facade's mean wall colour with lit windows. Each pixel is entirely one level or the other; over a
// band (u_building_lod, metres) an ordered dither shifts the share of pixels from the finer level
// to the coarser, so the switch never pops and the id AOV stays exact for the level drawn.
#ifndef CITY_LOD_GLSL
#define CITY_LOD_GLSL

#include "common/buildings.glsl"
#include "common/facade.glsl"
#include "generated/ShadingBlock.glsl"

// 4x4 Bayer matrix: 16 evenly spread thresholds per screen tile
const float LOD_BAYER[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0,
                                      3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);

// true where the pixel at distance s shows the coarser level of the band (start, end)
bool lod_coarse(vec2 band, float s) {
    ivec2 p = ivec2(gl_FragCoord.xy) & 3;
    return (s - band.x) / (band.y - band.x) > (LOD_BAYER[p.y * 4 + p.x] + 0.5) / 16.0;
}

bool lod_relief_flat(float s) { return lod_coarse(u_building_lod.xy, s); }
bool lod_cheap(float s) { return lod_coarse(u_building_lod.zw, s); }

// Per building (index), its grammar's mean wall colour (linear) and glass share: taken with the
// building's own seed and face, as the grammar's once-per-building choices set its colour
// (cityshade/render/_building_lod.py); zero for the other buildings. A grammar
// building's colour is evaluated once a view needs it (cityshade/render/_lod_colours.py): until
// then its glass share is negative and the building keeps the finer level.
layout(std430, binding = BINDING_BUILDING_LOD_COLOURS) readonly buffer BuildingLodColours { vec4 building_lod_colours[]; };

bool lod_colour_ready(int index) { return building_lod_colours[index].a >= 0.0; }

// the cheap level for a pixel at distance s of a building (index) with a grammar facade or not
bool lod_cheap_facade(float s, bool grammar, int index) { return lod_cheap(s) && (!grammar || lod_colour_ready(index)); }

// The cheapest level: the mean wall colour over the face and its glass share, the glass one window
// in each room's cell (bay_uv: the cell's uv) shaped as the window bay's glass and centred where
// it is, behind which the room glows in its mean colour (city/building.glsl): a lit room a lit
// window, as at the full level, not a dimmer glow over its whole cell. grammar: the building
// (index) has a grammar facade (its own mean, untinted as the grammar is); relief: the relief
// bay's mean; else the window bay's (both tinted as their textures are).
FacadeResult lod_facade(Building b, int index, vec3 n, vec3 wall, vec2 bay_uv, bool grammar, bool relief) {
    vec4 bay = relief ? u_relief_mean : u_bay_mean;
    vec4 mean = grammar ? building_lod_colours[index] : vec4(bay.rgb * building_tint(b), bay.a);
    vec2 pane = u_glass_rect.zw - u_glass_rect.xy;
    vec2 window = pane * sqrt(mean.a / (pane.x * pane.y));  // the pane's shape, the glass share's area
    window = window.x > 1.0 ? vec2(1.0, mean.a) : window.y > 1.0 ? vec2(mean.a, 1.0) : window;
    vec2 centre = clamp(0.5 * (u_glass_rect.xy + u_glass_rect.zw), 0.5 * window, 1.0 - 0.5 * window);
    // the share of the pixel's footprint on the glass, each axis apart: no crawl as the camera moves
    vec2 inside = clamp((0.5 * window - abs(fract(bay_uv) - centre)) / max(fwidth(bay_uv), 1e-4) + 0.5, 0.0, 1.0);
    float glass = inside.x * inside.y;
    return FacadeResult(mean.rgb, n, vec2(0.0), glass, wall, 0u);
}

#endif
