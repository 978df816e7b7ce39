// Doors of the city's buildings (cityshade/scene/_doors.py, whose `door_hit` is the numpy twin of
// `door_at`): up to MAX_DOORS per building, each a point on the outline with the outward normal of
// its wall (a zero normal: no door), DOOR_WIDTH wide and DOOR_HEIGHT high from the ground.
#ifndef CITY_DOORS_GLSL
#define CITY_DOORS_GLSL

#include "common/hash.glsl"
#include "common/buildings.glsl"

// Whether wall point p (object space) with outward normal n is in one of b's doors; `uv` is where
// in it (0..1 across, along the outline, and up), `index` which door.
bool door_at(Building b, vec3 p, vec3 n, out vec2 uv, out int index) {
    for (int i = 0; i < MAX_DOORS; i++) {
        vec4 door = b.doors[i];
        if (door.z == 0.0 && door.w == 0.0) continue;
        vec2 offset = p.xz - door.xy;
        float across = dot(offset, door.zw);
        float along = dot(offset, vec2(-door.w, door.z));
        if (dot(n.xz, door.zw) > DOOR_FACING && abs(across) < DOOR_PLANE && abs(along) < 0.5 * DOOR_WIDTH
                && p.y >= 0.0 && p.y < DOOR_HEIGHT) {
            uv = vec2(along / DOOR_WIDTH + 0.5, p.y / DOOR_HEIGHT);
            index = i;
            return true;
        }
    }
    return false;
}

// Painted door leaves (linear): bottle green, oxblood, navy, oiled wood, charcoal, grey.
const vec3 DOOR_PAINTS[6] = vec3[6](vec3(0.05, 0.15, 0.07), vec3(0.26, 0.04, 0.03), vec3(0.04, 0.07, 0.18),
                                    vec3(0.26, 0.12, 0.05), vec3(0.05), vec3(0.2, 0.2, 0.22));
const vec3 DOOR_FRAME = vec3(0.04);
const vec3 DOOR_GLASS = vec3(0.01, 0.012, 0.016);

// The door's albedo at `uv`: a dark frame, a leaf in one paint per door with a glazed top light and
// two raised panels, and a brass handle.
vec3 door_albedo(Building b, int index, vec2 uv) {
    if (uv.x < 0.06 || uv.x > 0.94 || uv.y > 0.97) return DOOR_FRAME;
    vec3 paint = DOOR_PAINTS[pcg_hash(uint(b.ids.x) * 8u + uint(index)) % 6u];
    if (uv.y > 0.78 && uv.y < 0.93 && uv.x > 0.14 && uv.x < 0.86) return DOOR_GLASS;
    vec2 handle = (uv - vec2(0.82, 0.45)) * vec2(DOOR_WIDTH, DOOR_HEIGHT);
    if (dot(handle, handle) < 0.0012) return vec3(0.5, 0.38, 0.12);
    float y0 = uv.y < 0.39 ? 0.08 : 0.42, y1 = uv.y < 0.39 ? 0.36 : 0.72;  // the lower or the upper panel
    bool panel = uv.x > 0.16 && uv.x < 0.84 && uv.y > y0 && uv.y < y1;
    bool edge = panel && (uv.x < 0.19 || uv.x > 0.81 || uv.y < y0 + 0.02 || uv.y > y1 - 0.02);
    return paint * (edge ? 0.6 : 1.0);
}

#endif
