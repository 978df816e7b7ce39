"""The tree generator and its procedural textures: determinism, mesh validity, LODs."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cityshade.gl import srgb_to_linear
from cityshade.trees import SPECIES, bark_textures, generate_tree, leaf_textures


@pytest.mark.parametrize("name", sorted(SPECIES))
def test_same_seed_same_tree_and_other_seed_other_tree(name):
    a, b, c = (generate_tree(SPECIES[name], seed) for seed in (4, 4, 5))
    assert np.array_equal(a.lods[0].branches, b.lods[0].branches)
    assert np.array_equal(a.lods[0].cards, b.lods[0].cards)
    assert a.lods[0].branches.shape != c.lods[0].branches.shape or not np.allclose(
        a.lods[0].branches, c.lods[0].branches
    )


@settings(max_examples=6, deadline=None)
@given(name=st.sampled_from(sorted(SPECIES)), seed=st.integers(0, 10_000))
def test_mesh_is_valid(name, seed):
    tree = generate_tree(SPECIES[name], seed)
    for lod in tree.lods:
        v = lod.branches
        assert np.isfinite(v).all()
        assert lod.branch_indices.max() < len(v) and len(lod.branch_indices) % 3 == 0
        normals, tangents = v[:, 3:6], v[:, 6:9]
        assert np.allclose(np.linalg.norm(normals, axis=1), 1, atol=1e-4)
        assert np.allclose(np.linalg.norm(tangents, axis=1), 1, atol=1e-4)
        assert np.abs(np.sum(normals * tangents, axis=1)).max() < 1e-4
        # Triangles wind counter-clockwise seen from outside: face normals agree with vertex normals.
        tri = lod.branch_indices.reshape(-1, 3)
        p = v[tri, :3]
        face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        assert (np.sum(face * v[tri[:, 0], 3:6], axis=1) > -1e-9).mean() > 0.99
        assert lod.card_indices.max() < len(lod.cards)
        assert (lod.fronds.size > 0) == SPECIES[name].fronds


@pytest.mark.parametrize("name", sorted(SPECIES))
def test_no_branch_or_leaf_goes_into_the_ground(name):
    """A fir's lowest branches droop (its spread is over 90 degrees) but run along the ground
    rather than into it: seed 1's once reached 0.71 m below it."""
    lowest = {}
    for seed in range(12):
        near = generate_tree(SPECIES[name], seed).lods[0]
        lowest[seed] = min(near.branches[:, 1].min(), near.cards[:, 1].min() if len(near.cards) else np.inf)
        if near.fronds.size:
            lowest[seed] = min(lowest[seed], near.fronds[:, 1].min())
    print({seed: round(float(y), 2) for seed, y in lowest.items()})
    assert min(lowest.values()) > -0.05


@pytest.mark.parametrize("name", sorted(SPECIES))
def test_far_lod_is_lighter_and_fits_the_near_one(name):
    tree = generate_tree(SPECIES[name], 1)
    near, far = tree.lods
    assert len(far.branch_indices) < len(near.branch_indices) / 2
    assert len(far.cards) < len(near.cards)
    assert np.allclose(near.branches[:, :3].min(0), far.branches[:, :3].min(0), atol=0.3)
    assert np.allclose(near.branches[:, :3].max(0), far.branches[:, :3].max(0), atol=0.3)


def test_species_have_their_shape():
    oak, fir, poplar = (generate_tree(SPECIES[n], 2) for n in ("oak", "fir", "poplar"))
    assert poplar.height / poplar.crown_radius > 2 * oak.height / oak.crown_radius
    assert fir.height > oak.height


def test_textures_are_tileable_and_leaves_have_alpha_and_offsets():
    bark = bark_textures()
    height = bark.color_height[..., 3].astype(float)
    # Tileable: the jump across the wrap is no larger than a typical neighbour step.
    wrap = np.abs(height[:, :, 0] - height[:, :, -1]).mean()
    inner = np.abs(np.diff(height, axis=2)).mean()
    assert wrap < 3 * inner
    leaves = leaf_textures()
    alpha = leaves.color[..., 3]
    assert 0.1 < (alpha > 127).mean() < 0.7
    offsets = leaves.detail[..., 2][alpha > 127]
    assert len(np.unique(offsets)) > 20  # one constant per leaf, many leaves


@pytest.mark.parametrize("level", [2, 4, 6, 8])
def test_leaf_atlas_mips_keep_the_leaves_colour(level):
    """A box-filtered mip texel (what build_mipmaps makes) of the leaf atlas has the mean colour of
    the leaves under it, not that colour darkened by the gaps' coverage: the transparent texels
    carry leaf colour. Alpha is the leaves' coverage, untouched by the fill."""
    color = leaf_textures().color.astype(np.float64) / 255.0
    linear, alpha = srgb_to_linear(color[..., :3]), color[..., 3:]
    assert set(np.unique(alpha)) == {0.0, 1.0}
    n, block = color.shape[0] >> level, 1 << level
    mip = linear.reshape(n, block, n, block, 3).mean(axis=(1, 3))
    coverage = alpha.reshape(n, block, n, block, 1).sum(axis=(1, 3))
    leaves = (linear * alpha).reshape(n, block, n, block, 3).sum(axis=(1, 3)) / np.maximum(coverage, 1)
    seen = coverage[..., 0] > 0
    ratio = mip[seen].sum(axis=-1) / leaves[seen].sum(axis=-1)
    far = np.abs(ratio - 1) > 0.15
    assert 0.95 < np.median(ratio) < 1.05 and far.mean() < 0.05, (
        f"mip level {level}: median colour ratio to the leaves' {np.median(ratio):.3f}, "
        f"{far.sum()} of {far.size} texels off by more than 15%"
    )
