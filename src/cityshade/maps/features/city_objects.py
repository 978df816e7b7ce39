"""CityJSON city objects other than buildings, drawn as given, and the ground under given buildings.

Every face of a city object is triangulated in its plane at its heights as given and drawn as ground
of its class: Road, Railway, TransportSquare and Waterway as asphalt, ballast, paving and water;
LandUse and PlantCover by their `class`/`function` (CLASS_MATERIALS, green by default); WaterBody as
water; Bridge, Tunnel, CityFurniture, GenericCityObject and anything else plain (concrete); TINRelief
as bare land. SolitaryVegetationObjects are trees at their lowest point, as tall as their `height`
attribute or their geometry. Under buildings drawn as given the ground follows their GroundSurfaces:
a Delaunay surface through the buildings' GroundSurfaces (or lowest corners) and the corners of the
ground objects (GROUND_TYPES), GROUND_BELOW under them (so it never fights a face drawn as given),
reaching the map's bounds at the heights of the nearest corners. What
`cityshade info` says: `city_objects` (type -> objects drawn) and `lod` (LoD -> buildings).
"""

from __future__ import annotations

from collections import Counter

import numpy as np
import scipy.spatial

from ...scene import (
    GROUND_ASPHALT,
    GROUND_BALLAST,
    GROUND_GRASS,
    GROUND_LAND,
    GROUND_PAVEMENT,
    GROUND_PLATFORM,
    GROUND_SAND,
    GROUND_WATER,
    Layer,
    plane_triangles,
)
from .._model import MapData, MapTree
from ._feature import Built, Feature
from .land import BASE_DEPTH
from .terrain import Relief
from .trees import tree_records

TYPE_MATERIALS = {
    "Road": GROUND_ASPHALT,
    "Railway": GROUND_BALLAST,
    "TransportSquare": GROUND_PAVEMENT,
    "Waterway": GROUND_WATER,
    "WaterBody": GROUND_WATER,
    "LandUse": GROUND_GRASS,
    "PlantCover": GROUND_GRASS,
    "TINRelief": GROUND_LAND,
}
GROUND_TYPES = ("Road", "Railway", "TransportSquare", "Waterway", "WaterBody", "LandUse", "PlantCover", "TINRelief")
PLAIN = GROUND_PLATFORM  # bridges, tunnels, furniture, generic objects: concrete
# words in a LandUse or PlantCover class that say its ground is not green
CLASS_MATERIALS = {
    "road": GROUND_ASPHALT,
    "rail": GROUND_BALLAST,
    "water": GROUND_WATER,
    "sand": GROUND_SAND,
    "bare": GROUND_LAND,
    "gesloten verharding": GROUND_PAVEMENT,
    "open verharding": GROUND_PAVEMENT,
    "paved": GROUND_PAVEMENT,
    "pavement": GROUND_PAVEMENT,
    "erf": GROUND_PAVEMENT,
    "onverhard": GROUND_SAND,
}
GROUND_BELOW = 0.1  # metres the ground under given buildings lies below their GroundSurfaces
DEFAULT_TREE_HEIGHT = 8.0


def object_material(obj) -> int:
    if obj.type in ("LandUse", "PlantCover") and obj.kind:
        kind = obj.kind.lower()
        for word, material in CLASS_MATERIALS.items():
            if word in kind:
                return material
    return TYPE_MATERIALS.get(obj.type, PLAIN)


def _scene_triangles(rings: list[np.ndarray], materials: list[int]) -> np.ndarray:
    """(N*3, 4) ground rows (scene x, y, z, material) of map-metre rings triangulated in their planes."""
    if not rings:
        return np.zeros((0, 4), np.float32)
    counts = np.array([len(r) for r in rings])
    points = np.vstack(rings)
    scene = np.column_stack([points[:, 0], points[:, 2], -points[:, 1]])  # map (x, y north, up) -> scene
    triangles, owner = plane_triangles(scene, counts)
    out = np.empty((len(triangles) * 3, 4), np.float32)
    out[:, :3] = triangles.reshape(-1, 3)
    out[:, 3] = np.repeat(np.asarray(materials)[owner], 3)
    return out


