"""The free-box acceleration structure A: free, shared only at equal depth, same as texel-by-texel growth."""

import numpy as np
from hypothesis import given, settings

from cityshade.relief import free_boxes, paper_facade
from relief_strategies import piecewise_constant


def grow_one_texel_at_a_time(depth, r, c):
    """§4.2 literally: grow left, right, down, up by one texel while free, until none can grow."""
    rows, cols = depth.shape
    d, (x0, y0, x1, y1) = depth[r, c], (c, r, c + 1, r + 1)
    grew = True
    while grew:
        grew = False
        if x0 > 0 and depth[y0:y1, x0 - 1].min() >= d:
            x0, grew = x0 - 1, True
        if x1 < cols and depth[y0:y1, x1].min() >= d:
            x1, grew = x1 + 1, True
        if y0 > 0 and depth[y0 - 1, x0:x1].min() >= d:
            y0, grew = y0 - 1, True
        if y1 < rows and depth[y1, x0:x1].min() >= d:
            y1, grew = y1 + 1, True
    return x0, y0, x1, y1


def check_boxes(depth):
    index, boxes = free_boxes(depth)
    assert index.shape == depth.shape and int(index.max()) == len(boxes) - 1
    rows, cols = np.indices(depth.shape)
    x0, y0, x1, y1 = (boxes[index][..., k].astype(int) for k in range(4))
    assert np.all((x0 <= cols) & (cols < x1) & (y0 <= rows) & (rows < y1)), "box must contain its texel"
    for b, (bx0, by0, bx1, by1) in enumerate(boxes.astype(int)):
        owners = index == b
        d = depth[owners]
        assert np.all(d == d[0]), "a box is shared only by texels of one depth"
        assert depth[by0:by1, bx0:bx1].min() >= d[0], "no texel in a box is higher than its bottom"
    return index, boxes


@settings(max_examples=80, deadline=None)
@given(piecewise_constant(max_side=24, max_value=9))
def test_boxes_match_texel_by_texel_growth(depth):
    index, boxes = check_boxes(depth)
    # The first texel (scan order) of each box grew it.
    for b in range(len(boxes)):
        first = np.flatnonzero(index.ravel() == b)[0]
        r, c = divmod(int(first), depth.shape[1])
        assert tuple(int(v) for v in boxes[b]) == grow_one_texel_at_a_time(depth, r, c)


def test_paper_facade_boxes_are_free_and_shared():
    maps = paper_facade("F1")
    index, boxes = check_boxes(maps.depth)
    assert len(boxes) < maps.depth.size / 1000, "texels of equal depth share boxes"
