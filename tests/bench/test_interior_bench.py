"""The polygonised-interiors baseline and `cityshade bench interior` (interior-mapping §3).
Speed is never asserted: only geometry, pictures and the result's shape."""

from __future__ import annotations

import json

import numpy as np
import pytest
from PIL import Image

from cityshade.bench import write
from cityshade.bench.interior import (
    FULL,
    QUICK,
    SETTINGS,
    TARGETS,
    Plan,
    comparison_camera,
    comparison_picture,
    run_plan,
    scaled_rooms,
)
from cityshade.bench.testing import MIN_TIMED_FRAMES
from cityshade.interior import POLYGONISED_LAYERS, polygonised_vertices, quad_counts, room_grid
from cityshade.interior.testing import FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z
from cityshade.render import Renderer
from cityshade.scene import cylinder, grid_city
from render_checks import render_finite

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context


def test_apartment_block_counts():
    """Fig. 9's block: 31 storeys, 6x6 windows -> 31 floors, 31 ceilings, 2 x (6 + 6) wall quads."""
    mass = grid_city(1).masses[0]
    assert room_grid(mass) == (6, 31, 6)
    assert quad_counts(mass) == {"floors": 31, "ceilings": 31, "walls": 24}
    layers = polygonised_vertices(grid_city(3).masses)
    assert tuple(layers) == POLYGONISED_LAYERS
    for name, quads in quad_counts(mass).items():
        assert len(layers[name]) == 3 * quads * 6  # two triangles per quad, three buildings
    assert set(layers["floors"]["ids"][:, 1]) == {FACE_FLOOR}
    assert set(layers["ceilings"]["ids"][:, 1]) == {FACE_CEILING}
    assert set(layers["walls"]["ids"][:, 1]) == {FACE_WALL_X, FACE_WALL_Z}
    assert set(layers["walls"]["ids"][:, 0]) == {0, 1, 2}


def test_quads_face_their_rooms():
    """Counter-clockwise seen from the room (back faces are culled) and inside the mass."""
    mass = grid_city(1).masses[0]
    for name, vertices in polygonised_vertices([mass]).items():
        tri = vertices["local"].reshape(-1, 3, 3).astype(np.float64)
        winding = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        normal = vertices["normal"].reshape(-1, 3, 3)[:, 0]
        assert np.all(np.einsum("ij,ij->i", winding, normal) > 0), name
        assert np.all(vertices["local"] >= -1e-4) and np.all(vertices["local"] <= mass.extent + 1e-4)


def test_only_boxes():
    with pytest.raises(ValueError, match="box buildings"):
        polygonised_vertices([cylinder((0, 0), 20.0, 30.0)])


def test_scaled_rooms_keep_the_mass():
    city = grid_city(2)
    for rooms in (1_000, 4_000_000):
        scaled = scaled_rooms(city, rooms)
        nx, ny, nz = room_grid(scaled.masses[0])
        assert 0.9 * rooms <= nx * ny * nz <= 1.1 * rooms
        assert np.allclose(scaled.masses[0].extent, city.masses[0].extent)


def test_polygonised_picture_matches_interior_mapping(output_dir):
    """Same rooms, variants and lights: the pictures differ along window edges only (alpha-tested
    glass against blended glass), which at this size are a good share of the pixels."""
    renderer = Renderer((160, 120), SETTINGS)
    picture = comparison_picture(renderer, grid_city(4), comparison_camera())
    renderer.release()
    Image.fromarray(picture).save(output_dir / "interior_vs_polygonised.png")
    left, right = picture[:, :160].astype(int), picture[:, -160:].astype(int)
    differing = np.abs(left - right).max(axis=-1) > 40
    assert differing.mean() < 0.15, f"{differing.mean():.1%} of pixels differ"
    assert np.abs(left - right).mean() < 12


def test_tiny_run_writes_the_ratios(tmp_path):
    plan = Plan((64, 48), 1, (10, 1000), (0.0,), 9, 4, (1_000, 4_000_000))
    result = run_plan(plan, tmp_path)
    write(result, tmp_path, tmp_path / "out.json")
    data = json.loads((tmp_path / "out.json").read_text())
    for key in TARGETS:
        assert key in data["ratios"] and np.isfinite(data["ratios"][key]), key
        assert key in data["targets"]
    assert (tmp_path / "interior_fig9.png").exists() and (tmp_path / "interior_vs_polygonised.png").exists()
    assert [len(t["rows"]) for t in data["tables"]] == [2, 3, 3, 2, 4]
    assert data["timing"]["samples_per_point"] == 1 and data["timing"]["interleaved"] is True
    poly, im = data["methods"]["polygonised interiors"], data["methods"]["interior mapping (paper's version)"]
    assert poly["cull_back_faces"] and poly["depth_prepass"] and poly["frustum_culling"]
    assert im["depth_prepass"] and im["msaa"] == poly["msaa"] == 0 and im["size"] == poly["size"] == [64, 48]


def test_cli_plans_time_enough_frames():
    assert QUICK.rounds >= MIN_TIMED_FRAMES and FULL.rounds >= MIN_TIMED_FRAMES


@pytest.mark.parametrize("polygonised", [False, True])
def test_depth_prepass_leaves_the_picture_unchanged(gl_context, polygonised):
    """The prepass only saves shading work: both methods draw the same picture with and without it."""
    city = grid_city(4)
    renderer = Renderer((128, 96), SETTINGS.with_(polygonised_interiors=polygonised), ctx=gl_context)
    renderer.set_city(city)
    with_prepass = render_finite(renderer, comparison_camera()).astype(int)
    renderer.set_settings(renderer.settings.with_(depth_prepass=False))
    without = render_finite(renderer, comparison_camera()).astype(int)
    renderer.release()
    differing = np.abs(with_prepass - without).max(axis=-1) > 2
    print(f"prepass on vs off: {differing.sum()} of {differing.size} pixels differ by more than 2/255")
    assert with_prepass.std() > 10 and differing.mean() < 0.001
