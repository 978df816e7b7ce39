"""Impostors of far trees: the layout of a species' view atlas and the numpy twin of its shading.

The atlas holds FRAMES x FRAMES views of the tree's full mesh, each an orthographic picture of
the tree's bounding sphere taken from a direction of the upper hemisphere laid out
hemi-octahedrally (frame (i, j) looks from `frame_direction((i, j))`). A far tree is one card
facing the frame nearest to the direction toward the viewer (or the sun, in the shadow pass), so
the card shows the picture exactly as it was taken; only the viewing angle's difference from the
frame's differs. Each texel holds the albedo and coverage (colour) and the normal, depth and
foliage share (surface) of the tree behind it; the card is lit per pixel from those
(shaders/trees/impostor.glsl, twin `impostor_twin` here).

Normals are stored in the view's own axes (right, up, toward the eye), and turned at draw time
into the axes of the actual direction toward the camera: the leaf cards of the mesh face the
camera, so their normals follow the eye and not the nearest frame (with model-space normals a
street view, whose nearest frames look from 8 or more degrees up, lit the leaves as if from there).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

FRAMES = 8  # views per side of the atlas
FRAME_PIXELS = 64  # texels per side of a view
BAKE_SUPERSAMPLE = 2  # each texel averages this many pixels per side of the baked picture


@dataclass(frozen=True)
class ImpostorAtlas:
    """One species' views. Rows run bottom to top (row 0 is texture coordinate v = 0)."""

    color: np.ndarray  # (H, W, 4) float16: linear albedo rgb, coverage
    surface: np.ndarray  # (H, W, 4) uint8: octahedral view-space normal rg, depth b (0 nearest), foliage share a
    centre: np.ndarray  # (3,) model-space centre of the tree's bounding sphere
    radius: float  # metres: the sphere's radius, the card's half-size at scale 1


def hemi_octahedral(direction) -> np.ndarray:
    """(..., 3) directions (y clamped to the upper hemisphere) -> (..., 2) atlas uv in [0, 1]."""
    d = np.asarray(direction, float).copy()
    d[..., 1] = np.maximum(d[..., 1], 0.0)
    d /= np.maximum(np.abs(d).sum(axis=-1, keepdims=True), 1e-9)
    return np.stack([d[..., 0] + d[..., 2], d[..., 0] - d[..., 2]], axis=-1) * 0.5 + 0.5


def hemi_octahedral_direction(uv) -> np.ndarray:
    """Inverse of `hemi_octahedral`: (..., 2) uv -> (..., 3) unit directions with y >= 0."""
    e = np.asarray(uv, float) * 2.0 - 1.0
    x, z = (e[..., 0] + e[..., 1]) * 0.5, (e[..., 0] - e[..., 1]) * 0.5
    d = np.stack([x, 1.0 - np.abs(x) - np.abs(z), z], axis=-1)
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def frame_of(direction) -> np.ndarray:
    """(..., 3) directions from the tree toward the viewer -> (..., 2) int frame (column, row)."""
    return np.clip(np.floor(hemi_octahedral(direction) * FRAMES), 0, FRAMES - 1).astype(int)


def frame_direction(frame) -> np.ndarray:
    """The direction (from the tree) a frame's view was taken from."""
    return hemi_octahedral_direction((np.asarray(frame, float) + 0.5) / FRAMES)


def frame_basis(direction) -> tuple[np.ndarray, np.ndarray]:
    """(right, up) of the card facing `direction` (unit): the picture's x and y axes."""
    d = np.asarray(direction, float)
    ref = np.array([0.0, 0.0, -1.0]) if abs(d[1]) > 0.999 else np.array([0.0, 1.0, 0.0])
    right = np.cross(ref, d)
    right /= np.linalg.norm(right)
    return right, np.cross(d, right)


def view_space_normals(normals: np.ndarray) -> np.ndarray:
    """(H, W, 3) model-space normals of the whole baked atlas -> each frame's (right, up, toward) axes."""
    p = normals.shape[0] // FRAMES
    out = np.empty_like(normals)
    for i in range(FRAMES):
        for j in range(FRAMES):
            d = frame_direction((i, j))
            axes = np.stack([*frame_basis(d), d])
            block = (slice(j * p, (j + 1) * p), slice(i * p, (i + 1) * p))  # rows are v, columns u
            out[block] = normals[block] @ axes.T
    return out


