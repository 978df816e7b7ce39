"""LOD cross-fade with alpha to coverage (§4.6.2).

Two LODs drawn on top of each other with the same alpha would get the same coverage mask, so
the fade curves are offset: the near LOD stays opaque over the first part of the band while the
far one fades in, then the near one fades out. Mid-band both are partly transparent (the
chapter notes the same).
"""

from __future__ import annotations

import numpy as np

OVERLAP = 0.35  # share of the band over which both LODs are drawn


def lod_alphas(distance, start: float, end: float, overlap: float = OVERLAP):
    """(near LOD alpha, far LOD alpha) at the given distances; the band is [start, end]. With
    `overlap` 0, one of the two is opaque at every distance: the far one fades in while the near
    one is whole, then the near one fades out (for a far level drawn behind the near one's
    gaps, as the impostor card is: trees/_impostor_atlas.py)."""
    t = np.clip((np.asarray(distance, float) - start) / (end - start), 0.0, 1.0)
    near = np.clip((1.0 - t) / (0.5 + overlap / 2), 0.0, 1.0)
    far = np.clip(t / (0.5 + overlap / 2), 0.0, 1.0)
    return near, far


def vanish_alphas(rows_spanned, start: float, end: float):
    """A tree's alpha multiplier from the rows of the image its height spans: 1 down to `start`
    rows, fading to 0 at `end` rows, so a tree shrinking below a pixel or two fades out (over as
    many frames as a walk takes to cross the band) instead of costing its whole mesh for nothing."""
    return np.clip((np.asarray(rows_spanned, float) - end) / (start - end), 0.0, 1.0)
