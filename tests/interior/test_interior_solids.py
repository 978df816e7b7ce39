"""The interior twin's own geometry (cityshade.interior.cast_masses): exact solids built from the
building records, checked against hits worked out by hand."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.interior import cast_masses
from cityshade.scene import box, cylinder, dome


def cast(mass, eye, direction):
    d = np.asarray(direction, float)
    return cast_masses([mass], np.asarray(eye, float), (d / np.linalg.norm(d))[None])


def test_box_wall_roof_and_miss():
    mass = box((0.0, 0.0), 18.0, 12.0, 20.0, room_width=4.5)  # 4 bays of 4.5 m along x
    wall = cast(mass, (5.0, 2.0, -10.0), (0, 0, 1))
    assert wall.t[0] == pytest.approx(10.0) and wall.building[0] == 0 and not wall.roof[0]
    assert np.allclose(wall.normal[0], (0, 0, -1)) and np.allclose(wall.facade[0], (5.0, 2.0, 4.5, 20.0 / 6))
    assert np.allclose(wall.face[0], (18.0, 0.0, 20.0, 4.0)) and tuple(wall.columns[0]) == (0, 3)
    side = cast(mass, (30.0, 3.0, 4.0), (-1, 0, 0))  # the +x facade runs from z = 0 toward +z
    assert side.t[0] == pytest.approx(12.0) and np.allclose(side.normal[0], (1, 0, 0))
    assert np.allclose(side.facade[0][:3], (4.0, 3.0, 12.0 / round(12.0 / mass.room_size[2])))
    assert tuple(side.columns[0]) == (3, 5)  # its first room is the -z facade's last: the same corner room
    roof = cast(mass, (9.0, 30.0, 6.0), (0, -1, 0))
    assert roof.t[0] == pytest.approx(10.0) and roof.roof[0] and np.allclose(roof.normal[0], (0, 1, 0))
    miss = cast(mass, (9.0, 30.0, 6.0), (0, 1, 0))
    assert np.isinf(miss.t[0]) and miss.building[0] == -1


def test_a_turned_box_is_hit_where_the_turned_footprint_stands():
    yaw = 0.35
    mass = box((26.0, -4.0), 12.0, 12.0, 30.0, yaw=yaw)
    # the local point (6, 5, 0) on the -z facade, in world space: rotate about +y, then move
    c, s = np.cos(yaw), np.sin(yaw)
    world = np.array([26.0 + 6 * c, 5.0, -4.0 - 6 * s])
    normal_world = np.array([-s, 0.0, -c])  # the local -z normal turned
    hit = cast(mass, world + 10 * normal_world, -normal_world)
    assert hit.t[0] == pytest.approx(10.0) and np.allclose(hit.local[0], (6.0, 5.0, 0.0))
    assert np.allclose(hit.facade[0][:2], (6.0, 5.0))


def test_cylinder_facade_runs_around_the_circle():
    mass = cylinder((0.0, 0.0), 14.0, 26.0, room_width=4.0)
    radius = 7.0
    hit = cast(mass, (7.0, 5.0, -20.0), (0, 0, 1))  # meets the circle at angle 3/2 pi (toward -z)
    assert hit.t[0] == pytest.approx(20.0) and np.allclose(hit.normal[0], (0, 0, -1))
    circumference = 2 * np.pi * radius
    assert np.allclose(hit.facade[0][:3], (1.5 * np.pi * radius, 5.0, circumference / round(circumference / 4.0)))
    assert np.allclose(hit.face[0][:3], (circumference, 0.0, 26.0))
    grazing = cast(mass, (7.0 + radius + 0.01, 5.0, -20.0), (0, 0, 1))
    assert np.isinf(grazing.t[0])


def test_dome_latitude_and_longitude():
    """A 16 m dome of 3 m floors: 4 storeys of 2 pi m up its arc, rings of 22.5 degrees; the first
    two are faces (their top circle at least 2/3 of their bottom one), the cap from 45 degrees is roof."""
    mass = dome((0.0, 0.0), 16.0, room_width=4.0)
    radius = 8.0
    storey = np.pi / 2 * radius / 4
    top = cast(mass, (8.0, 20.0, 8.0), (0, -1, 0))
    assert top.t[0] == pytest.approx(12.0) and np.allclose(top.normal[0], (0, 1, 0))
    assert top.facade[0][1] == pytest.approx(np.pi / 2 * radius) and top.roof[0]
    side = cast(mass, (8.0, 0.5, -20.0), (0, 0, 1))  # low on the -z side: longitude pi/2, the first ring
    circle = radius * np.cos(np.pi / 16)  # the circle half way up the first ring
    bays = round(2 * np.pi * circle / 4.0)
    assert not side.roof[0]
    assert side.facade[0][0] == pytest.approx(np.pi / 2 * circle, rel=1e-6)
    assert side.facade[0][1] == pytest.approx(np.arcsin(0.5 / radius) * radius)
    assert np.allclose(side.facade[0][2:], (2 * np.pi * circle / bays, storey))
    assert np.allclose(side.face[0][:3], (2 * np.pi * circle, 0.0, storey))
    assert np.array_equal(side.columns[0], (0, bays - 1))
    second = cast(mass, (8.0, radius * np.sin(np.radians(30)), -20.0), (0, 0, 1))  # 30 degrees up
    circle2 = radius * np.cos(3 * np.pi / 16)
    bays2 = round(2 * np.pi * circle2 / 4.0)
    assert not second.roof[0] and np.allclose(second.face[0][:3], (2 * np.pi * circle2, storey, 2 * storey))
    assert np.array_equal(second.columns[0], (bays, bays + bays2 - 1))
    cap = cast(mass, (8.0, radius * np.sin(np.radians(50)), -20.0), (0, 0, 1))  # 50 degrees up: the cap
    assert cap.roof[0]
    below = cast(mass, (8.0, -0.5, -20.0), (0, 0, 1))  # the lower half is not part of the dome
    assert np.isinf(below.t[0])
