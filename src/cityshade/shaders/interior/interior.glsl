// Interior mapping (van Dongen 2008): rooms ray-cast per pixel, one room behind each window bay of
// a wall face, in that face's frame.
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
#define SALT_ROOM_DEPTH 0x7000u

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
    ivec3 cell;     // (column round the building, storey, 0)
    vec3 lo, hi;    // the room's box in its face's frame (face_frame)
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

// The wall face a pixel is on (cityshade/scene/_wall_faces.py), from the mesh's attributes.
struct WallFace {
    float width;    // metres along the face
    float base;     // where its storeys start
    float storey;   // storey height
    float bay;      // window bay width: the face holds whole bays, one room each
    float depth;    // depth of the rooms behind it
    ivec2 columns;  // room columns of its first and last bay (numbered round the building)
};

WallFace wall_face(vec2 spacing, vec4 face, ivec4 ids) {
    return WallFace(face.x, face.y, spacing.y, spacing.x, face.w, ids.zw);
}

// Object space -> the face's frame: (metres along the face as facade u grows, up, into the building).
mat3 face_frame(vec3 n) {
    vec2 across = vec2(n.x, n.z);
    vec3 out_dir = dot(across, across) > 1e-8 ? normalize(vec3(n.x, 0.0, n.z)) : vec3(0.0, 0.0, -1.0);  // a dome's top
    return transpose(mat3(vec3(-out_dir.z, 0.0, out_dir.x), vec3(0.0, 1.0, 0.0), -out_dir));
}

// A room's light: its hash against the share of its use at this hour (a shop on a shop-front ground
// floor, else the building's use), times the building's own multiplier.
bool room_lit(ivec3 cell, Building b) {
    int use = cell.y == 0 && (b.ids.z & FLAG_SHOP_FRONT) != 0 ? USE_SHOP : building_use(b);
    return unit_float(hash3(cell, uint(b.ids.x) ^ SALT_LIGHT)) < u_lit_share[use] * b.extent.w;
}

// The room behind a window: `window` is the glass's rectangle in facade coordinates (u0, v0, u1,
// v1; a point for the window-bay facade), whose centre picks the bay and the storey, so the whole
// window opens onto one room. The room's box (face frame) spans its bay and storey and holds the
// window; rooms between the face's ends vary in depth (paper §4.3) by up to `jitter` of it.
Room find_room(vec4 window, WallFace f, Building b) {
    uint seed = uint(b.ids.x);
    float jitter = (b.ids.z & u_feature_mask & FLAG_ROOM_VARIATION) != 0 ? b.room.w : 0.0;
    // to 1/64 m, so that a window centred on a bay's edge (a grammar's windows often are) picks the
    // same side from every one of its pixels, whose rectangles differ by float rounding
    vec2 anchor = round(32.0 * (window.xy + window.zw)) / 64.0;
    int bays = max(1, int(round(f.width / f.bay)));
    int j = clamp(int(floor(anchor.x / f.bay)), 0, bays - 1);
    int storey = int(floor((anchor.y - f.base) / f.storey));
    Room r;
    r.cell = ivec3(j == bays - 1 ? f.columns.y : f.columns.x + j, storey, 0);
    float depth = f.depth;
    if (j > 0 && j < bays - 1) depth *= 1.0 + (unit_float(hash3(r.cell, seed ^ SALT_ROOM_DEPTH)) - 0.5) * 2.0 * jitter;
    r.lo = vec3(min(float(j) * f.bay, window.x), min(f.base + float(storey) * f.storey, window.y), 0.0);
    r.hi = vec3(max(float(j + 1) * f.bay, window.z), max(f.base + float(storey + 1) * f.storey, window.w), depth);
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

// In the face's frame (face_frame): p the facade point (u, v, metres behind the face), d the unit
// ray direction, dpdx/dpdy the screen derivatives of p; window: the glass's rectangle (find_room);
// s: distance from the camera to p.
InteriorHit interior_trace(vec3 p, vec3 d, vec4 window, WallFace f, Building b, vec3 dpdx, vec3 dpdy, float s) {
    const vec3 n = vec3(0.0, 0.0, -1.0);  // the face, seen from inside
    Room r = find_room(window, f, b);
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
