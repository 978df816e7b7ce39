// Relief facades on the city's buildings (included by city/building.glsl): one window bay,
// factorised with BMF, repeats across the walls (one bay wide, one floor high, so its windows sit
// in the interior-mapped rooms) and is ray-traced with facade displacement mapping.
// The record's facade field: x = FACADE_RELIEF.
#ifndef RELIEF_BUILDING_GLSL
#define RELIEF_BUILDING_GLSL

#define CODEC_BMF
#define TRACER_FDM
#define RELIEF_TILED
#include "common/buildings.glsl"
#include "common/facade.glsl"
#include "common/srgb.glsl"
#include "relief/maps.glsl"
#include "relief/trace.glsl"
#include "relief/materials.glsl"

uniform float u_relief_depth_unit;  // metres per depth step

bool has_relief_facade(Building b) { return b.facade.x == FACADE_RELIEF; }

// n: the wall's object-space normal; wall: the rasterised wall point (object space); facade: the
// mesh's (u, v above the face's base) and spacing its (bay width, storey height), in metres, so the
// bay repeats once per room; d: the unit view ray (object space). The result's point is where the
// ray meets the relief (the room behind recessed glass shows from there); no specular.
FacadeResult relief_building(Building b, vec3 n, vec3 wall, vec2 facade, vec2 spacing, vec3 d) {
    vec3 up = vec3(0.0, 1.0, 0.0);
    vec3 along = normalize(cross(n, up));  // the direction mesh u grows (right to left seen from outside)
    vec3 scale = vec3(vec2(u_map_size) / spacing, 1.0 / u_relief_depth_unit);  // map units per metre
    vec3 start = vec3(facade, 0.0) * scale;
    ReliefHit h = relief_trace(start, vec3(dot(d, along), d.y, -dot(d, n)) * scale, FACE_FRONT);
    vec3 offset = (h.point - start) / scale;
    vec3 normal = h.face == FACE_NEG_X ? -along : h.face == FACE_POS_X ? along
                : h.face == FACE_NEG_Y ? -up : h.face == FACE_POS_Y ? up : n;
    vec3 albedo = srgb_to_linear(relief_albedo(h.material, h.point.xy / scale.xy, h.face));
    return FacadeResult(albedo * building_tint(b), normal, vec2(0.0), h.hit && h.material == RELIEF_GLASS ? 1.0 : 0.0,
                        wall + along * offset.x + up * offset.y - n * offset.z, 0u);
}

#endif
