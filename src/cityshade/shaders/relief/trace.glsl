// Ray casting a facade's relief in map space: x, y in texels, z in depth steps into the wall.
// TRACER_FDM: facade displacement mapping (paper §4.2), box to box through the free boxes of A.
// TRACER_RM:  Policarpo relief mapping, RM_LINEAR linear then RM_BINARY binary steps (§4.1).
// RELIEF_TILED: the map repeats without end in x and y (a window bay on a building's walls); the
// free boxes, which never leave the map, are shifted to the repeat the ray is in.
// RELIEF_REGIONS: the maps are an atlas of regions stacked in rows (the city's window bay and the
// grammar styles' window openings); the caller sets relief_region, which is traced alone, tiled or
// not, and whose free boxes are in atlas texels.
// Needs relief/maps.glsl.

#ifndef FDM_MAX_STEPS
#define FDM_MAX_STEPS 256
#endif
#ifndef RM_LINEAR
#define RM_LINEAR 20
#endif
#ifndef RM_BINARY
#define RM_BINARY 6
#endif

// Free boxes, x0 | y0 << 16 and x1 | y1 << 16 in texels (half-open).
layout(std430, binding = BINDING_RELIEF_BOXES) readonly buffer ReliefBoxes { uvec2 uBoxes[]; };

uniform ivec2 u_map_size;     // columns, rows
uniform float u_slab_depth;   // deepest texel + 1: the bottom of the traced volume

struct ReliefHit {
    bool hit;
    vec3 point;     // map space
    int face;
    uint material;
    int steps;
};

ivec2 relief_cell(vec3 p) { return ivec2(floor(p.xy)); }

#if defined RELIEF_REGIONS
ivec4 relief_region;  // the region traced: first atlas row, columns, rows, 1 if it repeats
ivec2 relief_map_size() { return relief_region.yz; }
ivec2 relief_texel(ivec2 cell) {
    ivec2 local = relief_region.w != 0 ? ivec2(mod(vec2(cell), vec2(relief_region.yz))) : cell;  // exact: small integers
    return local + ivec2(0, relief_region.x);
}
bool relief_inside(ivec2 cell) {
    return relief_region.w != 0 || (all(greaterThanEqual(cell, ivec2(0))) && all(lessThan(cell, relief_region.yz)));
}
#elif defined RELIEF_TILED
ivec2 relief_map_size() { return u_map_size; }
ivec2 relief_texel(ivec2 cell) { return ivec2(mod(vec2(cell), vec2(u_map_size))); }  // exact: small integers
bool relief_inside(ivec2 cell) { return true; }
#else
ivec2 relief_map_size() { return u_map_size; }
ivec2 relief_texel(ivec2 cell) { return cell; }
bool relief_inside(ivec2 cell) { return all(greaterThanEqual(cell, ivec2(0))) && all(lessThan(cell, u_map_size)); }
#endif

ReliefHit relief_result(bool hit, vec3 p, int face, ivec2 cell, int steps) {
    return ReliefHit(hit, p, face, hit ? relief_fetch(MAP_MATERIAL, relief_texel(cell)) : 0u, steps);
}

#if defined TRACER_FDM
// p lies on the traced volume's boundary face entry_face; each step leaves the current free box
// through the nearest of its six planes (the bottom is the current texel's depth, the top z = 0).
// The cell is tracked, not recomputed from p, where p lies on a cell boundary (after crossing a
// box side, or entering through the far side faces), so rounding cannot put it on the wrong side.
ReliefHit relief_trace(vec3 p, vec3 d, int entry_face) {
    int face = entry_face;
    const float inf = 1e30;
    ivec2 cell = relief_cell(p);
    if (entry_face == FACE_POS_X) cell.x = relief_map_size().x - 1;
    if (entry_face == FACE_POS_Y) cell.y = relief_map_size().y - 1;
    bool hit = false;
    int steps = 0;
    for (; steps < FDM_MAX_STEPS; steps++) {
        if (!relief_inside(cell)) break;
        ivec2 texel = relief_texel(cell);
        float depth = float(relief_fetch(MAP_DEPTH, texel));
        if (p.z >= depth - 1e-3) { hit = true; break; }
        uvec2 corners = uBoxes[relief_fetch(MAP_BOXES, texel)];
        vec4 box = vec4(corners.x & 0xffffu, corners.x >> 16, corners.y & 0xffffu, corners.y >> 16)
                 + vec4(cell - texel, cell - texel);  // the repeat the ray is in and the region's atlas rows
        float tx = d.x > 0.0 ? (box.z - p.x) / d.x : d.x < 0.0 ? (box.x - p.x) / d.x : inf;
        float ty = d.y > 0.0 ? (box.w - p.y) / d.y : d.y < 0.0 ? (box.y - p.y) / d.y : inf;
        float tz = d.z > 0.0 ? (depth - p.z) / d.z : d.z < 0.0 ? -p.z / d.z : inf;
        float t = min(tx, min(ty, tz));
        // Lanes llvmpipe runs for pixels outside the triangle can carry NaN rays: they must not
        // keep the loop going to its bound.
        if (!(t >= 0.0 && t < inf)) break;
        if (t == tz) {
            if (d.z <= 0.0) break;  // out through the top
            p += d * t;
            p.z = depth;  // land exactly on the plane so the depth test above is exact
            face = FACE_FRONT;
            cell = relief_cell(p);
        } else if (t == tx) {
            p += d * t;
            p.x = d.x > 0.0 ? box.z : box.x;
            face = d.x > 0.0 ? FACE_NEG_X : FACE_POS_X;
            cell = ivec2(d.x > 0.0 ? int(box.z) : int(box.x) - 1, floor(p.y));
        } else {
            p += d * t;
            p.y = d.y > 0.0 ? box.w : box.y;
            face = d.y > 0.0 ? FACE_NEG_Y : FACE_POS_Y;
            cell = ivec2(floor(p.x), d.y > 0.0 ? int(box.w) : int(box.y) - 1);
        }
    }
    return relief_result(hit, p, face, cell, steps);
}

#elif defined TRACER_RM
bool relief_below_surface(vec3 p) {
    ivec2 cell = relief_cell(p);
    ivec2 texel = relief_texel(relief_inside(ivec2(-1)) ? cell : clamp(cell, ivec2(0), relief_map_size() - 1));
    return p.z >= float(relief_fetch(MAP_DEPTH, texel));
}

// Linear search along the segment from p to the volume's bottom, then binary search between the
// last point above and the first point below the surface; the normal is always the front one.
ReliefHit relief_trace(vec3 p, vec3 d, int entry_face) {
    vec3 segment = d * ((u_slab_depth - p.z) / d.z);
    vec3 step = segment / float(RM_LINEAR);
    vec3 above = p, below = p + segment;
    for (int i = 0; i < RM_LINEAR; i++) {
        vec3 q = p + step * float(i + 1);
        if (relief_below_surface(q)) { below = q; break; }
        above = q;
    }
    for (int i = 0; i < RM_BINARY; i++) {
        vec3 mid = 0.5 * (above + below);
        if (relief_below_surface(mid)) below = mid; else above = mid;
    }
    ivec2 cell = relief_cell(below);
    return relief_result(relief_inside(cell), below, FACE_FRONT, cell, RM_LINEAR + RM_BINARY);
}
#endif
