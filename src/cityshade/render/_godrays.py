"""God rays (SpeedTree §4.5): where the sun is on screen, for the radial blur in the tone-map pass
(shaders/post/godrays.glsl, enabled by the GOD_RAYS define)."""

from __future__ import annotations

import numpy as np

STRENGTH = 0.9
BRIGHT = 1.5  # HDR luminance that starts to feed the rays


def god_ray_uniforms(view_projection: np.ndarray, eye, sun_direction, sun_colour) -> dict:
    """u_sun_screen (texture coordinates of the sun's direction) and u_god_rays (0 behind the camera
    or below the horizon)."""
    p = view_projection @ np.append(np.asarray(eye, float) + np.asarray(sun_direction, float) * 1000.0, 1.0)
    visible = p[3] > 0 and sun_direction[1] > -0.02
    screen = p[:2] / p[3] * 0.5 + 0.5 if p[3] > 0 else np.array([-10.0, -10.0])
    strength = STRENGTH * min(1.0, float(np.max(sun_colour))) if visible else 0.0
    return dict(u_sun_screen=screen, u_god_rays=strength, u_bright=BRIGHT)
