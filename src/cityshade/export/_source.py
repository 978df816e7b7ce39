"""What an export holds: the city (from a map or a built-in layout), cut to a region, with each
building's metadata (its map id and tags, height, levels, roof shape, what was tagged or guessed)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import UsageError
from ..scene import City, building_vertices, make_city

REGION_HELP = "minlon,minlat,maxlon,maxlat"


@dataclass
class ExportCity:
    city: City
    metadata: list[dict]  # one per city.masses entry
    origin: tuple[float, float] | None  # longitude, latitude of scene (0, 0)
    crs: str | None


def parse_region(text: str) -> tuple[float, float, float, float]:
    """--region minlon,minlat,maxlon,maxlat -> four floats, checked."""
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 4 or not all(np.isfinite(values)):
        raise UsageError(f"--region {text!r}: expected {REGION_HELP} (four numbers in degrees)")
    lon0, lat0, lon1, lat1 = values
    if not (-180 <= lon0 < lon1 <= 180 and -90 <= lat0 < lat1 <= 90):
        raise UsageError(f"--region {text!r}: need -180 <= minlon < maxlon <= 180 and -90 <= minlat < maxlat <= 90")
    return values


def _map_metadata(building, buildings) -> dict:
    parent = buildings[building.parent].source_id if building.parent is not None else None
    return {
        "source_id": building.source_id,
        "kind": building.kind,
        "part": building.is_part,
        "part_of": parent,
        "tags": dict(building.tags),
        "height": building.height,
        "min_height": building.min_height,
        "levels": building.levels,
        "roof_shape": building.roof_shape,
        "tagged": sorted(building.tagged),
        "guessed": sorted(building.guessed),
    }


def _layout_metadata(city: City, index: int, mass) -> dict:
    walls = mass.wall_top - mass.base
    return {
        "source_id": f"{city.name}/{index}",
        "kind": "yes",
        "part": False,
        "part_of": None,
        "tags": {},
        "height": float(mass.height),
        "min_height": float(mass.base),
        "levels": max(1, round(walls / mass.floor_height)),
        "roof_shape": mass.roof.shape,
        "tagged": [],
        "guessed": sorted(mass.guessed),
    }


def map_export_city(path: Path, terrain: Path | None = None) -> ExportCity:
    from ..maps import city_from_guessed, guess_missing, load_map

    map_data = guess_missing(load_map(path, terrain=terrain))
    city = city_from_guessed(map_data)
    city = city.with_layers(lambda layer: replace(layer, ground=clip_ground(layer.ground, city.bounds)))
    # map masses carry their building's index as their seed (maps.building_masses)
    metadata = [_map_metadata(map_data.buildings[mass.seed], map_data.buildings) for mass in city.masses]
    return ExportCity(city, metadata, city.origin, city.crs)


def layout_export_city(name: str) -> ExportCity:
    city = make_city(name)
    return ExportCity(city, [_layout_metadata(city, i, m) for i, m in enumerate(city.masses)], None, None)


def region_box(export: ExportCity, region) -> tuple[float, float, float, float]:
    """The region as a scene (x0, z0, x1, z1) box (north is -z)."""
    import pyproj

    if export.origin is None:
        raise UsageError("--region needs a map (--map FILE): built-in cities have no geographic position")
    to_map = pyproj.Transformer.from_crs("EPSG:4326", export.crs, always_xy=True)
    ox, oy = to_map.transform(*export.origin)
    lon0, lat0, lon1, lat1 = region
    xs, ys = to_map.transform([lon0, lon1, lon0, lon1], [lat0, lat0, lat1, lat1])
    x = np.asarray(xs) - ox
    z = -(np.asarray(ys) - oy)
    return float(x.min()), float(z.min()), float(x.max()), float(z.max())


def _inside(points: np.ndarray, box) -> np.ndarray:
    x0, z0, x1, z1 = box
    return (points[:, 0] >= x0) & (points[:, 0] <= x1) & (points[:, 1] >= z0) & (points[:, 1] <= z1)


def clip_ground(ground: np.ndarray, box) -> np.ndarray:
    """Ground triangles (N*3, 4: x, y, z, material) cut to a scene box: the map's land plane reaches
    the horizon, which an exported model has no use for."""
    import shapely

    if ground is None or not len(ground):
        return ground
    tris = ground.reshape(-1, 3, 4)
    x0, z0, x1, z1 = box
    inside = np.all(_inside(tris[:, :, [0, 2]].reshape(-1, 2), box).reshape(-1, 3), axis=1)
    cut = tris[~inside]
    pieces = [tris[inside].reshape(-1, 4)]
    if len(cut):
        polygons = shapely.polygons(np.concatenate([cut[:, :, [0, 2]], cut[:, :1, [0, 2]]], axis=1))
        clipped = shapely.clip_by_rect(shapely.make_valid(polygons), x0, z0, x1, z1)
        for k in np.flatnonzero(~shapely.is_empty(clipped)):
            parts = shapely.get_parts(shapely.constrained_delaunay_triangles(clipped[k]))
            parts = parts[shapely.get_type_id(parts) == 3]
            if not len(parts):
                continue
            corners = shapely.get_coordinates(parts).reshape(-1, 4, 2)[:, :3].reshape(-1, 2)
            flat = np.empty((len(corners), 4), np.float32)
            flat[:, 0], flat[:, 2] = corners[:, 0], corners[:, 1]
            flat[:, 1], flat[:, 3] = cut[k, 0, 1], cut[k, 0, 3]  # ground triangles are level
            pieces.append(flat)
    return np.concatenate(pieces).astype(np.float32)


def mass_centres(masses) -> np.ndarray:
    """(n, 2) scene x, z of each mass's vertex centroid."""
    if not masses:
        return np.zeros((0, 2))
    return np.stack([building_vertices(m, i)["position"][:, [0, 2]].mean(axis=0) for i, m in enumerate(masses)])


def crop(export: ExportCity, region, region_text: str) -> ExportCity:
    """Keeps the buildings, ground triangles and trees whose centres lie in the region."""
    box = region_box(export, region)
    city = export.city
    keep = np.flatnonzero(_inside(mass_centres(city.masses), box))
    if not len(keep):
        raise UsageError(
            f"--region {region_text}: no building of {city.name} lies in it; "
            f"the data's buildings lie around lon,lat {export.origin[0]:.5f},{export.origin[1]:.5f}"
        )

    def crop_layer(layer):
        trees = layer.trees
        if trees is not None and len(trees):
            trees = trees[_inside(trees["position"][:, [0, 2]].astype(np.float64), box)]
        return replace(layer, ground=clip_ground(layer.ground, box), trees=trees)

    cropped = replace(
        city.with_layers(crop_layer),
        masses=[city.masses[i] for i in keep],
        bounds=box,
        ground=[],
        parks=[],
        streets=[],
    )
    return replace(export, city=cropped, metadata=[export.metadata[i] for i in keep])
