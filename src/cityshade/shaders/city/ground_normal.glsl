// The normal of the ground triangle under a pixel, from the screen derivatives of its world
// position (exact for a plane), turned to face up: relief shaded without a normal per vertex.
// Numpy twin: cityshade/terrain/_normals.py face_normals.
#ifndef CITY_GROUND_NORMAL_GLSL
#define CITY_GROUND_NORMAL_GLSL

vec3 ground_face_normal(vec3 world) {
    vec3 n = normalize(cross(dFdx(world), dFdy(world)));
    return n.y < 0.0 ? -n : n;
}

#endif
