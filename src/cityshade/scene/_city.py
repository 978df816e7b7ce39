"""Procedural city layouts: streets, blocks, lots, building masses and named viewpoints."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .._values import check_seed
from ..errors import UsageError
from ._buildings import BuildingMass, box, cylinder, dome
from ._camera import Camera
from ._layers import Layer, no_ground
from ._mass_table import MassColumns, MassTable

GROUND_ASPHALT, GROUND_PAVEMENT, GROUND_GRASS = 0, 1, 2
GROUND_MATERIALS = {"GROUND_ASPHALT": GROUND_ASPHALT, "GROUND_PAVEMENT": GROUND_PAVEMENT, "GROUND_GRASS": GROUND_GRASS}
# and those of cities from maps (shaders/city/map_ground.glsl): water, paint, tracks, land, lamps, a DEM's relief
(
    GROUND_WATER,
    GROUND_MARKING,
    GROUND_RAIL,
    GROUND_BALLAST,
    GROUND_LAND,
    GROUND_SAND,
    GROUND_POST,
    GROUND_BULB,
    GROUND_PLATFORM,
    GROUND_TERRAIN,
) = range(3, 13)
MAP_GROUND_MATERIALS = {
    "GROUND_WATER": GROUND_WATER,
    "GROUND_MARKING": GROUND_MARKING,
    "GROUND_RAIL": GROUND_RAIL,
    "GROUND_BALLAST": GROUND_BALLAST,
    "GROUND_LAND": GROUND_LAND,
    "GROUND_SAND": GROUND_SAND,
    "GROUND_POST": GROUND_POST,
    "GROUND_BULB": GROUND_BULB,
    "GROUND_PLATFORM": GROUND_PLATFORM,
    "GROUND_TERRAIN": GROUND_TERRAIN,
}
# each ground material's dataset class (dataset/_classes.py) and linear base colour in exports
GROUND_TABLE = {
    GROUND_ASPHALT: ("road", (0.05, 0.05, 0.055)),
    GROUND_PAVEMENT: ("pavement", (0.22, 0.21, 0.2)),
    GROUND_GRASS: ("grass", (0.09, 0.2, 0.05)),
    GROUND_WATER: ("water", (0.03, 0.08, 0.12)),
    GROUND_MARKING: ("lane_marking", (0.8, 0.8, 0.78)),
    GROUND_RAIL: ("rail", (0.18, 0.16, 0.14)),
    GROUND_BALLAST: ("rail", (0.14, 0.12, 0.1)),
    GROUND_LAND: ("bare_ground", (0.16, 0.15, 0.12)),
    GROUND_SAND: ("bare_ground", (0.45, 0.4, 0.3)),
    GROUND_POST: ("lamp", (0.1, 0.1, 0.1)),
    GROUND_BULB: ("lamp", (1.0, 0.85, 0.6)),
    GROUND_PLATFORM: ("pavement", (0.42, 0.41, 0.38)),
    GROUND_TERRAIN: ("terrain", (0.13, 0.15, 0.07)),
}


@dataclass
class City:
    name: str
    seed: int
    masses: MassTable  # given as any sequence of BuildingMass, kept as a MassTable
    # ground rectangles (x0, z0, x1, z1, material) drawn over an asphalt plane (the built-in cities)
    ground: list[tuple[float, float, float, float, int]]
    bounds: tuple[float, float, float, float]
    viewpoints: dict[str, Camera] = field(default_factory=dict)
    parks: list[tuple[float, float, float, float]] = field(default_factory=list)
    streets: list[tuple[float, float, float, float]] = field(default_factory=list)
    # what maps bring besides buildings (streets, water, trees, lamps, ...), in drawing order
    layers: tuple[Layer, ...] = ()
    origin: tuple[float, float] | None = None  # longitude, latitude of scene (0, 0)
    crs: str | None = None  # the projection from longitude/latitude to scene metres

    def __post_init__(self):
        if not isinstance(self.masses, MassTable):
            self.masses = MassTable(self.masses)

    def camera(self, name: str) -> Camera:
        if name not in self.viewpoints:
            raise UsageError(f"unknown camera {name!r}; allowed: {', '.join(self.viewpoints)}")
        return self.viewpoints[name]

    @property
    def ground_mesh(self) -> np.ndarray | None:
        """The layers' ground triangles one after another, or None where no layer brings any (the
        built-in cities draw `ground`'s rectangles instead)."""
        pieces = [layer.ground for layer in self.layers if len(layer.ground)]
        return np.concatenate(pieces) if pieces else None

    @property
    def lights(self) -> np.ndarray:
        """The layers' point lights one after another ((N, 4) float32)."""
        return np.concatenate([no_ground()] + [layer.lights for layer in self.layers])

    @property
    def trees(self) -> np.ndarray | None:
        """The layers' tree records, or None where no layer plants any (the built-in cities plant
        their parks and streets, trees.city_trees)."""
        planted = [layer.trees for layer in self.layers if layer.trees is not None]
        return np.concatenate(planted) if planted else None

    def with_layers(self, change) -> City:
        """This city with each layer replaced by `change(layer)`."""
        return replace(self, layers=tuple(change(layer) for layer in self.layers))

    def keep_ground(self, rows: np.ndarray) -> City:
        """This city with only the rows of `ground_mesh` that the mask `rows` keeps, each layer its own."""
        masks = np.split(rows, np.cumsum([len(layer.ground) for layer in self.layers])[:-1])
        layers = tuple(replace(layer, ground=layer.ground[mask]) for layer, mask in zip(self.layers, masks))
        return replace(self, layers=layers)


