"""Facade coordinates of a dome: its surface cut into storeys up the arc, each storey a ring that is
a face of its own, and the cap above the last ring that still holds windows.

A dome's storeys are whole storeys of about the floor height along the arc from the ground to the
top (a quarter circle of the radius). Each storey is a ring: a face as wide as the circumference at
the ring's middle latitude, one storey high, with whole bays of about the room width, so a grammar
or the window bays fit whole windows into each ring in its true size. Its facade u is the longitude
times the radius of that middle circle (0 to the width), v the arc length from the ground.

The cap: a ring whose top circle is shorter than DOME_TAPER times its bottom circle would squeeze
its windows into wedges (the top ring always: it closes at the pole), so it and every ring above it
are the dome's roof, drawn as a roof, not a facade. A dome too small for any ring below its cap is
all roof. The cap is the shape of the building, not a face its grammar failed to fit: no warning.

Rooms: one per bay of each ring (a ring is one storey); room columns are numbered ring after ring,
so every room of the dome has its own column.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._wall_faces import storeys

DOME_TAPER = 2 / 3


@dataclass(frozen=True)
class DomeFaces:
    """Per ring, from the ground up: its base and top (arc length), the latitudes of both, the
    circle radius its facade u is measured on, its face width, bay width and room columns (first
    bay, last bay); `storey` the rings' height and `cap` the latitude where the roof cap begins
    (pi / 2: no cap)."""

    base: np.ndarray
    top: np.ndarray
    lat: np.ndarray  # (rings, 2): bottom, top (radians)
    circle: np.ndarray
    width: np.ndarray
    bay: np.ndarray
    columns: np.ndarray  # (rings, 2) int
    storey: float
    cap: float

    @property
    def walls(self) -> int:
        """How many rings below the cap are faces."""
        return int(np.searchsorted(self.lat[:, 0], self.cap - 1e-9, side="right"))

    def ring_of(self, arc: np.ndarray) -> np.ndarray:
        """The ring holding each arc length from the ground (the last one at the top)."""
        return np.clip(np.floor(np.asarray(arc) / self.storey).astype(np.int64), 0, len(self.base) - 1)


def dome_faces(radius: float, floor_height: float, room_width: float) -> DomeFaces:
    """The rings of a hemisphere of `radius` with storeys of about `floor_height` along its arc
    and bays of about `room_width` round each ring."""
    arc = np.pi / 2 * radius
    storey, levels = storeys(0.0, arc, floor_height)
    levels = max(levels, 1)
    base = np.arange(levels) * storey
    top = base + storey
    lat = np.stack([base, top], axis=1) / radius
    circle = radius * np.cos(lat.mean(axis=1))
    width = 2 * np.pi * circle
    bays = np.maximum(1, np.round(width / room_width)).astype(np.int64)
    first = np.cumsum(bays) - bays
    squeezed = np.cos(lat[:, 1]) < DOME_TAPER * np.cos(lat[:, 0]) - 1e-12
    squeezed[-1] = True  # the top ring closes at the pole
    cap = float(lat[np.argmax(squeezed), 0])
    return DomeFaces(
        base, top, lat, circle, width, width / bays, np.stack([first, first + bays - 1], axis=1), storey, cap
    )
