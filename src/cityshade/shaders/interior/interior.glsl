// Interior mapping (van Dongen 2008): rooms ray-cast per pixel in object space.
// Twin: cityshade/interior/_reference.py (same cells, faces, room ids and per-room randomness).
#ifndef INTERIOR_INTERIOR_GLSL
#define INTERIOR_INTERIOR_GLSL

#include "common/hash.glsl"
#include "common/buildings.glsl"
#include "generated/ShadingBlock.glsl"

#define SALT_LIGHT 0x1000u
#define SALT_VARIANT 0x2000u
#define SALT_FURNITURE 0x3000u
#define SALT_PHASE 0x4000u
#define SALT_CURTAIN 0x5000u
#define SALT_WALL_X 0x6000u
#define SALT_WALL_Z 0x7000u

// Depth of the furniture plane behind the facade (fraction of the room's depth) and of the curtain (metres).
#define FURNITURE_DEPTH 0.45
#define CURTAIN_DEPTH 0.08
#define SPRITE_WIDTH 0.55
#define SPRITE_HEIGHT 0.8
#define EMPTY_ROOM_SHARE 0.3
#define CURTAIN_SHARE 0.55


#ifdef IM_SINGLE_ATLAS
// Paper §3.2: every face of every variant in one texture; column = variant, row = face.
uniform sampler2D u_room_atlas;
#else
// Every face of every variant, one texture array: layer = (face - FACE_CEILING) * variants + variant.
uniform sampler2DArray u_rooms;
#endif
uniform sampler2DArray u_sprites;  // layer = kind * frames + frame
uniform sampler2D u_curtain;

struct Room {
    ivec3 cell;     // (column along x, floor, column along z)
    vec3 lo, hi;    // the room's box in object space, walls displaced (paper §4.3)
    uint id;
    bool lit;
    int variant;
};

struct InteriorHit {
    vec3 color;
    int face;
    uint room;
    float t;       // distance from the facade along the ray
    bool lit;
    int variant;
};

uint room_id(ivec3 cell) {
    return (uint(cell.x) & 0x7FFu) | ((uint(cell.z) & 0x7FFu) << 11u) | ((uint(cell.y) & 0x3FFu) << 22u);
}

// Displacement of wall line k (in rooms), constant per floor; the facades' lines stay put.
float wall_offset(int k, int floor_index, int lines, uint salt, float jitter) {
    if (k <= 0 || k >= lines) return 0.0;
    return (unit_float(hash3(ivec3(k, floor_index, 0), salt)) - 0.5) * 2.0 * jitter;
}

// The room interval containing x along one axis. Walls move less than half a room, so the
// nearest grid line and one neighbour decide it: two walls checked, constant time.
void room_interval(float x, float size, int lines, int floor_index, uint salt, float jitter,
                   out int k, out float lo, out float hi) {
    int k0 = int(floor(x / size));
    float w0 = (float(k0) + wall_offset(k0, floor_index, lines, salt, jitter)) * size;
    float w1 = (float(k0 + 1) + wall_offset(k0 + 1, floor_index, lines, salt, jitter)) * size;
    if (x < w0) {
        k = k0 - 1; hi = w0;
        lo = (float(k0 - 1) + wall_offset(k0 - 1, floor_index, lines, salt, jitter)) * size;
    } else if (x >= w1) {
        k = k0 + 1; lo = w1;
        hi = (float(k0 + 2) + wall_offset(k0 + 2, floor_index, lines, salt, jitter)) * size;
    } else {
        k = k0; lo = w0; hi = w1;
    }
}

// A room's light: its hash against the share of its use at this hour (a shop on a shop-front ground
// floor, else the building's use), times the building's own multiplier.
bool room_lit(ivec3 cell, Building b) {
    int use = cell.y == 0 && (b.ids.z & FLAG_SHOP_FRONT) != 0 ? USE_SHOP : building_use(b);
    return unit_float(hash3(cell, uint(b.ids.x) ^ SALT_LIGHT)) < u_lit_share[use] * b.extent.w;
}

