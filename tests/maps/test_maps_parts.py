"""Outlines and their building:part ways: an outline its parts cover in part is drawn only where no
part stands, so no wall of it stands in the same place, facing the same way, as a part's wall."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.maps import building_masses, load_map, to_scene
from cityshade.maps.testing import building_mass
from cityshade.scene import SURFACE_WALL, building_vertices, rotation_y
from render_checks import style_face_labels

PARTS = Path(__file__).parents[1] / "data" / "maps" / "parts.osm"
STEP = 0.01  # metres off a wall to tell which side of it a mass stands


@pytest.fixture(scope="module")
def data():
    return load_map(PARTS)


def by_id(data, source_id):
    (building,) = [b for b in data.buildings if b.source_id == source_id]
    return building


def wall_points(mass):
    """Centres of the mass's wall triangles in the world and their outward normals (world x, y, z)."""
    v = building_vertices(mass, 0)
    v = v[v["ids"][:, 1] == SURFACE_WALL]
    tris = v["position"].astype(np.float64).reshape(-1, 3, 3)  # world already
    normals = v["normal"].reshape(-1, 3, 3)[:, 0].astype(np.float64) @ rotation_y(mass.yaw).T  # object -> world
    keep = np.abs(normals[:, 1]) < 1e-6  # upright walls, not undersides
    return tris[keep].mean(axis=1), normals[keep]


def inside(masses, points):
    """Whether each world point lies inside one of the masses' volumes (prism footprint, base..height)."""
    hit = np.zeros(len(points), dtype=bool)
    for mass in masses:
        c, s = np.cos(mass.yaw), np.sin(mass.yaw)
        local = shapely.Polygon(mass.footprint, mass.holes)
        dx, dz = points[:, 0] - mass.position[0], points[:, 2] - mass.position[1]
        x, z = c * dx - s * dz, s * dx + c * dz  # world -> object space: the inverse of rotation_y
        within = shapely.contains_xy(local, x, z) & (points[:, 1] > mass.base) & (points[:, 1] < mass.height)
        hit |= within
    return hit


def same_facing(outline_masses, part_masses):
    """(wall triangles of the outline's masses with a part's volume behind them: a wall standing where a
    part's wall stands, facing the same way; wall triangles back to back with a part's wall)."""
    centres, normals = (
        np.concatenate([wall_points(m)[0] for m in outline_masses]),
        np.concatenate([wall_points(m)[1] for m in outline_masses]),
    )
    behind = inside(part_masses, centres - STEP * normals)
    front = inside(part_masses, centres + STEP * normals)
    return int(behind.sum()), int(front.sum())


def test_outlines_with_parts_are_replaced_cut_or_kept(data):
    assert by_id(data, "way/300").replaced_by_parts  # covered whole by its part
    kept = by_id(data, "way/400")
    assert kept.drawn and kept.remainder is None and kept.drawn_footprint is kept.outline
    half = by_id(data, "way/200")
    part = by_id(data, "way/201")
    assert half.drawn and not half.replaced_by_parts
    # the east half stays; the 0.4 m strip north of the part is a sliver, dropped and counted
    assert half.remainder.area == pytest.approx(half.outline.area / 2, rel=0.01)
    assert shapely.intersection(half.remainder, part.outline).area < 1e-6
    assert data.report.skipped[next(k for k in data.report.skipped if k[0] == "building outline sliver")] == 1
    assert sum(n for (what, _), n in data.report.repaired.items() if what == "building outline") == 4


def test_no_outline_wall_stands_where_a_parts_wall_does(data):
    masses = building_masses(data)
    for outline_id, part_id in (("way/200", "way/201"), ("way/500", "way/501"), ("way/600", "way/601")):
        outline, part = by_id(data, outline_id), by_id(data, part_id)
        drawn = [m for m in masses if m.seed == outline.index]
        parts = [m for m in masses if m.seed == part.index]
        assert drawn and parts
        behind, back_to_back = same_facing(drawn, parts)
        assert behind == 0
        assert back_to_back > 0  # where they meet, each wall faces away from the other
        # the whole outline, drawn as before, has walls with the part's volume behind them: the check can fail
        whole = [building_mass(outline, p) for p in shapely.get_parts(shapely.transform(outline.outline, to_scene))]
        assert same_facing(whole, parts)[0] > 0


def test_a_cut_l_loses_its_gable_and_stops_at_the_eaves(data):
    (mass,) = [m for m in building_masses(data) if m.seed == by_id(data, "way/500").index]
    assert mass.roof.shape == "flat" and mass.height == pytest.approx(10.0)  # 14 m tagged, 4 m of roof
    (rectangle,) = [m for m in building_masses(data) if m.seed == by_id(data, "way/200").index]
    assert rectangle.height == pytest.approx(12.0)


def test_the_outline_stays_under_a_part_that_floats_up_to_its_base(data):
    outline, part = by_id(data, "way/600"), by_id(data, "way/601")
    ((under, above),) = outline.beneath_parts
    assert above is part and shapely.symmetric_difference(under, part.outline).area < 1e-3
    masses = [m for m in building_masses(data) if m.seed == outline.index]
    assert sorted(m.height for m in masses) == pytest.approx([6.0, 12.0])
    low = next(m for m in masses if m.height == pytest.approx(6.0))
    assert low.roof.shape == "flat" and low.roof.parapet == 0.0  # the part stands on it
    # on the ground, the outline's masses cover the whole outline
    assert sum(shapely.Polygon(m.footprint).area for m in masses) == pytest.approx(outline.outline.area, rel=1e-6)


