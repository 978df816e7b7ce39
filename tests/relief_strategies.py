"""Hypothesis strategies shared by the relief tests."""

import numpy as np
from hypothesis import strategies as st


@st.composite
def piecewise_constant(draw, max_side=40, max_value=1000):
    """A facade-like matrix: rectangles of equal values painted over a background."""
    rows, cols = draw(st.integers(1, max_side)), draw(st.integers(1, max_side))
    matrix = np.full((rows, cols), draw(st.integers(0, max_value)), np.uint16)
    for _ in range(draw(st.integers(0, 8))):
        r0, c0 = draw(st.integers(0, rows - 1)), draw(st.integers(0, cols - 1))
        r1, c1 = draw(st.integers(r0 + 1, rows)), draw(st.integers(c0 + 1, cols))
        matrix[r0:r1, c0:c1] = draw(st.integers(0, max_value))
    return matrix
