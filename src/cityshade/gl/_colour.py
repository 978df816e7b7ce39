"""The one sRGB conversion (IEC 61966-2-1), in numpy; shaders/common/srgb.glsl is its GLSL twin."""

from __future__ import annotations

import numpy as np

# The piecewise curve's constants, shared with the GLSL twin through the generated include.
SRGB_DECODE_KNEE = 0.04045
SRGB_ENCODE_KNEE = 0.0031308
SRGB_SLOPE = 12.92
SRGB_OFFSET = 0.055
SRGB_GAMMA = 2.4


def srgb_to_linear(rgb: np.ndarray) -> np.ndarray:
    """sRGB-encoded values in [0, 1] -> linear light."""
    rgb = np.asarray(rgb, dtype=np.float32)
    return np.where(rgb <= SRGB_DECODE_KNEE, rgb / SRGB_SLOPE, ((rgb + SRGB_OFFSET) / (1 + SRGB_OFFSET)) ** SRGB_GAMMA)


def linear_to_srgb(rgb: np.ndarray) -> np.ndarray:
    """Linear light in [0, 1] -> sRGB-encoded values."""
    rgb = np.maximum(np.asarray(rgb, dtype=np.float32), 0.0)
    return np.where(rgb < SRGB_ENCODE_KNEE, rgb * SRGB_SLOPE, (1 + SRGB_OFFSET) * rgb ** (1 / SRGB_GAMMA) - SRGB_OFFSET)
