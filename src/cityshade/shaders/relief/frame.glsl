// Where a facade stands: per instance, the world position of its lower-left corner, the unit
// direction along it (u) and its outward normal; v is world up. Map space (texels, texels, depth
// steps into the wall) maps to world with u_map_scale = (texel, texel, depth unit) in metres.
#ifndef RELIEF_FRAME_GLSL
#define RELIEF_FRAME_GLSL

uniform vec3 u_map_scale;

struct FacadeFrame { vec3 origin; vec3 along; vec3 out_; };

vec3 facade_to_world(FacadeFrame f, vec3 map_point) {
    vec3 m = map_point * u_map_scale;
    return f.origin + f.along * m.x + vec3(0.0, m.y, 0.0) - f.out_ * m.z;
}

vec3 world_to_map(FacadeFrame f, vec3 world) {
    vec3 e = world - f.origin;
    return vec3(dot(e, f.along), e.y, -dot(e, f.out_)) / u_map_scale;
}

// A world direction in facade space (x along, y up, z out of the wall): for lighting.
vec3 world_to_facade_dir(FacadeFrame f, vec3 dir) { return vec3(dot(dir, f.along), dir.y, dot(dir, f.out_)); }

#endif
