"""Building masses: what a building is before it becomes triangles."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._face_levels import LEVEL_MASK, LEVEL_SHIFT
from ._records import FLAG_CURTAINS, FLAG_FURNITURE, FLAG_NO_INTERIOR, FLAG_ROOM_VARIATION, FLAG_SHOP_FRONT, SHAPES
from ._roofs import FLAT_ROOF, Roof
from ._uses import USE_COUNT, USE_MIXED, USE_SHIFT


@dataclass(frozen=True)
class BuildingMass:
    """A low-poly building. `footprint` is a counter-clockwise polygon (seen from above, x right,
    z toward the viewer) in building-local metres with its bounding box starting at (0, 0);
    the mass stands at `position` (world x, z of the local origin) rotated by `yaw` about +y.
    Cylinders and domes use the footprint's bounding box as their diameter.

    Buildings from maps add courtyards (`holes`, clockwise rings in the same frame), walls that
    start above the ground (`base`, with an underside, and `first_level`, the storey they start
    at: a grammar's facade.level, _face_levels.py), a `roof` on top of the walls (walls run
    up to `height - roof.height`), no walls at all (`walls=False`: a canopy), tagged tints and no
    rooms behind the glass (`interior=False`: an outbuilding's dark panes) and a `use` code."""

    shape: str
    position: tuple[float, float]
    footprint: tuple[tuple[float, float], ...]
    height: float
    yaw: float = 0.0
    floor_height: float = 3.2
    room_width: float = 4.5
    seed: int = 0
    style: int = 0
    lights: float = 1.0  # multiplies the lit share of its use at the hour (0: never lit)
    use: int = USE_MIXED  # what it is used for, a USE_* code (scene/_uses.py): decides when its rooms are lit
    shop_front: bool = False  # shops on the ground floor: those rooms are lit as a shop's, whatever the use
    wall_jitter: float = 0.25
    furniture: bool = True
    curtains: bool = True
    interior: bool = True  # False: no rooms behind the glass, only a dark pane
    holes: tuple[tuple[tuple[float, float], ...], ...] = ()
    base: float = 0.0
    first_level: int = 0
    roof: Roof = FLAT_ROOF
    walls: bool = True
    wall_colour: tuple[float, float, float] | None = None  # sRGB 0..1; None: the style's own tint
    wall_material: str | None = None
    # doors: (x, z, outward normal x, z) on the outline (scene/_doors.py); "doors" in `guessed` when placed without data
    doors: tuple[tuple[float, float, float, float], ...] = ()
    guessed: frozenset[str] = frozenset()  # map attributes the data did not give ("height", "roof_shape", ...)
    # faces as given (CityJSON): (GIVEN_* kind, ring of (x, y, z) in object space) each, drawn instead of
    # the footprint's walls and roof (scene/_given.py)
    given: tuple[tuple[int, tuple[tuple[float, float, float], ...]], ...] = ()

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise ValueError(f"unknown building shape {self.shape!r}; allowed: {', '.join(SHAPES)}")
        if self.height <= min(self.base, 0.0):  # heights over a terrain or as given may lie below sea level
            raise ValueError(f"building height must be above its base, got {self.height} over {self.base}")
        if self.use not in range(USE_COUNT):
            raise ValueError(f"unknown building use code {self.use!r}; allowed: 0..{USE_COUNT - 1} (scene/_uses.py)")
        if self.base > self.wall_top or (self.walls and self.base == self.wall_top):
            raise ValueError(f"building walls must run upward from base {self.base} to {self.wall_top}")
        if not isinstance(self.first_level, (int, np.integer)) or self.first_level not in range(LEVEL_MASK + 1):
            raise ValueError(
                f"building first level must be a whole number from 0 to {LEVEL_MASK}, got {self.first_level}"
            )

    @property
    def wall_top(self) -> float:
        return self.height - self.roof.height

    @property  # not cached: a cached array costs 200 bytes a building for the city's whole life
    def extent(self) -> np.ndarray:
        pts = np.asarray(self.footprint, dtype=np.float64)
        width, depth = pts.max(axis=0)
        height = min(self.height, width / 2) if self.shape == "dome" else self.height
        return np.array([width, height, depth])

    @property
    def room_size(self) -> np.ndarray:
        """Room size chosen so that whole rooms fill the mass: walls meet the facades' corners."""
        return room_sizes(self.extent[None], np.array([self.room_width]), np.array([self.floor_height]))[0]

    @property
    def flags(self) -> int:
        """The record's flags word: FLAG_* bits, the use code from bit USE_SHIFT and the first level
        from bit LEVEL_SHIFT."""
        return (
            (FLAG_FURNITURE if self.furniture and self.shape != "dome" else 0)
            | (FLAG_CURTAINS if self.curtains else 0)
            | (FLAG_ROOM_VARIATION if self.wall_jitter > 0 else 0)
            | (0 if self.interior else FLAG_NO_INTERIOR)
            | (FLAG_SHOP_FRONT if self.shop_front else 0)
            | self.use << USE_SHIFT
            | self.first_level << LEVEL_SHIFT
        )


def room_sizes(extent: np.ndarray, room_width: np.ndarray, floor_height: np.ndarray) -> np.ndarray:
    """Room sizes (n, 3) of masses of `extent` (n, 3) asking for rooms `room_width` wide and floors
    `floor_height` high (n,): whole rooms across each extent (at least one), the nearest count."""
    nominal = np.stack([room_width, floor_height, room_width], axis=1)
    return extent / np.maximum(1, np.round(extent / nominal))


def box(position, width, depth, height, **kwargs) -> BuildingMass:
    footprint = ((0.0, 0.0), (width, 0.0), (width, depth), (0.0, depth))
    return BuildingMass("prism", tuple(position), footprint, height, **kwargs)


def cylinder(position, diameter, height, **kwargs) -> BuildingMass:
    footprint = ((0.0, 0.0), (diameter, 0.0), (diameter, diameter), (0.0, diameter))
    return BuildingMass("cylinder", tuple(position), footprint, height, **kwargs)


def dome(position, diameter, **kwargs) -> BuildingMass:
    footprint = ((0.0, 0.0), (diameter, 0.0), (diameter, diameter), (0.0, diameter))
    return BuildingMass("dome", tuple(position), footprint, diameter / 2, **kwargs)
