"""Facade coordinates for any wall (cityshade.scene.wall_faces and the meshes' rows): faces end at
corners, curved runs of short segments are one face with a continuous arc length, every face holds
whole bays, and convex corners share their room."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.scene import (
    CORNER_TURN,
    SURFACE_DORMER,
    SURFACE_ROOF,
    SURFACE_WALL,
    BuildingMass,
    Roof,
    building_vertices,
    storeys,
    wall_faces,
)


def _faces(ring, nominal=4.0, first_column=0):
    ring = np.asarray(ring, float)
    d = np.roll(ring, -1, axis=0) - ring
    return wall_faces(np.hypot(d[:, 0], d[:, 1]), d, nominal, first_column)


def _circle(n, radius, centre=(20.0, 20.0)):
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)], axis=1)


L_SHAPE = ((0.0, 0.0), (24.0, 0.0), (24.0, 10.0), (10.0, 10.0), (10.0, 22.0), (0.0, 22.0))


def test_a_box_has_four_faces_of_whole_bays_and_shares_its_corner_rooms():
    faces = _faces([(0, 0), (18, 0), (18, 13), (0, 13)], nominal=4.5)
    assert np.allclose(faces.width, (18, 13, 18, 13)) and np.allclose(faces.along, 0)
    assert np.allclose(faces.bay, (4.5, 13 / 3, 4.5, 13 / 3))
    assert np.allclose(faces.depth, (13 / 3, 4.5, 13 / 3, 4.5))  # the bays of the faces beside it
    # columns: each face's first room is the last of the one before, round the building
    assert faces.columns.tolist() == [[0, 3], [3, 5], [5, 8], [8, 0]]


def test_an_l_shape_ends_faces_at_every_corner_and_keeps_rooms_apart_at_the_inner_one():
    faces = _faces(L_SHAPE)
    assert np.allclose(faces.width, (24, 10, 14, 12, 10, 22))
    assert np.all(np.abs(faces.width / faces.bay - np.round(faces.width / faces.bay)) < 1e-9)
    first, last = faces.columns[:, 0], faces.columns[:, 1]
    # the inner corner (a right turn, between the faces 14 m and 12 m long) shares no room
    assert first[3] == last[2] + 1
    assert first[1] == last[0] and first[2] == last[1] and first[4] == last[3] and first[5] == last[4]
    assert last[5] == first[0]


@pytest.mark.parametrize("sides", [12, 32, 180])
def test_a_round_tower_drawn_as_short_segments_is_one_face_with_a_continuous_arc_length(sides):
    radius = 8.0
    faces = _faces(_circle(sides, radius))
    chord = 2 * radius * np.sin(np.pi / sides)
    assert np.allclose(faces.width, sides * chord)
    assert np.allclose(faces.along, np.arange(sides) * chord)  # no restart at any vertex
    assert np.allclose(faces.bay, sides * chord / round(sides * chord / 4.0))
    assert np.all(faces.columns == [0, round(sides * chord / 4.0) - 1])


def test_corners_are_turns_beyond_thirty_degrees():
    assert CORNER_TURN == pytest.approx(np.radians(30))
    octagon = _faces(_circle(8, 10.0))  # 45 degree turns: eight faces
    assert np.allclose(octagon.width, 20 * np.sin(np.pi / 8)) and np.allclose(octagon.along, 0)
    # a curved block: a street front bending by 10 degrees per segment, closed by two straight walls
    t = np.radians(np.arange(0, 91, 10))
    ring = np.vstack([np.stack([20 * np.sin(t), 20 - 20 * np.cos(t)], axis=1), [(0.0, 20.0)]])
    faces = _faces(ring)
    chord = 40 * np.sin(np.radians(5))
    assert np.allclose(faces.width[:9], 9 * chord) and np.allclose(faces.along[:9], np.arange(9) * chord)
    assert np.allclose(faces.width[9:], 20.0) and np.allclose(faces.along[9:], 0)


def test_courtyards_continue_the_room_columns_and_mesh_rows_carry_the_face():
    hole = ((8.0, 8.0), (8.0, 16.0), (16.0, 16.0), (16.0, 8.0))  # clockwise
    mass = BuildingMass(
        "prism",
        (0.0, 0.0),
        ((0.0, 0.0), (24.0, 0.0), (24.0, 24.0), (0.0, 24.0)),
        14.0,
        holes=(hole,),
        room_width=4.0,
        floor_height=3.0,
    )
    v = building_vertices(mass, 0)
    walls = v[v["ids"][:, 1] != SURFACE_ROOF]
    inner = np.all((walls["local"][:, [0, 2]] >= 8 - 1e-6) & (walls["local"][:, [0, 2]] <= 16 + 1e-6), axis=1)
    assert set(np.unique(walls["face"][inner, 0])) == {8.0} and set(np.unique(walls["face"][~inner, 0])) == {24.0}
    assert walls["ids"][inner, 2:].min() > walls["ids"][~inner, 2:].max()  # the courtyard's rooms come after
    storey, levels = storeys(0.0, 14.0, 3.0)
    assert (storey, levels) == (pytest.approx(14 / 5), 5) and np.allclose(walls["facade"][:, 3], storey)
    assert np.allclose(walls["face"][:, 1:3], (0.0, 14.0))
    # facade u runs from 0 to the face's width along each face
    assert walls["facade"][:, 0].min() == pytest.approx(0) and np.allclose(walls["facade"][:, 0].max(), 24.0)


def test_a_polygon_tower_mesh_runs_its_windows_round_without_restarting():
    pts = _circle(64, 9.0, centre=(9.0, 9.0))
    mass = BuildingMass("prism", (0.0, 0.0), tuple(map(tuple, pts)), 30.0, room_width=4.0)
    v = building_vertices(mass, 0)
    walls = v[v["ids"][:, 1] != SURFACE_ROOF]
    perimeter = 64 * 2 * 9.0 * np.sin(np.pi / 64)
    assert np.allclose(walls["face"][:, 0], perimeter, rtol=1e-6)
    assert walls["facade"][:, 0].max() == pytest.approx(perimeter, rel=1e-6)
    assert np.allclose(walls["facade"][:, 2], perimeter / round(perimeter / 4.0), rtol=1e-6)


def test_every_gable_and_dormer_front_has_rooms_of_its_own():
    """An L-shaped block under a gabled roof with rooms in it: its two gable ends (14 m: 3 bays,
    9 m: 2 bays) and its dormer fronts each own a run of room columns, one per bay, that no other
    wall piece and no wall below uses (a shared run gave two gables' windows one key and a gable's
    middle bay a dormer's room)."""
    outline = ((0.0, 0.0), (30.0, 0.0), (30.0, 14.0), (9.0, 14.0), (9.0, 25.0), (0.0, 25.0))
    roof = Roof("gabled", 6.0, attic_storey=3.0)
    mass = BuildingMass("prism", (0.0, 0.0), outline, 18.0, room_width=4.5, floor_height=3.0, roof=roof)
    tris = building_vertices(mass, 0).reshape(-1, 3)
    surface, span_top = tris["ids"][:, 0, 1], tris["face"][:, 0, 2]
    fronts = tris[surface == SURFACE_DORMER]
    gables = tris[(surface == SURFACE_WALL) & (span_top == mass.height)]
    walls = tris[(surface == SURFACE_WALL) & (span_top == mass.wall_top)]
    runs = {}  # each wall piece (a gable: its plane; a dormer front: also its middle) -> its bays' room columns
    for tri in np.concatenate([gables, fronts]):
        local, row = tri["local"].astype(np.float64), tri[0]
        normal = np.round(row["normal"].astype(np.float64), 3)
        across = local @ (-normal[2], 0.0, normal[0])
        middle = round(float(across.min() + across.max()) / 2, 1) if row["ids"][1] == SURFACE_DORMER else None
        plane = (row["ids"][1], *normal, round(float(np.dot(normal, local[0])), 2), middle)
        bays = round(float(row["face"][0] / row["facade"][2]))
        first, last = int(row["ids"][2]), int(row["ids"][3])
        assert last == first + bays - 1  # a column per bay
        assert runs.setdefault(plane, (first, last)) == (first, last)  # the same on all of the piece's triangles
    gable_bays = sorted(last - first + 1 for (kind, *_), (first, last) in runs.items() if kind == SURFACE_WALL)
    assert gable_bays == [2, 3] and len(runs) == 2 + len(np.unique(fronts["ids"][:, 0, 2])) > 3
    columns = [c for first, last in runs.values() for c in range(first, last + 1)]
    assert len(columns) == len(set(columns))  # no two pieces share a room
    assert min(columns) > walls["ids"][..., 2:].max()  # nor a wall below