def octahedral_normal(n: np.ndarray) -> np.ndarray:
    """(..., 3) unit normals -> (..., 2) in [-1, 1] (octahedral encoding, both hemispheres)."""
    n = n / np.maximum(np.abs(n).sum(axis=-1, keepdims=True), 1e-9)
    xy = n[..., [0, 1]]
    folded = (1.0 - np.abs(xy[..., ::-1])) * np.where(xy >= 0.0, 1.0, -1.0)
    return np.where(n[..., 2:3] >= 0.0, xy, folded)


def octahedral_normal_decode(e: np.ndarray) -> np.ndarray:
    """Inverse of `octahedral_normal` (as shaders/trees/impostor.glsl decodes it)."""
    n = np.concatenate([e, (1.0 - np.abs(e[..., :1]) - np.abs(e[..., 1:]))], axis=-1)
    t = np.maximum(-n[..., 2:3], 0.0)
    n[..., :2] += np.where(n[..., :2] >= 0.0, -t, t)
    return n / np.linalg.norm(n, axis=-1, keepdims=True)


def bilinear(image: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """GL's LINEAR sampling of level 0 (texel centres at half-integers, clamped to the edge) of an
    (H, W, C) image with row 0 at v = 0; `uv` (..., 2) -> (..., C) float."""
    h, w = image.shape[:2]
    x = np.asarray(uv[..., 0], float) * w - 0.5
    y = np.asarray(uv[..., 1], float) * h - 0.5
    x0, y0 = np.floor(x), np.floor(y)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    x0, y0 = x0.astype(int), y0.astype(int)

    def at(yy, xx):
        return image[np.clip(yy, 0, h - 1), np.clip(xx, 0, w - 1)].astype(float)

    top = at(y0, x0) * (1 - fx) + at(y0, x0 + 1) * fx
    bottom = at(y0 + 1, x0) * (1 - fx) + at(y0 + 1, x0 + 1) * fx
    return top * (1 - fy) + bottom * fy


@dataclass(frozen=True)
class Light:
    """The frame block's lighting values the impostor reads (cityshade.gl.FRAME_BLOCK)."""

    sun_dir: np.ndarray
    sun_color: np.ndarray
    sky_ambient: np.ndarray
    ground_ambient: np.ndarray


def _smoothstep(e0: float, e1: float, x):
    t = np.clip((x - e0) / (e1 - e0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def shade_impostor(albedo, normal, foliage, view, dist, light: Light, specular_fade, two_sided: bool = True):
    """Colour of impostor texels (unshadowed), as shaders/trees/impostor.glsl: bark lit as
    common/lighting.glsl's lit_surface, foliage as trees/leaf_lighting.glsl's shade_leaf, mixed by
    the foliage share. albedo, normal, view (eye -> point, unit): (N, 3); foliage, dist: (N,)."""
    sun = np.asarray(light.sun_dir, float)
    ndl = normal @ sun
    ambient = light.ground_ambient + (light.sky_ambient - light.ground_ambient) * (0.5 + 0.5 * normal[:, 1:2])
    bark = albedo * (light.sun_color * np.maximum(ndl, 0.0)[:, None] + ambient)
    if two_sided:
        mu = _smoothstep(0.0, 0.9, view @ sun)[:, None]
        g = albedo[:, 1:2]
        transmitted = np.concatenate([g * 0.9, g * 1.0, g * 0.2], axis=1)
        color = albedo + (transmitted - albedo) * mu
        diffuse = np.maximum(ndl, 0.0)[:, None] * (1 - mu) + np.maximum(-ndl, 0.0)[:, None] * 1.2 * mu
        spec_scale = 1.0 - mu
    else:
        color, diffuse, spec_scale = albedo, np.maximum(ndl, 0.0)[:, None], 1.0
    h = sun - view
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    spec = np.maximum(np.sum(normal * h, axis=1, keepdims=True), 0.0) ** 12.0 * 0.25 * spec_scale
    spec = spec * (1.0 - _smoothstep(specular_fade[0], specular_fade[1], dist))[:, None]
    leaf = color * (light.sun_color * diffuse + ambient) + light.sun_color * spec
    f = np.asarray(foliage, float)[:, None]
    return bark + (leaf - bark) * f


def impostor_twin(atlas: ImpostorAtlas, place, scale: float, eye, inv_view_proj, size, light: Light, specular_fade):
    """The numpy twin of one impostor card drawn with alpha test, no shadows and fade 1: (H, W, 3)
    colour (top row first) and the (H, W) mask of pixels it covers. `place` is the instance's
    trunk base and yaw (in_place); pixels are sampled at their centres."""
    x, y, z, yaw = (float(v) for v in place)
    c, s = np.cos(yaw), np.sin(yaw)
    rotate = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])  # model -> world directions (instance.glsl)
    base = np.array([x, y, z])
    centre = base + rotate @ atlas.centre * scale
    eye = np.asarray(eye, float)
    toward = rotate.T @ (eye - centre)
    frame = frame_of(toward)
    direction = frame_direction(frame)
    right, up = (rotate @ axis for axis in frame_basis(direction))
    normal_axis = rotate @ direction
    eye_axis = (eye - centre) / np.linalg.norm(eye - centre)
    eye_axes = np.stack([*frame_basis(eye_axis), eye_axis])  # view-space normals -> world
    w, h = size
    px, py = np.meshgrid((np.arange(w) + 0.5) / w * 2 - 1, 1 - (np.arange(h) + 0.5) / h * 2)
    far = np.stack([px, py, np.ones_like(px), np.ones_like(px)], axis=-1) @ np.asarray(inv_view_proj).T
    ray = far[..., :3] / far[..., 3:] - eye
    ray /= np.linalg.norm(ray, axis=-1, keepdims=True)
    t = ((centre - eye) @ normal_axis) / (ray @ normal_axis)
    hit = eye + ray * t[..., None]
    half = atlas.radius * scale
    corner = np.stack([(hit - centre) @ right, (hit - centre) @ up], axis=-1) / half
    inside = (t > 0) & (np.abs(corner) <= 1.0).all(axis=-1)
    uv = (frame + corner * 0.5 + 0.5) / FRAMES
    texel = bilinear(atlas.color.astype(np.float32), uv)
    surface = bilinear(atlas.surface.astype(np.float32) / 255.0, uv)
    covered = inside & (texel[..., 3] >= 0.5)
    normal = octahedral_normal_decode(surface[covered][:, :2] * 2 - 1) @ eye_axes
    color = np.zeros((h, w, 3))
    color[covered] = shade_impostor(
        texel[covered][:, :3],
        normal,
        surface[covered][:, 3],
        ray[covered],
        np.linalg.norm(hit[covered] - eye, axis=1),
        light,
        specular_fade,
    )
    return color, covered


def downsample_views(color: np.ndarray, normal: np.ndarray, foliage: np.ndarray, factor: int):
    """Coverage-weighted averages of factor x factor blocks of the baked picture: color (H, W, 4)
    albedo + coverage (0 or 1), normal (H, W, 4) xyz + depth, foliage (H, W). Returns the atlas's
    (color float16, surface uint8) with the empty texels filled from their covered neighbours in
    the same frame, so filtering at the silhouette does not pull in black."""
    h, w = color.shape[0] // factor, color.shape[1] // factor

    def blocks(a):
        return a.reshape(h, factor, w, factor, -1).sum(axis=(1, 3))

    cover = color[..., 3:4]
    weight = blocks(cover)
    mean = np.concatenate([color[..., :3], normal, foliage[..., None]], axis=-1) * cover
    mean = blocks(mean) / np.maximum(weight, 1e-9)
    mean = _dilate(mean, weight[..., 0] > 0)
    n = mean[..., 3:6]
    n = n / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-9)
    n[np.linalg.norm(mean[..., 3:6], axis=-1) < 1e-9] = (0.0, 0.0, 1.0)
    out_color = np.concatenate([mean[..., :3], weight / factor**2], axis=-1).astype(np.float16)
    surface = np.concatenate([octahedral_normal(n) * 0.5 + 0.5, mean[..., 6:7], mean[..., 7:8]], axis=-1)
    return out_color, np.round(np.clip(surface, 0, 1) * 255).astype(np.uint8)


def _dilate(values: np.ndarray, covered: np.ndarray, steps: int = 4) -> np.ndarray:
    """Empty texels take the mean of their covered 3x3 neighbours within their frame, `steps` times."""
    p = FRAME_PIXELS
    v = values.reshape(FRAMES, p, FRAMES, p, -1).transpose(0, 2, 1, 3, 4).copy()
    c = covered.reshape(FRAMES, p, FRAMES, p).transpose(0, 2, 1, 3).astype(float)
    for _ in range(steps):
        vp = np.pad(v * c[..., None], ((0, 0), (0, 0), (1, 1), (1, 1), (0, 0)))
        cp = np.pad(c, ((0, 0), (0, 0), (1, 1), (1, 1)))
        total = sum(vp[:, :, i : i + p, j : j + p] for i in range(3) for j in range(3))
        count = sum(cp[:, :, i : i + p, j : j + p] for i in range(3) for j in range(3))
        grow = (c == 0) & (count > 0)
        v[grow] = (total / np.maximum(count, 1e-9)[..., None])[grow]
        c = np.where(grow, 1.0, c)
    return v.transpose(0, 2, 1, 3, 4).reshape(values.shape)