Room find_room(vec3 p, vec3 n, Building b) {
    vec3 size = b.room.xyz;
    uint seed = uint(b.ids.x);
    float jitter = (b.ids.z & u_feature_mask & FLAG_ROOM_VARIATION) != 0 ? b.room.w : 0.0;
    ivec3 lines = ivec3(round(b.extent.xyz / size));
    vec3 q = p - n * (1e-3 * min(size.x, min(size.y, size.z)));   // just inside the facade
    Room r;
    r.cell.y = int(floor(q.y / size.y));
    r.lo.y = float(r.cell.y) * size.y;
    r.hi.y = r.lo.y + size.y;
    room_interval(q.x, size.x, lines.x, r.cell.y, seed ^ SALT_WALL_X, jitter, r.cell.x, r.lo.x, r.hi.x);
    room_interval(q.z, size.z, lines.z, r.cell.y, seed ^ SALT_WALL_Z, jitter, r.cell.z, r.lo.z, r.hi.z);
    r.id = room_id(r.cell);
    r.lit = room_lit(r.cell, b);
    r.variant = int(hash3(r.cell, seed ^ SALT_VARIANT) % uint(u_room_variants));
    return r;
}

#ifndef IM_SINGLE_ATLAS
int room_layer(int face, int variant) { return (face - FACE_CEILING) * u_room_variants + variant; }
#endif

vec4 room_texture(int face, vec2 uv, vec2 duvdx, vec2 duvdy, int variant) {
#ifdef IM_SINGLE_ATLAS
    // tile (column = variant, row = face - FACE_CEILING), inside its padding
    float tile = u_atlas_layout.x, pad = u_atlas_layout.y;
    vec2 atlas = u_atlas_layout.zw;
    vec2 origin = vec2(float(variant), float(face - FACE_CEILING)) * (tile + 2.0 * pad) + pad;
    vec2 st = (origin + clamp(uv, 0.0, 1.0) * tile) / atlas;
    return textureGrad(u_room_atlas, st, duvdx * tile / atlas, duvdy * tile / atlas);
#else
    return textureGrad(u_rooms, vec3(uv, float(room_layer(face, variant))), duvdx, duvdy);
#endif
}

// The mean colour of a room: the last mip level of its back wall (used by the distance LOD).
vec3 room_mean_color(Room r) {
#ifdef IM_SINGLE_ATLAS
    return room_texture(FACE_WALL_Z, vec2(0.5), vec2(1.0), vec2(1.0), r.variant).rgb;
#else
    return textureLod(u_rooms, vec3(0.5, 0.5, float(room_layer(FACE_WALL_Z, r.variant))), 16.0).rgb;
#endif
}

vec3 room_radiance(Room r) {
    return r.lit ? u_room_light : u_room_dark;
}