def test_a_raised_part_starts_at_its_level_and_draws_no_ground_floor(data):
    """A part from min_height 6 m with no building:min_level starts at its min height over its storey
    height (2); the outline beneath it at the ground (0); a building:min_level (tagged, or guessed
    from min_height by the guessing model) wins.
    The raised part's faces, evaluated with brick at their facade.level, have no door; the
    outline's, on the ground, have theirs."""
    import dataclasses

    from cityshade.assets import LABELS
    from cityshade.scene import batch, vertex_face_levels

    outline, part = by_id(data, "way/600"), by_id(data, "way/601")
    masses = building_masses(data)
    (raised,) = [m for m in masses if m.seed == part.index]
    low = [m for m in masses if m.seed == outline.index]
    assert part.min_level is None and raised.base == pytest.approx(6.0) and raised.first_level == 2
    assert [m.first_level for m in low] == [0, 0]
    polygon = shapely.transform(part.outline, to_scene)
    assert building_mass(dataclasses.replace(part, min_level=3.0), polygon).first_level == 3
    doors = {}
    for name, mass in (("raised", raised), ("ground", max(low, key=lambda m: m.height))):
        vertices, records = batch([mass])
        walls = vertices[vertices["ids"][:, 1] == SURFACE_WALL]
        walls = walls[walls["face"][:, 0] >= 5.0]  # faces wide enough for brick's door bay
        faces, first = np.unique(walls["ids"][:, 2], return_index=True)
        levels = vertex_face_levels(walls[first], records)
        doors[name] = 0
        for face, row, level in zip(faces, walls[first], levels):
            size = (float(row["face"][0]), float(row["face"][2] - row["face"][1]))
            labels = style_face_labels("brick", size, mass.seed, int(face), int(level))
            doors[name] += int(np.count_nonzero(labels == LABELS.index("door")))
        print(f"{name}: faces at levels {sorted(set(levels.tolist()))}, {doors[name]} door points")
    assert doors["raised"] == 0 and doors["ground"] > 0


def test_an_outline_covered_whole_by_a_floating_part_stands_under_it(data):
    outline, part = by_id(data, "way/700"), by_id(data, "way/701")
    assert not outline.replaced_by_parts and outline.remainder.is_empty
    ((under, above),) = outline.beneath_parts
    assert above is part
    (mass,) = [m for m in building_masses(data) if m.seed == outline.index]
    assert mass.base == pytest.approx(0.0) and mass.height == pytest.approx(4.0)
    assert shapely.Polygon(mass.footprint).area == pytest.approx(outline.outline.area, rel=1e-6)
    (raised,) = [m for m in building_masses(data) if m.seed == part.index]
    assert raised.base == pytest.approx(4.0)


def test_helsinki_wall_under_a_part_shows_one_building_per_pixel(helsinki_pbf, gl_context, output_dir):
    """Part way/89541313 (upper storeys from building:min_level 2) inside relation/1320784 shares 47 m of
    its west wall with the outline. Looking at that wall, the id AOV shows only the part within its
    storeys and only the outline below them; drawn whole, the outline showed through in streaks."""
    from PIL import Image

    from cityshade.maps import map_city
    from cityshade.render import Renderer, RenderSettings
    from cityshade.scene import Camera

    data = load_map(helsinki_pbf)
    city = map_city(data)
    outline = next(b for b in data.buildings if b.source_id == "relation/1320784" and not b.is_part)
    part = by_id(data, "way/89541313")
    shared = shapely.intersection(outline.outline.exterior, part.outline.boundary.buffer(0.05))
    runs = [np.asarray(line.coords) for line in shapely.get_parts(shapely.line_merge(shared))]
    a, b = max(((p, q) for run in runs for p, q in zip(run[:-1], run[1:])), key=lambda s: np.hypot(*(s[1] - s[0])))
    mid, along = (a + b) / 2, (b - a) / np.hypot(*(b - a))
    out = np.array([along[1], -along[0]])
    if outline.outline.contains(shapely.Point(mid + 0.5 * out)):
        out = -out
    eye = mid + 10.0 * out  # 11.6 m of street before the next building
    (part_mass,) = [m for m in city.masses if m.seed == part.index]
    seeds = np.array([m.seed for m in city.masses])
    renderer = Renderer((160, 120), RenderSettings(samples=0, god_rays=False), ctx=gl_context)
    renderer.set_city(city)
    counts = {}
    try:
        for name, y in (("part storeys", (part_mass.base + part_mass.wall_top) / 2), ("below them", 3.0)):
            camera = Camera((eye[0], y, -eye[1]), (mid[0], y, -mid[1]), fov_y=40.0)
            mass = renderer.render_ids(camera)[30:90, 40:120, 2].astype(np.int64) - 1  # the middle: the wall
            building = np.where(mass >= 0, seeds[np.maximum(mass, 0)], -1)
            counts[name] = {
                "part": int((building == part.index).sum()),
                "outline": int((building == outline.index).sum()),
            }
            Image.fromarray(renderer.render(camera)).save(output_dir / f"parts_helsinki_{y:.0f}m.png")
    finally:
        renderer.release()
    print(counts)
    assert counts["part storeys"] == {"part": 4800, "outline": 0}
    assert counts["below them"] == {"part": 0, "outline": 4800}
