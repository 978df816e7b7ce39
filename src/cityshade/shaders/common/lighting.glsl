// Sun + sky lighting shared by every opaque surface of the city.
#ifndef COMMON_LIGHTING_GLSL
#define COMMON_LIGHTING_GLSL

// u_sun_dir, u_sun_color, u_sky_ambient, u_ground_ambient: the frame block (cityshade.gl.FRAME_BLOCK)
uniform samplerCube u_env;    // environment (sky) radiance, HDR

vec3 ambient_light(vec3 n) {
    return mix(u_ground_ambient, u_sky_ambient, 0.5 + 0.5 * n.y);
}

// Diffuse + ambient lighting of an albedo; `shadow` is 1 where the sun is visible.
vec3 lit_surface(vec3 albedo, vec3 n, float shadow) {
    return albedo * (u_sun_color * max(dot(n, u_sun_dir), 0.0) * shadow + ambient_light(n));
}

// Schlick's Fresnel reflectance for a dielectric with normal-incidence reflectance f0.
float fresnel(float cos_theta, float f0) {
    return f0 + (1.0 - f0) * pow(1.0 - clamp(cos_theta, 0.0, 1.0), 5.0);
}

vec3 environment(vec3 dir) {
    return texture(u_env, dir).rgb;
}

#endif