// p: facade point, d: unit ray direction, n: facade normal (all object space);
// dpdx/dpdy: screen derivatives of p; s: distance from the camera to p.
InteriorHit interior_trace(vec3 p, vec3 d, vec3 n, Building b, vec3 dpdx, vec3 dpdy, float s) {
    Room r = find_room(p, n, b);
    vec3 size = r.hi - r.lo;
    // ceilings, floors and walls: the far planes of the room box in the ray's direction (§2.1-2.2)
    vec3 far_planes = mix(r.lo, r.hi, step(0.0, d));
    vec3 tt = (far_planes - p) / d;
    InteriorHit hit;
    hit.room = r.id;
    hit.lit = r.lit;
    hit.variant = r.variant;
    vec2 uv;
    if (tt.y <= tt.x && tt.y <= tt.z) {
        hit.t = tt.y;
        hit.face = d.y > 0.0 ? FACE_CEILING : FACE_FLOOR;
    } else if (tt.x <= tt.z) {
        hit.t = tt.x;
        hit.face = FACE_WALL_X;
    } else {
        hit.t = tt.z;
        hit.face = FACE_WALL_Z;
    }
    vec3 rl = (p + d * hit.t - r.lo) / size;
    // Derivative-correct sampling: the footprint on the hit plane grows with (s + t) / s, and is
    // continuous across room edges, so mip selection has no seams or sparkles there.
    float grow = (s + hit.t) / s;
    vec3 dh_dx = dpdx * grow / size;
    vec3 dh_dy = dpdy * grow / size;
    vec2 gx, gy;
    if (hit.face == FACE_CEILING || hit.face == FACE_FLOOR) {
        uv = rl.xz; gx = dh_dx.xz; gy = dh_dy.xz;
    } else if (hit.face == FACE_WALL_X) {
        float flip = d.x > 0.0 ? 1.0 : -1.0;
        uv = vec2(d.x > 0.0 ? rl.z : 1.0 - rl.z, rl.y); gx = vec2(flip * dh_dx.z, dh_dx.y); gy = vec2(flip * dh_dy.z, dh_dy.y);
    } else {
        float flip = d.z > 0.0 ? -1.0 : 1.0;
        uv = vec2(d.z > 0.0 ? 1.0 - rl.x : rl.x, rl.y); gx = vec2(flip * dh_dx.x, dh_dx.y); gy = vec2(flip * dh_dy.x, dh_dy.y);
    }
    vec3 albedo = room_texture(hit.face, uv, gx, gy, r.variant).rgb;
    // a little falloff toward the back of the room so depth reads even in unlit rooms
    hit.color = albedo * room_radiance(r) * mix(1.0, 0.65, clamp(hit.t / (2.0 * max(size.x, size.z)), 0.0, 1.0));

    uint seed = uint(b.ids.x);
    float facing = max(-dot(n, d), 1e-4);
    // §2.4 furniture plane parallel to the facade, alpha-tested, animated
    if ((b.ids.z & u_feature_mask & FLAG_FURNITURE) != 0) {
        float kind_pick = unit_float(hash3(r.cell, seed ^ SALT_FURNITURE));
        float depth = FURNITURE_DEPTH * dot(abs(n), size);
        float tf = depth / facing;
        if (kind_pick >= EMPTY_ROOM_SHARE && tf < hit.t) {
            vec3 hf = p + d * tf;
            vec3 rf = (hf - r.lo) / size;
            vec3 tangent = normalize(cross(vec3(0.0, 1.0, 0.0), n));
            float u = 0.5 + dot(rf - 0.5, tangent);
            float centre = 0.3 + 0.4 * unit_float(hash3(r.cell, seed ^ SALT_PHASE));
            vec2 su = vec2((u - centre) / SPRITE_WIDTH + 0.5, rf.y / SPRITE_HEIGHT);
            if (all(greaterThanEqual(su, vec2(0.0))) && all(lessThan(su, vec2(1.0)))) {
                int kind = int((kind_pick - EMPTY_ROOM_SHARE) / (1.0 - EMPTY_ROOM_SHARE) * float(u_sprite_kinds));
                kind = min(kind, u_sprite_kinds - 1);
                int frame = int(floor(u_time * 2.0 + 7.0 * unit_float(hash3(r.cell, seed ^ SALT_PHASE ^ 1u)))) % u_sprite_frames;
                vec2 sprite_size = vec2(dot(abs(tangent), size) * SPRITE_WIDTH, size.y * SPRITE_HEIGHT);
                float grow_f = (s + tf) / s;
                vec2 sgx = vec2(dot(dpdx, tangent), dpdx.y) / sprite_size * grow_f;
                vec2 sgy = vec2(dot(dpdy, tangent), dpdy.y) / sprite_size * grow_f;
                int layer = kind * u_sprite_frames + frame;
#if defined ID_PASS
                // the exact texel decides, as in the numpy twin
                vec4 sprite = texelFetch(u_sprites, ivec3(ivec2(su * vec2(textureSize(u_sprites, 0).xy)), layer), 0);
#else
                vec4 sprite = textureGrad(u_sprites, vec3(su, float(layer)), sgx, sgy);
#endif
                if (sprite.a >= 0.5) {
                    hit.t = tf;
                    hit.face = FACE_FURNITURE;
                    hit.color = sprite.rgb * room_radiance(r);
                }
            }
        }
    }
    // curtains: a share of rooms have them drawn across the top part of the window
    if ((b.ids.z & u_feature_mask & FLAG_CURTAINS) != 0) {
        float pick = unit_float(hash3(r.cell, seed ^ SALT_CURTAIN));
        if (pick < CURTAIN_SHARE) {
            float closed = 0.15 + 0.8 * pick / CURTAIN_SHARE;
            float tc = CURTAIN_DEPTH / facing;
            vec3 hc = p + d * tc;
            float v = (hc.y - r.lo.y) / size.y;
            if (v >= u_glass_rect.w - closed * (u_glass_rect.w - u_glass_rect.y)) {
                hit.t = tc;
                hit.face = FACE_CURTAIN;
                vec2 cuv = vec2(dot(hc, cross(vec3(0.0, 1.0, 0.0), n)), hc.y) * 0.8;
                hit.color = textureGrad(u_curtain, cuv, dFdx(cuv), dFdy(cuv)).rgb * (r.lit ? u_room_light * 0.55 : u_room_dark);
            }
        }
    }
    return hit;
}

#endif
