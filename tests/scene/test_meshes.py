"""Meshing footprints: walls and roof of any outline, in time linear in its vertices (the roof
no longer rescans the footprint per vertex); outlines denser than can be seen are simplified."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from cityshade.scene import SURFACE_ROOF, BuildingMass, building_vertices
from cityshade.scene.testing import OUTLINE_TOLERANCE, simplified_outline


def _wavy(n: int, radius: float) -> np.ndarray:
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = radius * (1 + 0.02 * np.sin(a * 37))
    return np.stack([radius * 1.1 + r * np.cos(a), radius * 1.1 + r * np.sin(a)], 1)


def _roof_area(vertices) -> float:
    roof = vertices["local"][vertices["ids"][:, 1] == SURFACE_ROOF][:, [0, 2]].reshape(-1, 3, 2).astype(np.float64)
    a, b, c = roof[:, 0], roof[:, 1], roof[:, 2]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    assert np.all(cross <= 0) or np.all(cross >= 0), "roof triangles wound both ways"
    return float(np.abs(cross).sum() / 2)


@pytest.mark.parametrize("n, radius", [(5, 10.0), (400, 30.0), (3000, 600.0)])
def test_outlines_seen_at_their_resolution_are_meshed_as_given(n, radius):
    pts = _wavy(n, radius)
    assert np.array_equal(simplified_outline(pts), pts)
    mass = BuildingMass("prism", (0.0, 0.0), tuple(map(tuple, pts)), 25.0)
    vertices = building_vertices(mass, 3)
    walls = vertices[vertices["ids"][:, 1] != SURFACE_ROOF]
    assert len(walls) == 6 * n and set(np.unique(walls["local"][:, 1])) == {0.0, 25.0}
    assert _roof_area(vertices) == pytest.approx(shapely.Polygon(pts).area, rel=1e-5)
    assert np.all(vertices["ids"][:, 0] == 3)


def test_dense_outlines_are_simplified_within_the_tolerance():
    pts = _wavy(50_000, 20.0)  # a vertex every 2.5 mm
    simple = simplified_outline(pts)
    assert 50 < len(simple) < 5000
    assert (
        shapely.hausdorff_distance(shapely.Polygon(pts).exterior, shapely.Polygon(simple).exterior)
        <= OUTLINE_TOLERANCE * 1.01
    )
    mass = BuildingMass("prism", (0.0, 0.0), tuple(map(tuple, pts)), 25.0)
    assert _roof_area(building_vertices(mass, 0)) == pytest.approx(shapely.Polygon(pts).area, rel=1e-3)
