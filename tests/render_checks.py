"""Checks every render test applies: colours are finite (a NaN clipped to 0 or 255 looks like a
dark or bright pixel, so the 8-bit picture cannot show it); and the edges of a twin's id picture,
the only pixels where a GPU id may differ from its twin's."""

import numpy as np


def assert_finite(colour: np.ndarray, what: str):
    bad = ~np.isfinite(colour).all(axis=-1)
    assert not bad.any(), f"{what}: {int(bad.sum())} pixels are not finite (first at row, column {tuple(np.argwhere(bad)[0])})"


def render_finite(renderer, camera) -> np.ndarray:
    """renderer.render(camera), after checking that the frame's HDR colour is finite."""
    image = renderer.render(camera)
    assert_finite(renderer.read_hdr(), f"HDR frame of {renderer.city.city.name if renderer.city else 'no city'}")
    return image


def key_edges(key: np.ndarray) -> np.ndarray:
    """Pixels whose 3x3 neighbourhood holds another value of `key` (H, W): where a ray grazes an
    edge and two tracers may pick either side. Built from one picture (the twin's) alone, so a
    false answer of the other is never excused elsewhere."""
    padded = np.pad(key, 1, mode="edge")
    h, w = key.shape
    return np.any([padded[1 + dy:1 + dy + h, 1 + dx:1 + dx + w] != key for dy in (-1, 0, 1) for dx in (-1, 0, 1)], axis=0)


def id_edges(ids: np.ndarray) -> np.ndarray:
    """key_edges of the id AOV's (face, room, building)."""
    return key_edges(ids[..., 0].astype(np.int64) << 48 ^ ids[..., 1].astype(np.int64) << 8 ^ ids[..., 2].astype(np.int64))


def hit_edges(hits) -> np.ndarray:
    """key_edges of relief hits' (material, face); a miss (material -1) is a surface of its own."""
    return key_edges(np.where(hits.material < 0, -1, hits.material * 8 + hits.face))
