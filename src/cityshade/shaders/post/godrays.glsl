// God rays (SpeedTree §4.5): a radial blur of the frame's bright pixels toward the sun's position
// on screen, added to the HDR colour before tone mapping. Leaves and trunks in front of the sun
// block the bright sky pixels, so the rays come out as shafts between them.
#ifndef POST_GODRAYS_GLSL
#define POST_GODRAYS_GLSL

#define GOD_RAY_SAMPLES 16

uniform vec2 u_sun_screen;      // the sun's position in texture coordinates (may be off screen)
uniform float u_god_rays;       // strength; 0 when the sun is behind the camera
uniform float u_bright;         // luminance above which a pixel feeds the rays

vec3 bright_part(vec3 c) {
    float luma = dot(c, vec3(0.2126, 0.7152, 0.0722));
    return c * (max(luma - u_bright, 0.0) / max(luma, 1e-4));
}

vec3 god_rays(sampler2D hdr, vec2 uv) {
    vec2 step = (u_sun_screen - uv) / float(GOD_RAY_SAMPLES) * 0.9;
    vec3 sum = vec3(0.0);
    float weight = 1.0;
    // Start each pixel's ray at a jittered fraction of a step, so the few taps blur instead of banding.
    vec2 p = uv + step * (fract(52.9829189 * fract(dot(gl_FragCoord.xy, vec2(0.06711056, 0.00583715)))) - 0.5);
    for (int i = 0; i < GOD_RAY_SAMPLES; i++) {
        p += step;
        if (any(lessThan(p, vec2(0.0))) || any(greaterThan(p, vec2(1.0)))) break;
        sum += bright_part(textureLod(hdr, p, 0.0).rgb) * weight;
        weight *= 0.92;  // decay along the ray
    }
    // Fade with the distance to the sun on screen so the rays stay around it.
    float falloff = 1.0 - smoothstep(0.2, 0.9, length((uv - u_sun_screen) * vec2(1.6, 1.0)));
    return sum / float(GOD_RAY_SAMPLES) * u_god_rays * falloff;
}

#endif
