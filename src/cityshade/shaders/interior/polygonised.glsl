// The polygonised-interiors baseline (interior-mapping §3.1, fig. 9): real floors, ceilings and walls
// behind the windows (cityshade/interior/_polygonised.py). Each fragment finds its room with the
// room grid cell directly (the baseline's walls are not displaced, so no wall search), with interior
// mapping's hashes. Its grid is the building's bounding box's in object space, while interior
// mapping's rooms follow each face's windows (interior/interior.glsl), so the two pick texture
// variants and lights for different cells. Defines: DEPTH_ONLY (the rooms' z prepass), IM_SINGLE_ATLAS.

#include "common/building_vertex.glsl"

#if defined FRAGMENT_SHADER && defined DEPTH_ONLY
void main() {}
#elif defined FRAGMENT_SHADER
#include "common/hash.glsl"
#include "common/buildings.glsl"
#include "interior/interior.glsl"

in vec3 v_local;
in vec3 v_normal;    // toward the room the quad belongs to
in vec2 v_facade;
flat in vec2 v_spacing;
flat in vec4 v_face;
flat in ivec4 v_ids; // building, face code

layout(location = 0) out vec4 out_color;

// The room behind a quad: the cell of the building's regular room grid just behind it (n: the
// quad's normal, pointing into the room).
Room grid_room(vec3 p, vec3 n, Building b) {
    vec3 size = b.room.xyz;
    Room r;
    r.cell = ivec3(floor((p + n * (1e-3 * min(size.x, min(size.y, size.z)))) / size));
    r.lo = vec3(r.cell) * size;
    r.hi = r.lo + size;
    uint seed = uint(b.ids.x);
    r.id = room_id(r.cell);
    r.lit = room_lit(r.cell, b);
    r.variant = int(hash3(r.cell, seed ^ SALT_VARIANT) % uint(u_room_variants));
    return r;
}

void main() {
    Building b = buildings[v_ids.x];
    int face = v_ids.y;
    Room r = grid_room(v_local, v_normal, b);
    vec3 size = r.hi - r.lo;
    vec3 rl = (v_local - r.lo) / size;
    vec3 dx = dFdx(v_local) / size;
    vec3 dy = dFdy(v_local) / size;
    // texture coordinates as interior_trace maps them, seen from inside the room
    vec2 uv, gx, gy;
    if (face == FACE_CEILING || face == FACE_FLOOR) {
        uv = rl.xz; gx = dx.xz; gy = dy.xz;
    } else if (face == FACE_WALL_X) {
        float flip = v_normal.x < 0.0 ? 1.0 : -1.0;  // facing -x: the room's +x wall
        uv = vec2(v_normal.x < 0.0 ? rl.z : 1.0 - rl.z, rl.y); gx = vec2(flip * dx.z, dx.y); gy = vec2(flip * dy.z, dy.y);
    } else {
        float flip = v_normal.z < 0.0 ? -1.0 : 1.0;  // facing -z: the room's +z wall
        uv = vec2(v_normal.z < 0.0 ? 1.0 - rl.x : rl.x, rl.y); gx = vec2(flip * dx.x, dx.y); gy = vec2(flip * dy.x, dy.y);
    }
    out_color = vec4(room_texture(face, uv, gx, gy, r.variant).rgb * room_radiance(r), 1.0);
}
#endif
