"""Exact factorisations of detail maps: SVD and BMF round trips, greedy bicliques, bit packing."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cityshade.errors import CityshadeError
from cityshade.relief import (
    METHODS,
    PAPER_FACADES,
    detail_matrices,
    factorize,
    greedy_biclique,
    pack_bits,
    paper_facade,
    unpack_bits,
)
from relief_strategies import piecewise_constant


@pytest.fixture(scope="module", params=sorted(PAPER_FACADES))
def facade_matrices(request):
    matrices, _ = detail_matrices(paper_facade(request.param))
    return matrices


@pytest.mark.parametrize("method", METHODS)
def test_paper_facades_round_trip_exactly(facade_matrices, method):
    for name, matrix in facade_matrices.items():
        factors = factorize(matrix, method, name=name)
        assert np.array_equal(factors.reconstruct(), matrix), name
        if method == "bmf":
            assert factors.x.dtype == bool and factors.y.dtype == bool
            assert np.all(factors.s == np.rint(factors.s))


@settings(max_examples=60, deadline=None)
@given(piecewise_constant(), st.sampled_from(METHODS))
def test_random_piecewise_constant_round_trip(matrix, method):
    factors = factorize(matrix, method)
    assert np.array_equal(factors.reconstruct(), matrix)


@settings(max_examples=60, deadline=None)
@given(piecewise_constant())
def test_greedy_biclique_is_complete_and_on_maximum(matrix):
    edges = matrix == matrix.max()
    rows, cols = greedy_biclique(edges, np.ones(edges.shape[0], int), np.ones(edges.shape[1], int))
    assert rows.any() and cols.any()
    assert edges[np.ix_(rows, cols)].all()


def test_biclique_prefers_the_largest_clique():
    edges = np.array([[1, 1, 0, 0], [1, 1, 1, 1], [1, 1, 1, 0], [1, 1, 0, 0]], bool)
    rows, cols = greedy_biclique(edges, np.ones(4, int), np.ones(4, int))
    assert rows.tolist() == [True, True, True, True] and cols.tolist() == [True, True, False, False]


def test_too_many_terms_is_a_clear_error():
    noise = np.random.default_rng(1).integers(0, 1000, (64, 64)).astype(np.uint16)
    with pytest.raises(CityshadeError, match="more than 16 terms"):
        factorize(noise, "bmf", max_terms=16, name="noise")


def test_zero_map_needs_no_terms():
    for method in METHODS:
        factors = factorize(np.zeros((5, 7), np.uint16), method)
        assert factors.terms == 0 and not factors.reconstruct().any()


@given(st.integers(1, 20), st.integers(0, 100), st.randoms(use_true_random=False))
def test_bit_packing_round_trip(rows, terms, rnd):
    bits = np.array([[rnd.random() < 0.3 for _ in range(terms)] for _ in range(rows)], bool).reshape(rows, terms)
    packed = pack_bits(bits)
    assert packed.dtype == np.uint32 and packed.shape == (rows, -(-terms // 32))
    assert np.array_equal(unpack_bits(packed, terms), bits)
    for k in range(terms):  # term k lives in bit k % 32 of word k // 32
        assert np.array_equal((packed[:, k // 32] >> np.uint32(k % 32)) & 1, bits[:, k])
