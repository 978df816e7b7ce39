// The relief tile library, in the order of cityshade.relief.MATERIALS:
// wall, glass, frame, stone, wood, brick. Procedural so no texture files are needed.

vec3 relief_normal(int face) {
    if (face == FACE_NEG_X) return vec3(-1.0, 0.0, 0.0);
    if (face == FACE_POS_X) return vec3(1.0, 0.0, 0.0);
    if (face == FACE_NEG_Y) return vec3(0.0, -1.0, 0.0);
    if (face == FACE_POS_Y) return vec3(0.0, 1.0, 0.0);
    return vec3(0.0, 0.0, 1.0);  // facing out of the wall (facade space z points out)
}

// Albedo at facade point (u, v) metres on a face.
vec3 relief_albedo(uint material, vec2 uv, int face) {
    // Side faces use the coordinate running along them so patterns do not smear.
    vec2 st = face == FACE_NEG_X || face == FACE_POS_X ? vec2(uv.y, uv.y) : uv;
    if (material == 1u) return vec3(0.10, 0.14, 0.18);                       // glass
    if (material == 2u) return vec3(0.85, 0.85, 0.80);                       // frame
    if (material == 3u) return vec3(0.62, 0.58, 0.50) * (0.92 + 0.08 * fract(sin(dot(floor(st * 2.0), vec2(12.9, 78.2))) * 43758.5));  // stone
    if (material == 4u) return vec3(0.35, 0.20, 0.10) * (0.85 + 0.15 * sin(st.x * 60.0));  // wood
    if (material == 5u) {                                                    // brick, mortar lines
        vec2 b = st / vec2(0.24, 0.075);
        b.x += 0.5 * floor(b.y);
        bool mortar = fract(b.x) < 0.06 || fract(b.y) < 0.12;
        return mortar ? vec3(0.70, 0.68, 0.62) : vec3(0.55, 0.24, 0.16);
    }
    return vec3(0.78, 0.72, 0.60);                                           // wall (plaster)
}
