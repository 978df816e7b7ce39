"""A city meshed at once (scene.batch) equals its buildings meshed one by one (building_vertices,
building_record), byte for byte: the built-in district, Helsinki and hand-made odd masses."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.maps import load_map, map_city
from cityshade.scene import (
    BuildingMass,
    Roof,
    batch,
    box,
    building_record,
    building_vertices,
    cylinder,
    default_city,
    dome,
)


def _one_by_one(masses):
    return (
        np.concatenate([building_vertices(m, i) for i, m in enumerate(masses)]),
        np.stack([building_record(m) for m in masses]),
    )


def _assert_same(masses):
    vertices, records = batch(masses)
    expected_vertices, expected_records = _one_by_one(masses)
    assert vertices.dtype == expected_vertices.dtype and len(vertices) == len(expected_vertices)
    differing = {f: int(np.any(vertices[f] != expected_vertices[f], axis=1).sum()) for f in vertices.dtype.names}
    assert vertices.tobytes() == expected_vertices.tobytes(), f"vertices differing per field: {differing}"
    assert records.tobytes() == expected_records.tobytes()


def _odd_masses() -> list[BuildingMass]:
    square = ((0.0, 0.0), (20.0, 0.0), (20.0, 20.0), (0.0, 20.0))
    a = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    b = np.linspace(0, np.pi, 24)
    round_block = tuple(
        map(
            tuple,
            np.concatenate([np.stack([np.cos(b), np.sin(b)], 1) * 15 + 15, [(0.0, -10.0), (30.0, -10.0)]]).tolist(),
        )
    )
    dense = tuple(map(tuple, (np.stack([np.cos(a), np.sin(a)], 1) * 30 + 31).tolist()))
    return [
        box((0.0, 0.0), 12.0, 9.0, 20.0, yaw=0.3, seed=3),
        BuildingMass("prism", (30.0, 5.0), square[::-1], 12.0, yaw=-1.1),  # clockwise outline
        BuildingMass("prism", (60.0, 0.0), square[:2] + square[1:2] + square[2:], 9.0),  # a repeated corner
        BuildingMass("prism", (90.0, 0.0), square, 15.0, holes=(((5.0, 5.0), (5.0, 15.0), (15.0, 15.0), (15.0, 5.0)),)),
        BuildingMass("prism", (120.0, 0.0), square, 8.0, base=3.0, roof=Roof("gabled", 3.0)),  # an underside
        BuildingMass("prism", (150.0, 0.0), square, 4.0, base=3.0, walls=False),  # a canopy
        cylinder((180.0, 0.0), 16.0, 30.0),
        BuildingMass("prism", (0.0, 60.0), dense, 25.0, roof=Roof("hipped", 5.0)),  # simplified
        dome((220.0, 0.0), 18.0),
        BuildingMass("prism", (250.0, 0.0), square, 14.0, roof=Roof("pyramidal", 4.0), yaw=2.0),
        BuildingMass(
            "prism",
            (290.0, 0.0),
            square,
            14.0,
            roof=Roof("dome", 4.0),
            wall_colour=(0.8, 0.2, 0.1),
            holes=(((5.0, 5.0), (15.0, 5.0), (15.0, 15.0), (5.0, 15.0)),),
        ),  # counter-clockwise courtyard
        BuildingMass("prism", (330.0, 0.0), square, 12.0, roof=Roof(parapet=1.2), doors=((10.0, 0.0, 0.0, -1.0),)),
        BuildingMass(
            "prism",
            (360.0, 0.0),
            ((0.0, 0.0), (40.0, 0.0), (40.0, 20.0), (0.0, 20.0)),
            12.0,
            holes=(
                ((4.0, 4.0), (4.0, 16.0), (16.0, 16.0), (16.0, 4.0)),
                ((24.0, 4.0), (24.0, 16.0), (36.0, 16.0), (36.0, 4.0)),
            ),
        ),  # room columns over 3 rings
        BuildingMass("prism", (420.0, 0.0), round_block, 20.0),  # a curved block: one face per run
        BuildingMass("prism", (460.0, 0.0), square, 15.0, roof=Roof(parapet=0.5, seed=7), yaw=0.4),  # rooftop units
        BuildingMass(
            "prism",
            (490.0, 0.0),
            ((0.0, 0.0), (24.0, 0.0), (24.0, 10.0), (0.0, 10.0)),
            14.0,
            roof=Roof("gabled", 4.5, seed=2, attic_storey=3.2),
        ),  # dormers on both slopes
    ]


def test_odd_masses_meshed_at_once_equal_one_by_one():
    _assert_same(_odd_masses())


@pytest.mark.parametrize("blocks", [6, 12])
def test_the_district_meshed_at_once_equals_one_by_one(blocks):
    _assert_same(default_city(blocks=blocks).masses)


def test_helsinki_meshed_at_once_equals_one_by_one(helsinki_pbf):
    _assert_same(map_city(load_map(helsinki_pbf)).masses)


def test_no_masses_give_empty_arrays():
    vertices, records = batch([])
    assert len(vertices) == 0 and len(records) == 0


def test_canopies_alone_mesh_as_one_by_one():
    """A batch whose prisms all lack walls (a tile of canopies alone) has no wall edges at all."""
    canopies = [mass for mass in _odd_masses() if not mass.walls]
    assert canopies
    _assert_same(canopies)
