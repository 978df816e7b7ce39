"""The batched city's chunks (its vertex order) and the box-against-frustum test; the GPU culling
itself is tested in test_culling_gpu.py."""

from __future__ import annotations

import numpy as np

from cityshade.render._culling import BuildingChunks, boxes_visible, frustum_planes
from cityshade.scene import Camera, batch, make_city


def test_chunks_cover_every_vertex_once_and_keep_triangles_whole():
    city = make_city("default")
    vertices, _ = batch(city.masses)
    chunks = BuildingChunks(vertices)
    assert chunks.count.sum() == len(vertices)
    assert np.all(chunks.first[1:] == chunks.first[:-1] + chunks.count[:-1])
    assert np.all(chunks.count % 3 == 0)
    # every triangle's three vertices come from one building
    ids = chunks.vertices["ids"][:, 0].reshape(-1, 3)
    assert np.all(ids == ids[:, :1])
    assert len(chunks) > 10


def test_box_test_is_exact_for_clear_cases():
    camera = Camera((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), fov_y=60.0, near=0.5, far=100.0)
    planes = frustum_planes(camera.view_projection(1.0))
    lo = np.array([[-1.0, -1.0, -11.0], [-1.0, -1.0, 9.0], [50.0, -1.0, -11.0], [-1, -1, -200.0]])
    hi = lo + 2.0
    assert boxes_visible(planes, lo, hi).tolist() == [True, False, False, False]