def given_ground(data: MapData) -> np.ndarray:
    """The ground under buildings drawn as given (see the module docstring)."""
    corners = []
    for b in data.buildings:
        if b.surfaces:  # its GroundSurfaces, else its lowest corners
            grounds = b.surfaces.get("GroundSurface")
            rings = grounds or [ring[ring[:, 2] <= b.ground + 0.01] for rings in b.surfaces.values() for ring in rings]
            corners += rings
    # ground drawn as given (roads, land, water): the ground under the buildings runs below it too
    corners += [ring for o in data.city_objects if o.type in GROUND_TYPES for _, ring in o.faces]
    if not corners:
        return np.zeros((0, 4), np.float32)
    points = np.vstack(corners)
    x0, y0, x1, y1 = data.bounds()
    margin = 30.0
    edge = np.array(
        [(x0 - margin, y0 - margin), (x1 + margin, y0 - margin), (x1 + margin, y1 + margin), (x0 - margin, y1 + margin)]
    )
    nearest = scipy.spatial.cKDTree(points[:, :2]).query(edge)[1]
    points = np.vstack([points, np.column_stack([edge, points[nearest, 2]])])
    points = points[np.unique(np.round(points[:, :2], 2), axis=0, return_index=True)[1]]
    if len(points) < 3:
        return np.zeros((0, 4), np.float32)
    try:
        triangles = scipy.spatial.Delaunay(points[:, :2]).simplices
    except scipy.spatial.QhullError:  # every corner on one line
        return np.zeros((0, 4), np.float32)
    corner = points[triangles.ravel()]
    out = np.empty((len(corner), 4), np.float32)
    out[:, 0], out[:, 1], out[:, 2], out[:, 3] = corner[:, 0], corner[:, 2] - GROUND_BELOW, -corner[:, 1], GROUND_LAND
    return out


def _trees(data: MapData) -> np.ndarray | None:
    vegetation = [o for o in data.city_objects if o.type == "SolitaryVegetationObject"]
    if not vegetation:
        return None
    trees, ground = [], []
    for obj in vegetation:
        points = np.vstack([ring for _, ring in obj.faces])
        tree = MapTree(obj.source_id, (float(points[:, 0].mean()), float(points[:, 1].mean())))
        height = obj.attributes.get("height", obj.attributes.get("treeHeight"))
        measured = float(np.ptp(points[:, 2]))
        tree.height = (
            float(height)
            if isinstance(height, (int, float)) and 0 < height < 150
            else (measured or DEFAULT_TREE_HEIGHT)
        )
        trees.append(tree)
        ground.append(float(points[:, 2].min()))
    return tree_records(trees, np.asarray(ground))


class CityObjects(Feature):
    name = "city_objects"

    def summary(self, data):
        given = [b for b in data.buildings if b.lod is not None]
        if not given and not data.city_objects:
            return {}
        return {
            "city_objects": dict(data.drawn_types.most_common()),
            "lod": dict(sorted(Counter(b.lod for b in given).items())),
        }

    def build(self, data):
        drawn = [o for o in data.city_objects if o.type != "SolitaryVegetationObject"]
        rings = [ring for o in drawn for _, ring in o.faces]
        materials = [object_material(o) for o in drawn for _ in o.faces]
        ground = np.concatenate([given_ground(data), _scene_triangles(rings, materials)])
        return Built(Layer(self.name, ground, trees=_trees(data)))


def given_ground_height(city):
    """For a city with ground under buildings drawn as given or a terrain (--terrain): the height at
    scene (x, z) of that ground, from its nearest corners (None for any other city, whose ground is at 0)."""
    for name, below in ((Relief.name, BASE_DEPTH), (CityObjects.name, GROUND_BELOW)):
        layer = next((layer for layer in city.layers if layer.name == name and len(layer.ground)), None)
        if layer is not None:
            return _nearest_height(layer.ground, below)
    return None


def _nearest_height(ground: np.ndarray, below: float):
    """Height at scene (x, z) of a ground mesh's nearest corners (inverse-distance weighted), lifted by
    `below`; corners of upright triangles (a terrain's skirts, walls) left out."""
    corners = ground.reshape(-1, 3, 4)
    u, v = corners[:, 1, [0, 2]] - corners[:, 0, [0, 2]], corners[:, 2, [0, 2]] - corners[:, 0, [0, 2]]
    lying = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) > 1e-6
    ground = corners[lying].reshape(-1, 4) if lying.any() else ground
    tree = scipy.spatial.cKDTree(ground[:, [0, 2]])

    def height(x, z):
        distance, index = tree.query([x, z], k=8)
        weights = 1.0 / np.maximum(distance, 1e-6)
        return float((ground[index, 1] * weights).sum() / weights.sum()) + below

    return height
