"""Faces as given (CityJSON) meshed: grammar only on whole cells inside each wall, the rest plain."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from cityshade.scene import (
    GIVEN_FLOOR,
    GIVEN_ROOF,
    GIVEN_WALL,
    SURFACE_PLAIN_WALL,
    SURFACE_ROOF,
    SURFACE_WALL,
    BuildingMass,
    MassTable,
    batch,
    building_vertices,
)

# a 12 x 9 m gabled house standing at 100 m: walls to 106 m, the ridge at 109 m along x (object space:
# x right, y up, z toward the viewer; rings counter-clockwise seen from outside)
A, B, C, D = (0, 100, 0), (12, 100, 0), (12, 100, 9), (0, 100, 9)
A2, B2, C2, D2 = (0, 106, 0), (12, 106, 0), (12, 106, 9), (0, 106, 9)
R0, R1 = (0, 109, 4.5), (12, 109, 4.5)
GABLED = (
    (GIVEN_WALL, (B, A, A2, B2)),  # facing -z
    (GIVEN_WALL, (D, C, C2, D2)[::-1]),  # facing +z
    (GIVEN_WALL, (C, B, B2, R1, C2)),  # the gable facing +x
    (GIVEN_WALL, (A, D, D2, R0, A2)),  # the gable facing -x
    (GIVEN_ROOF, (A2, R0, R1, B2)),
    (GIVEN_ROOF, (R1, R0, D2, C2)),
    (GIVEN_FLOOR, (A, B, C, D)),
)


def _house(**kwargs):
    footprint = ((0.0, 0.0), (12.0, 0.0), (12.0, 9.0), (0.0, 9.0))
    return BuildingMass(
        "prism", (5.0, 7.0), footprint, 109.0, base=100.0, floor_height=3.0, room_width=3.0, given=GABLED, **kwargs
    )


def _facing(vertices):
    """Per triangle: the winding's normal . the stored normal."""
    t = vertices["local"].astype(np.float64).reshape(-1, 3, 3)
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    return np.sum(n * vertices["normal"].reshape(-1, 3, 3)[:, 0], axis=1)


def test_given_faces_are_drawn_whole_and_wound_to_face_out():
    vertices = building_vertices(_house(), 0)
    surface = vertices["ids"][::3, 1]
    t = vertices["local"].astype(np.float64).reshape(-1, 3, 3)
    area = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
    walls = 2 * 12 * 6 + 2 * (9 * 6 + 9 * 3 / 2)
    roofs = 2 * 12 * np.hypot(4.5, 3.0)
    assert area[surface != SURFACE_ROOF].sum() == pytest.approx(walls, rel=1e-5)
    assert area[surface == SURFACE_ROOF].sum() == pytest.approx(roofs + 12 * 9, rel=1e-5)
    assert np.all(_facing(vertices) > 0)  # counter-clockwise about the face's normal, as extruded walls are
    assert vertices["local"][:, 1].min() == 100.0 and vertices["local"][:, 1].max() == 109.0  # heights as given


def test_grammar_only_on_whole_cells_inside_a_gable():
    vertices = building_vertices(_house(), 0)
    gable = vertices["normal"][:, 0] > 0.5  # the wall facing +x
    grammar = gable & (vertices["ids"][:, 1] == SURFACE_WALL)
    plain = gable & (vertices["ids"][:, 1] == SURFACE_PLAIN_WALL)
    u, v = vertices["facade"][:, 0], vertices["facade"][:, 1]
    bay, storey = vertices["facade"][:, 2], vertices["facade"][:, 3]
    assert np.allclose(bay[gable], 3.0) and np.allclose(storey[gable], 3.0)  # 9 m in 3 bays; 9 m in 3 storeys
    outline = shapely.Polygon([(0, 100), (9, 100), (9, 106), (4.5, 109), (0, 106)])  # the gable in (u, v)
    for k in np.flatnonzero(grammar)[::3]:  # every grammar triangle lies in a cell inside the gable
        corners = np.column_stack([u[k : k + 3], v[k : k + 3]])
        column, row = np.floor((corners.mean(axis=0) - (0.0, 100.0)) / 3.0)
        cell = shapely.box(column * 3, 100 + row * 3, column * 3 + 3, 100 + row * 3 + 3)
        assert outline.buffer(1e-3).contains(cell)
    assert v[grammar].max() == pytest.approx(106.0)  # the two storeys' cells, none in the triangle
    assert plain.any() and v[plain].min() == pytest.approx(106.0) and v[plain].max() == pytest.approx(109.0)
    assert np.all(vertices["face"][gable, 1] == 100.0)  # storeys counted from the building's base


def test_rectangular_walls_carry_the_grammar_whole():
    vertices = building_vertices(_house(), 0)
    long_walls = (np.abs(vertices["normal"][:, 2]) > 0.5) & (np.abs(vertices["normal"][:, 1]) < 0.1)
    assert np.all(vertices["ids"][long_walls, 1] == SURFACE_WALL)
    assert np.allclose(vertices["face"][long_walls, 0], 12.0)  # one face 12 m wide, 4 bays of 3 m
    columns = vertices["ids"][long_walls, 2:]
    assert {tuple(c) for c in columns.tolist()} == {(0, 3), (4, 7)}  # each wall its own run of room columns


def test_batch_meshes_given_faces_as_building_vertices_does():
    masses = [_house(seed=1), _house(seed=2, yaw=0.3)]
    vertices, _ = batch(masses)
    one_by_one = np.concatenate([building_vertices(m, i) for i, m in enumerate(masses)])
    assert vertices.tobytes() == one_by_one.tobytes()


def test_mass_table_keeps_given_faces():
    mass = _house()
    assert MassTable([mass])[0] == mass
