"""Cascade scheduling (§4.3.2) and cascade fitting."""

import numpy as np

from cityshade.scene import Camera
from cityshade.trees import EVERY_FRAME, cascade_view_projection, cascades_due, split_distances, texture_matrix

ALL = ("buildings", "fronds", "leaves", "trunks")
NO_FRONDS = ("buildings", "leaves", "trunks")
LEAVES = ("buildings", "leaves")


def test_frames_0_to_7_redraw_the_papers_cascades_with_their_casters():
    expected = {
        0: [(0, ALL), (1, NO_FRONDS), (2, LEAVES)],  # maps start empty
        1: [(0, ALL), (1, NO_FRONDS)],
        2: [(0, ALL), (2, LEAVES)],
        3: [(0, ALL), (1, NO_FRONDS)],
        4: [(0, ALL)],
        5: [(0, ALL), (1, NO_FRONDS)],
        6: [(0, ALL), (2, LEAVES)],
        7: [(0, ALL), (1, NO_FRONDS)],
    }
    for frame, due in expected.items():
        assert [(i, tuple(sorted(c))) for i, c in cascades_due(frame)] == due
    counts = np.bincount([i for f in range(1, 9) for i, _ in cascades_due(f)], minlength=3)
    assert counts.tolist() == [8, 4, 2]  # every frame, every 2, every 4
    assert all(len(cascades_due(f, EVERY_FRAME)) == 3 for f in range(8))


def test_each_cascade_covers_its_slice_of_the_view():
    camera = Camera((0, 2, 0), (0, 2, -10), near=0.5, far=500)
    inv = np.linalg.inv(camera.view_projection(16 / 9))
    splits = split_distances(0.5, 150.0)
    assert splits[0] == 0.5 and np.isclose(splits[-1], 150.0) and np.all(np.diff(splits) > 0)
    sun = np.array([0.4, 0.6, 0.3])
    for i in range(3):
        m = texture_matrix(cascade_view_projection(inv, 0.5, 500, splits[i], splits[i + 1], sun / np.linalg.norm(sun),
                                                   1024, 100.0))
        mid = (splits[i] + splits[i + 1]) / 2
        point = m @ np.array([0.0, 2.0, -mid, 1.0])
        assert np.all((point[:3] > 0) & (point[:3] < 1))
