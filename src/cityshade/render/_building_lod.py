"""Building level of detail: where facades switch to cheaper levels, and the cheapest level's
colours (shaders/city/lod.glsl).

A level is dropped where its detail shrinks below a few pixels: the distance at which a room (one
window bay, ROOM_METRES wide) spans `pixels` rows depends only on the viewport's height and the
vertical field of view, so the switches move out on a bigger image or a narrower lens.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .. import assets
from ..grammar import BUILDING_STYLES, evaluate, library_texture

ROOM_METRES = 4.5  # a room's width on the facade: one window bay
SAMPLE_FACE = (13.5, 12.0)         # metres: the face a style's mean is taken over (3 bays, 4 storeys)
SAMPLE_STEP = 0.1                  # metres between the sample points
STYLE_SLOTS = 8                    # facade style codes the ShadingBlock has room for (grammar.BUILDING_STYLES)


def room_distance(pixels: float, rows: int, fov_y_degrees: float) -> float:
    """The distance at which a room spans `pixels` of a viewport `rows` high."""
    return ROOM_METRES * rows / (2.0 * np.tan(np.radians(fov_y_degrees) / 2.0) * pixels)


def lod_distances(pixels, rows: int, fov_y_degrees: float) -> np.ndarray:
    """(relief start, relief end, cheap start, cheap end) in metres for the ShadingBlock, from the
    pixels a room spans at each (RenderSettings.building_lod_pixels)."""
    return np.array([room_distance(p, rows, fov_y_degrees) for p in pixels])


def _linear(srgb: np.ndarray) -> np.ndarray:
    return np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)


def _wall_mean(albedo: np.ndarray, glass: np.ndarray) -> np.ndarray:
    """(mean linear albedo of the wall around the glass, glass fraction)."""
    wall = ~glass if glass.dtype == bool else 1.0 - glass
    weight = wall.astype(np.float64)
    mean = (albedo * weight[:, None]).sum(0) / max(weight.sum(), 1e-6)
    return np.array([*mean, 1.0 - weight.mean()])


@lru_cache(maxsize=1)
def bay_mean() -> np.ndarray:
    """The window bay texture's wall colour (linear, before the building's tint) and glass share."""
    image, _ = assets.facade_texture()
    pixels = image.reshape(-1, 4).astype(np.float64) / 255.0
    return _wall_mean(_linear(pixels[:, :3]), 1.0 - pixels[:, 3])


@lru_cache(maxsize=1)
def style_means() -> np.ndarray:
    """Per facade style code (the building record's ids.y), its grammar's mean wall colour (linear)
    and glass share over a sample face, evaluated with the numpy reference; zero where no style."""
    compiled, tiles = library_texture(), assets.tile_array()
    w, h = SAMPLE_FACE
    x, y = np.meshgrid(np.arange(SAMPLE_STEP / 2, w, SAMPLE_STEP), np.arange(SAMPLE_STEP / 2, h, SAMPLE_STEP))
    uv = np.stack([x.ravel(), y.ravel()], axis=1).astype(np.float32)
    means = np.zeros((STYLE_SLOTS, 4))
    for code, style in BUILDING_STYLES.items():
        result = evaluate(compiled, compiled.address(style), uv, (w, h), (0.0, 0.0), tiles, building=(4, code))
        means[code] = _wall_mean(_linear(np.asarray(result.color, np.float64)), np.asarray(result.glass))
    return means