def _subdivide_block(rng, x0, z0, x1, z1, min_lot=12.0, max_lot=28.0):
    """Lots around a block's perimeter: each side cut into frontages, depth into the block."""
    lots = []
    width, depth = x1 - x0, z1 - z0
    lot_depth = min(depth / 2, rng.uniform(14, 22))
    # front (z0) and back (z1) rows span the full width; sides fill the middle
    for za, zb in ((z0, z0 + lot_depth), (z1 - lot_depth, z1)):
        x = x0
        while x < x1 - 1e-6:
            w = min(rng.uniform(min_lot, max_lot), x1 - x)
            if x1 - (x + w) < min_lot:
                w = x1 - x
            lots.append((x, za, x + w, zb))
            x += w
    middle = (z0 + lot_depth, z1 - lot_depth)
    if middle[1] - middle[0] > min_lot:
        side_w = min(width / 2, rng.uniform(14, 20))
        for xa, xb in ((x0, x0 + side_w), (x1 - side_w, x1)):
            z = middle[0]
            while z < middle[1] - 1e-6:
                d = min(rng.uniform(min_lot, max_lot), middle[1] - z)
                if middle[1] - (z + d) < min_lot:
                    d = middle[1] - z
                lots.append((xa, z, xb, z + d))
                z += d
    return lots


def _massing(rng, lot, seed, centre_distance, setback=1.0) -> BuildingMass:
    x0, z0, x1, z1 = lot
    w, d = x1 - x0 - 2 * setback, z1 - z0 - 2 * setback
    # taller toward the centre of the district
    tall = min(max(1.0 - centre_distance / 260.0, 0.15), 1.0)  # min/max: np.clip costs microseconds per scalar
    floors = int(min(max(rng.gamma(2.0, 3.0 + 8.0 * tall), 2), 45))
    floor_height = rng.choice([3.0, 3.2, 3.5])
    return box(
        (x0 + setback, z0 + setback),
        w,
        d,
        floors * floor_height,
        floor_height=floor_height,
        room_width=float(rng.uniform(3.6, 5.5)),
        seed=seed,
        style=int(rng.integers(0, 8)),
        lights=float(rng.uniform(0.6, 1.3)),
    )


