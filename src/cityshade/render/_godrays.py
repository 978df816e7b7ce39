"""God rays (SpeedTree §4.5): where the sun is on screen, and the half-resolution radial blur of
the frame's bright pixels that the tone-map pass adds (shaders/post/godrays.glsl, the GOD_RAYS
define of frame/tonemap.glsl). `god_rays_reference` is the blur's numpy twin."""

from __future__ import annotations

import moderngl
import numpy as np

from ..frame import Target
from ..gl import RenderTarget, bind_textures, draw_fullscreen, set_uniforms

STRENGTH = 0.9
BRIGHT = 1.5  # HDR luminance that starts to feed the rays
REACH = 0.9  # the rays gather light from this fraction of the way to the sun
TAPS = 8  # per blur step (GOD_RAY_TAPS)
# the blur steps' tap spacings, finest first: TAPS ** len(SPACINGS) evenly spaced taps over REACH
SPACINGS = tuple(REACH / TAPS**k for k in (3, 2, 1))
DECAY = 16 / REACH * np.log(1 / 0.92)  # a tap's weight falls by 0.92 every sixteenth of the reach


def god_ray_uniforms(view_projection: np.ndarray, eye, sun_direction, sun_colour) -> dict:
    """u_sun_screen (texture coordinates of the sun's direction) and u_god_rays (0 behind the camera
    or below the horizon)."""
    p = view_projection @ np.append(np.asarray(eye, float) + np.asarray(sun_direction, float) * 1000.0, 1.0)
    visible = p[3] > 0 and sun_direction[1] > -0.02
    screen = p[:2] / p[3] * 0.5 + 0.5 if p[3] > 0 else np.array([-10.0, -10.0])
    strength = STRENGTH * min(1.0, float(np.max(sun_colour))) if visible else 0.0
    return dict(u_sun_screen=screen, u_god_rays=strength)


def half_size(size: tuple[int, int]) -> tuple[int, int]:
    return ((size[0] + 1) // 2, (size[1] + 1) // 2)


# the blur steps' two half-resolution targets, drawn into by turns: the last (of three) is GOD_RAYS
GOD_RAY_STEPS = Target("god ray steps", divisor=2, linear=True)
GOD_RAYS = Target("god rays", divisor=2, linear=True)


def draw_god_rays(programs, hdr: moderngl.Texture, sun_screen, targets: tuple[RenderTarget, RenderTarget]):
    """The bright part of `hdr`, blurred toward the sun, into the second of `targets`."""
    bright = programs.get("post/godrays.glsl", {"BRIGHT_PASS": True})
    targets[0].use()
    bind_textures(bright, {"u_hdr": hdr})
    set_uniforms(bright, u_bright=BRIGHT)
    draw_fullscreen(bright)
    blur = programs.get("post/godrays.glsl")
    for step, spacing in enumerate(SPACINGS):
        source, target = targets[step % 2], targets[(step + 1) % 2]
        target.use()
        bind_textures(blur, {"u_rays": source.colors[0]})
        set_uniforms(blur, u_sun_screen=sun_screen, u_spacing=spacing, u_decay=DECAY)
        draw_fullscreen(blur)


def _bright_part(hdr: np.ndarray) -> np.ndarray:
    luma = hdr @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    return hdr * (np.maximum(luma - BRIGHT, 0.0) / np.maximum(luma, 1e-4))[..., None]


def _bilinear(image: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """GL's linear filtering of `image` (rows bottom first) at texture coordinates uv, clamped to the edge."""
    h, w = image.shape[:2]
    x, y = uv[..., 0] * w - 0.5, uv[..., 1] * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]

    def at(dx, dy):
        return image[np.clip(y0 + dy, 0, h - 1).astype(int), np.clip(x0 + dx, 0, w - 1).astype(int)]

    return (1 - fy) * ((1 - fx) * at(0, 0) + fx * at(1, 0)) + fy * ((1 - fx) * at(0, 1) + fx * at(1, 1))


def god_rays_reference(hdr: np.ndarray, sun_screen, strength: float) -> np.ndarray:
    """numpy twin of the god rays the tone map adds to the frame `hdr` (HxWx3 linear, top row first):
    the blur steps at half resolution, each stored as float16, then the tone map's fetch and falloff."""
    height, width = hdr.shape[:2]
    frame = hdr[::-1].astype(np.float32)  # rows bottom first, as GL's
    hw, hh = half_size((width, height))
    rows = np.minimum(np.arange(hh)[:, None] * 2 + np.array([0, 1]), height - 1)  # a 2x2 block, clamped
    cols = np.minimum(np.arange(hw)[:, None] * 2 + np.array([0, 1]), width - 1)
    bright = _bright_part(frame)[rows[:, :, None, None], cols[None, None, :, :]]  # hh, 2, hw, 2, 3
    rays = bright.mean(axis=(1, 3)).astype(np.float16)
    sun = np.asarray(sun_screen, np.float64)
    uv = np.stack(np.meshgrid((np.arange(hw) + 0.5) / hw, (np.arange(hh) + 0.5) / hh), axis=-1)
    for spacing in SPACINGS:
        step = (sun - uv) * spacing
        total = np.zeros((hh, hw, 3))
        inside = np.ones((hh, hw), bool)
        for tap in range(TAPS):
            p = uv + step * tap
            inside &= ((p >= 0.0) & (p <= 1.0)).all(axis=-1)  # a tap off screen ends the pixel's ray
            weight = np.exp(-DECAY * spacing * tap)
            total += np.where(inside[..., None], weight * _bilinear(rays.astype(np.float64), p), 0.0)
        rays = (total / TAPS).astype(np.float16)
    full = np.stack(np.meshgrid((np.arange(width) + 0.5) / width, (np.arange(height) + 0.5) / height), axis=-1)
    falloff = 1.0 - _smoothstep(0.2, 0.9, np.hypot(*((full - sun) * np.array([1.6, 1.0])).transpose(2, 0, 1)))
    added = _bilinear(rays.astype(np.float64), full) * strength * falloff[..., None]
    return added[::-1]


def _smoothstep(edge0: float, edge1: float, x: np.ndarray) -> np.ndarray:
    t = np.clip((x - edge0) / (edge1 - edge0), 0.0, 1.0)
    return t * t * (3 - 2 * t)
