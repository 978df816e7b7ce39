"""Cascaded shadow maps (§4.3.2): which cascade is redrawn on which frame with which casters, and
where each cascade's light-space box goes.

The chapter's rates: the nearest cascade every frame with every caster, the second every two
frames without fronds, the third every four frames with leaves only. Phases are staggered so
the second and third cascades never redraw on the same frame; frame 0 draws all three because
the maps start empty. Buildings are not trees: they cast into every cascade.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scene import look_at

SHADOW_CASTERS = ("buildings", "trunks", "fronds", "leaves")


@dataclass(frozen=True)
class CascadeRate:
    every: int  # redraw every this many frames
    phase: int  # on frames where frame % every == phase
    casters: frozenset[str]


PAPER_RATES = (
    CascadeRate(1, 0, frozenset(SHADOW_CASTERS)),
    CascadeRate(2, 1, frozenset({"buildings", "trunks", "leaves"})),
    CascadeRate(4, 2, frozenset({"buildings", "leaves"})),
)
EVERY_FRAME = tuple(CascadeRate(1, 0, frozenset(SHADOW_CASTERS)) for _ in range(3))


def slowed_rates(rates, factor: int) -> tuple[CascadeRate, ...]:
    """`rates` redrawn `factor` times less often. The first cascade keeps phase 0; the others move
    to the frames between its redraws (phase * factor + factor - 1), so, as in the chapter's rates,
    no frame redraws more than one of them beside it."""
    if factor == 1:
        return tuple(rates)
    return tuple(
        CascadeRate(r.every * factor, r.phase * factor + (factor - 1 if r.phase else 0), r.casters) for r in rates
    )


def cascades_due(frame: int, rates=PAPER_RATES) -> list[tuple[int, frozenset[str]]]:
    """(cascade index, casters) for each cascade redrawn on this frame."""
    return [(i, r.casters) for i, r in enumerate(rates) if frame == 0 or frame % r.every == r.phase]


def split_distances(near: float, far: float, count: int = 3, blend: float = 0.6) -> np.ndarray:
    """Cascade boundaries along the view: a blend of logarithmic and uniform splits (Zhang et al.)."""
    i = np.arange(count + 1) / count
    return blend * near * (far / near) ** i + (1 - blend) * (near + (far - near) * i)


def _ortho(half: float, near: float, far: float):
    m = np.identity(4)
    m[0, 0] = m[1, 1] = 1.0 / half
    m[2, 2] = -2.0 / (far - near)
    m[2, 3] = -(far + near) / (far - near)
    return m


def light_basis(sun_dir) -> tuple[np.ndarray, np.ndarray]:
    """Right and up axes of a view looking along -sun_dir (how leaf cards face the light)."""
    view = look_at(np.zeros(3), -np.asarray(sun_dir, float), _up_for(sun_dir))
    return view[0, :3].copy(), view[1, :3].copy()


def _up_for(sun_dir):
    return np.array([0.0, 0.0, 1.0]) if abs(sun_dir[1]) > 0.99 else np.array([0.0, 1.0, 0.0])


def cascade_view_projection(
    inv_view_proj: np.ndarray,
    near: float,
    far: float,
    z0: float,
    z1: float,
    sun_dir,
    resolution: int,
    caster_reach: float,
) -> np.ndarray:
    """Light view-projection of the view-frustum slice [z0, z1] (distances along the view).

    The slice is wrapped in a sphere, so the box does not change size as the camera turns, and its
    centre snaps to whole shadow-map texels, so shadows do not shimmer as it moves. The box reaches
    `caster_reach` metres toward the sun so tall casters outside the slice still cast into it.
    """
    corners = []
    for z in (z0, z1):
        ndc_z = (far + near) / (far - near) - 2 * far * near / ((far - near) * z)
        for x in (-1, 1):
            for y in (-1, 1):
                p = inv_view_proj @ np.array([x, y, ndc_z, 1.0])
                corners.append(p[:3] / p[3])
    corners = np.array(corners)
    centre = corners.mean(axis=0)
    radius = np.linalg.norm(corners - centre, axis=1).max()
    sun = np.asarray(sun_dir, float) / np.linalg.norm(sun_dir)
    view = look_at(np.zeros(3), -sun, _up_for(sun))
    texel = 2 * radius / resolution
    local = view[:3, :3] @ centre
    local[:2] = np.floor(local[:2] / texel) * texel
    centre = view[:3, :3].T @ local
    eye = centre + sun * (radius + caster_reach)
    light_view = look_at(eye, centre, _up_for(sun))
    return _ortho(radius, 0.0, 2 * radius + caster_reach) @ light_view


def texture_matrix(view_projection: np.ndarray) -> np.ndarray:
    """World -> shadow-map texture space [0, 1]^3 (the bias matrix times the light view-projection)."""
    bias = np.identity(4) * 0.5
    bias[3, 3] = 1.0
    bias[:3, 3] = 0.5
    return bias @ view_projection
