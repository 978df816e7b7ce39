// The ground of cities from maps (materials 3 and up; ids in cityshade/maps/_ground.py): water
// that reflects the sky with Fresnel and small ripples, paint, rails, ballast, land, sand, lamp
// posts and bulbs; and the haze that blends the land plane into the sky at the horizon.
#ifndef CITY_MAP_GROUND_GLSL
#define CITY_MAP_GROUND_GLSL


#include "city/street_lights.glsl"


const vec2 HAZE_RANGE = vec2(1500.0, 25000.0);  // metres: the ground fades into the horizon's colour
const float BULB_RADIANCE = 30.0;

vec3 map_albedo(int material, vec3 world, float noise) {
    if (material == GROUND_MARKING) return vec3(0.62, 0.62, 0.6) * (0.9 + 0.1 * noise);
    if (material == GROUND_RAIL) return vec3(0.32, 0.3, 0.29);
    if (material == GROUND_BALLAST) return vec3(0.25, 0.23, 0.21) * (0.75 + 0.5 * noise);
    if (material == GROUND_PLATFORM) return vec3(0.5, 0.49, 0.46) * (0.92 + 0.16 * noise);  // concrete slabs
    if (material == GROUND_SAND) return vec3(0.52, 0.47, 0.36) * (0.9 + 0.2 * noise);
    if (material == GROUND_TERRAIN) return vec3(0.19, 0.21, 0.11) * (0.8 + 0.4 * noise);  // a DEM's open ground
    if (material == GROUND_POST || material == GROUND_BULB) return vec3(0.09, 0.09, 0.1);
    return vec3(0.13, 0.14, 0.11) * (0.85 + 0.3 * noise);  // land: worn paving, soil and weeds
}

// Flat shading for the few upright faces (lamp posts) of the ground mesh.
vec3 map_normal(int material, vec3 world) {
    if (material != GROUND_POST && material != GROUND_BULB) return vec3(0.0, 1.0, 0.0);
    vec3 n = normalize(cross(dFdx(world), dFdy(world)));
    return dot(n, u_camera - world) < 0.0 ? -n : n;
}

vec3 map_emission(int material) {
    return material == GROUND_BULB ? LAMP_COLOR * BULB_RADIANCE * u_street_lights : vec3(0.0);
}

// The colour of the light water scatters back from below its surface (a northern harbour's
// blue-green), lit by the sky and the sun: water seen from above is dark, never black.
const vec3 WATER_BODY = vec3(0.045, 0.085, 0.1);

// Ripples: a few travelling sine waves; their slopes tilt the normal by a few degrees. A wave finer
// than about two pixels (`footprint`: metres a pixel spans on the water) fades out before it aliases
// into stripes and moire that crawl in motion.
vec3 water_normal(vec2 p, float footprint) {
    vec2 slope = vec2(0.0);
    const vec2 dirs[4] = vec2[](vec2(0.8, 0.6), vec2(-0.5, 0.86), vec2(0.2, -0.98), vec2(-0.95, -0.3));
    const float freqs[4] = float[](0.9, 1.7, 2.9, 4.3);
    for (int i = 0; i < 4; ++i) {
        float phase = dot(dirs[i], p) * freqs[i] + u_time * (1.2 + 0.4 * float(i));
        float resolved = 1.0 - smoothstep(0.25, 1.0, freqs[i] * footprint / 3.14159265);
        slope += dirs[i] * cos(phase) * 0.035 / (1.0 + float(i)) * resolved;
    }
    return normalize(vec3(-slope.x, 1.0, -slope.y));
}

vec3 water_surface(vec3 world, float shadow) {
    vec3 n = water_normal(world.xz, length(fwidth(world.xz)));
    vec3 to_eye = normalize(u_camera - world);
    vec3 r = reflect(-to_eye, n);
    r.y = abs(r.y);  // ripples never reflect the ground below the horizon
    float f = fresnel(dot(n, to_eye), 0.02);
    vec3 body = WATER_BODY * (u_sky_ambient + u_sun_color * max(u_sun_dir.y, 0.0) * 0.3);
    vec3 glint = u_sun_color * pow(max(dot(r, u_sun_dir), 0.0), 400.0) * 40.0 * shadow;
    return mix(body, environment(r), f) + glint * f;
}

vec3 ground_haze(vec3 color, vec3 world) {
    vec3 d = world - u_camera;
    float fade = smoothstep(HAZE_RANGE.x, HAZE_RANGE.y, length(d.xz));
    return mix(color, environment(normalize(vec3(d.x, 0.0, d.z))), fade);
}

#endif
