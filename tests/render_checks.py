"""Checks every render test applies: colours are finite (a NaN clipped to 0 or 255 looks like a
dark or bright pixel, so the 8-bit picture cannot show it)."""

import numpy as np


def assert_finite(colour: np.ndarray, what: str):
    bad = ~np.isfinite(colour).all(axis=-1)
    assert not bad.any(), f"{what}: {int(bad.sum())} pixels are not finite (first at row, column {tuple(np.argwhere(bad)[0])})"


def render_finite(renderer, camera) -> np.ndarray:
    """renderer.render(camera), after checking that the frame's HDR colour is finite."""
    image = renderer.render(camera)
    assert_finite(renderer.read_hdr(), f"HDR frame of {renderer.city.city.name if renderer.city else 'no city'}")
    return image
