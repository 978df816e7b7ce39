// Vertex inputs of the branch mesh (cityshade.trees BRANCH_ATTRIBUTES), shared by trunks and fins.
#ifndef TREES_BRANCH_INPUTS_GLSL
#define TREES_BRANCH_INPUTS_GLSL
in vec3 in_position;
in vec3 in_normal;
in vec3 in_tangent;
in vec2 in_uv;
in float in_radius;
in float in_wind;
#endif
