// Per-building records, mirrored by cityshade/scene/_records.py (BUILDING_DTYPE, std430). The
// SHAPE_* and FLAG_* codes come from the generated constants (cityshade.shader_constants).
#ifndef COMMON_BUILDINGS_GLSL
#define COMMON_BUILDINGS_GLSL

struct Building {
    vec4 origin_yaw;   // xyz: world position of the object-space origin; w: yaw (radians)
    vec4 room;         // xyz: room size in metres; w: maximum wall displacement (fraction of a room)
    vec4 extent;       // xyz: object-space size of the mass; w: light probability multiplier
    ivec4 ids;         // x: seed, y: facade style, z: flags (FLAG_* bits, the use above USE_SHIFT, the first level above LEVEL_SHIFT), w: shape
    ivec4 facade;      // x: technique (0 window bay, 1 grammar, 2 relief), y: grammar start rule, zw: grammar seed (1/8 m)
    vec4 tint;         // rgb: linear facade tint; w: 1 if tinted (a tagged colour or material), 0: the style's own
    vec4 roof;         // rgb: linear roof colour; w: roof material id (ROOF_* in city/roof.glsl)
    vec4 doors[MAX_DOORS];  // xy: a door's point on the outline (object space), zw: its wall's outward normal (0: none)
};

layout(std430, binding = BINDING_BUILDINGS) readonly buffer Buildings {
    Building buildings[];
};

// What the building is used for: a USE_* code (cityshade/scene/_uses.py).
int building_use(Building b) {
    return (b.ids.z >> USE_SHIFT) & USE_MASK;
}

// The storey its walls start at: 0 on the ground, a raised part's first level (cityshade/scene/_face_levels.py).
int building_first_level(Building b) {
    return (b.ids.z >> LEVEL_SHIFT) & LEVEL_MASK;
}

mat3 building_rotation(Building b) {
    // object -> world rotation about +y
    float c = cos(b.origin_yaw.w), s = sin(b.origin_yaw.w);
    return mat3(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c);
}

#endif