def default_city(seed: int = 7, blocks: int = 6) -> City:
    """A downtown district: a grid of blocks with perimeter lots, a park, a cylinder tower and a
    domed hall beside the main street, seen at street level."""
    rng = np.random.default_rng(seed)
    pitch, street = 84.0, 16.0
    half = blocks * pitch / 2
    masses = MassColumns()  # columns as they come: 100,000 mass objects at once would fragment the heap
    ground, parks = [], []
    park_block = (blocks // 2, blocks // 2 - 2)
    special_block = (blocks // 2 - 1, blocks // 2)
    for bi in range(blocks):
        for bj in range(blocks):
            x0 = -half + bi * pitch + street / 2
            z0 = -half + bj * pitch + street / 2
            x1, z1 = x0 + pitch - street, z0 + pitch - street
            ground.append((x0 - 2.5, z0 - 2.5, x1 + 2.5, z1 + 2.5, GROUND_PAVEMENT))
            if (bi, bj) == park_block:
                ground.append((x0, z0, x1, z1, GROUND_GRASS))
                parks.append((x0, z0, x1, z1))
                continue
            cx, cz = (x0 + x1) / 2, (z0 + z1) / 2
            if (bi, bj) == special_block:
                masses.append(
                    cylinder(
                        (x0 + 4, z0 + 4),
                        26.0,
                        96.0,
                        floor_height=3.4,
                        room_width=4.5,
                        seed=int(rng.integers(1 << 30)),
                        style=1,
                    )
                )
                masses.append(
                    dome(
                        (x0 + 6, z1 - 36),
                        34.0,
                        floor_height=3.6,
                        room_width=4.0,
                        seed=int(rng.integers(1 << 30)),
                        style=6,  # dusk: a grammar facade on each storey's ring (its storeys all alike)
                    )
                )
                masses.append(box((x1 - 28, z0 + 2), 26.0, 20.0, 24.0, seed=int(rng.integers(1 << 30)), style=3))
                continue
            for lot in _subdivide_block(rng, x0, z0, x1, z1):
                masses.append(_massing(rng, lot, int(rng.integers(1 << 30)), np.hypot(cx, cz)))
    streets = [(-half, -half + k * pitch - street / 2, half, -half + k * pitch + street / 2) for k in range(blocks + 1)]
    streets += [
        (-half + k * pitch - street / 2, -half, -half + k * pitch + street / 2, half) for k in range(blocks + 1)
    ]
    main_x = -half + (blocks // 2 - 1) * pitch  # the street west of the tower and dome block
    viewpoints = {
        "street": Camera((main_x - 5.0, 1.7, 96.0), (main_x + 40.0, 24.0, 30.0), fov_y=66.0),
        "corner": Camera((main_x - 14.0, 12.0, 12.0), (main_x + 40.0, 30.0, -30.0), fov_y=60.0),
        "aerial": Camera((-half * 1.1, half * 0.8, half * 1.1), (0.0, 0.0, 0.0), fov_y=55.0),
        "closeup": Camera((main_x + 5.0, 8.0, 14.0), (main_x + 12.0, 12.0, 0.0), fov_y=60.0),
        "dome": Camera((main_x - 9.0, 14.0, 87.0), (main_x + 31.0, 8.0, 57.0), fov_y=50.0),
    }
    return City("default", seed, masses.table(), ground, (-half, -half, half, half), viewpoints, parks, streets)


def grid_city(count: int = 100, seed: int = 1, spacing: float = 40.0, floors: int = 31, windows: int = 6) -> City:
    """A regular grid of identical apartment blocks (paper §3: 31 floors, 6x6 windows)."""
    side = int(np.ceil(np.sqrt(count)))
    rng = np.random.default_rng(seed)
    width = windows * 4.0
    masses = []
    for k in range(count):
        i, j = divmod(k, side)
        masses.append(
            box(
                (i * spacing - side * spacing / 2, j * spacing - side * spacing / 2),
                width,
                width,
                floors * 3.2,
                floor_height=3.2,
                room_width=4.0,
                seed=int(rng.integers(1 << 30)),
                wall_jitter=0.0,
            )
        )
    half = side * spacing / 2
    viewpoints = {
        "orbit": Camera((half * 1.2, half * 0.6 + 40, half * 1.2), (0.0, 30.0, 0.0), fov_y=55.0),
        "street": Camera((-half - 10, 1.7, -half - 10), (0.0, 20.0, 0.0), fov_y=60.0),
    }
    return City("grid", seed, masses, [], (-half, -half, half, half), viewpoints)


def interior_city(seed: int = 0) -> City:
    """Interior mapping's validation scene: boxes (one turned), a cylinder and a dome (paper fig. 4),
    with viewpoints on a facade, a corner, the curved walls and the dome."""
    masses = [
        box((0.0, 0.0), 18.0, 13.0, 22.0, seed=seed + 11, room_width=4.5, floor_height=3.3, wall_jitter=0.3),
        box((26.0, -4.0), 12.0, 12.0, 30.0, yaw=0.35, seed=seed + 12, room_width=4.0, floor_height=3.0),
        cylinder((-22.0, 4.0), 14.0, 26.0, seed=seed + 13, room_width=4.0),
        dome((-8.0, 26.0), 16.0, seed=seed + 14, room_width=4.0),
    ]
    viewpoints = {
        "front": Camera((9.0, 6.0, -16.0), (9.0, 8.0, 6.0), fov_y=60.0),
        "corner": Camera((-7.0, 9.0, -9.0), (6.0, 9.0, 5.0), fov_y=70.0),
        "cylinder": Camera((-14.0, 4.0, -10.0), (-15.0, 6.0, 11.0), fov_y=60.0),
        "yawed": Camera((36.0, 5.0, -18.0), (30.0, 10.0, 2.0), fov_y=60.0),
        "dome": Camera((-3.0, 3.5, 15.0), (0.0, 4.0, 34.0), fov_y=60.0),
        "overview": Camera((-40.0, 18.0, -40.0), (0.0, 10.0, 10.0), fov_y=60.0),
    }
    return City("interior", seed, masses, [], (-60.0, -60.0, 60.0, 60.0), viewpoints)


def _ring(n: int, radius: float, start: float = 0.0) -> np.ndarray:
    a = start + np.linspace(0, 2 * np.pi, n, endpoint=False)
    return radius * np.stack([1 + np.cos(a), 1 + np.sin(a)], axis=1)


def outlines_city(seed: int = 0) -> City:
    """Facades and rooms on outlines other than boxes, as maps draw them: an L-shaped block (window
    bays), a round tower drawn as 32 short walls and a curved block (grammar facades), and a block
    round a courtyard (grammar); with viewpoints on each."""
    bend = np.radians(np.arange(0.0, 90.1, 7.5))  # a street front bending 7.5 degrees per wall
    curved = np.vstack([np.stack([30 * np.sin(bend), 30 - 30 * np.cos(bend)], axis=1), [(12.0, 30.0), (0.0, 12.0)]])
    masses = [
        BuildingMass(
            "prism",
            (0.0, 0.0),
            ((0.0, 0.0), (26.0, 0.0), (26.0, 11.0), (11.0, 11.0), (11.0, 24.0), (0.0, 24.0)),
            19.0,
            seed=seed + 21,
            room_width=4.2,
            floor_height=3.2,
        ),
        BuildingMass(
            "prism",
            (36.0, -2.0),
            tuple(map(tuple, _ring(32, 8.0))),
            31.0,
            seed=seed + 22,
            style=3,
            room_width=4.0,
            floor_height=3.4,
        ),
        BuildingMass(
            "prism",
            (0.0, 40.0),
            ((0.0, 0.0), (30.0, 0.0), (30.0, 28.0), (0.0, 28.0)),
            16.0,
            seed=seed + 23,
            style=4,
            holes=(((9.0, 9.0), (9.0, 19.0), (21.0, 19.0), (21.0, 9.0)),),
            room_width=4.5,
            floor_height=3.1,
        ),
        BuildingMass(
            "prism",
            (42.0, 36.0),
            tuple(map(tuple, curved)),
            22.0,
            seed=seed + 24,
            style=1,
            room_width=4.0,
            floor_height=3.5,
        ),
    ]
    viewpoints = {
        "l_shape": Camera((30.0, 7.0, 26.0), (8.0, 9.0, 6.0), fov_y=65.0),
        "tower": Camera((44.0, 1.7, -30.0), (44.0, 16.0, 6.0), fov_y=66.0),
        "courtyard": Camera((12.0, 9.0, 57.5), (20.0, 8.0, 50.0), fov_y=75.0),
        "curved": Camera((86.0, 6.0, 40.0), (58.0, 10.0, 52.0), fov_y=60.0),
    }
    return City("outlines", seed, masses, [], (-30.0, -40.0, 100.0, 100.0), viewpoints)


CITIES = {"default": default_city, "grid": grid_city, "interior": interior_city, "outlines": outlines_city}


def make_city(name: str = "default", seed: int | None = None) -> City:
    if not isinstance(name, str) or name not in CITIES:
        raise UsageError(f"unknown city {name!r}; allowed: {', '.join(CITIES)}")
    return CITIES[name]() if seed is None else CITIES[name](seed=check_seed(seed))
