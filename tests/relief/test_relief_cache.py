"""The relief maps' disk cache, the city's stacked atlas and the grammar styles' window openings."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade import assets
from cityshade.assets import tile_array
from cityshade.grammar import BUILDING_STYLES, evaluate, hole_cut, library_texture, seed_vector
from cityshade.relief import (
    CACHE_ENV,
    GLASS,
    PROFILE,
    DetailMaps,
    cache_dir,
    cached_arrays,
    cached_compress,
    compress,
    generate_bay,
    relief_atlas,
    smallest_compression,
    stack_bmf,
    style_openings,
)
from cityshade.relief.testing import OPENING_DEPTH, WALL, cached_openings


@pytest.fixture()
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv(CACHE_ENV, str(tmp_path))
    return tmp_path


def test_cache_hit_change_and_damage(cache):
    bay = generate_bay()
    first, hit = cached_compress(bay, "bmf")
    assert not hit and cache_dir() == cache
    files = list(cache.glob("*.cfdm"))
    assert len(files) == 1
    again, hit = cached_compress(bay, "bmf")
    assert hit and again.digests == first.digests
    # other content: a new entry beside the first
    depth = bay.depth.copy()
    depth[0, 0] += 1
    changed = DetailMaps(depth, bay.material, bay.texel, bay.depth_unit)
    _, hit = cached_compress(changed, "bmf")
    assert not hit and len(list(cache.glob("*.cfdm"))) == 2
    # a damaged file is rebuilt and replaced
    files[0].write_bytes(files[0].read_bytes()[:-9] + b"garbage!!")
    rebuilt, hit = cached_compress(bay, "bmf")
    assert not hit and rebuilt.digests == first.digests
    assert cached_compress(bay, "bmf")[1]
    # a sound file of other maps under this name (foreign) is rebuilt too
    files[0].write_bytes(next(p for p in cache.glob("*.cfdm") if p != files[0]).read_bytes())
    foreign, hit = cached_compress(bay, "bmf")
    assert not hit and foreign.digests == first.digests


def test_smallest_compression_picks_fewer_bytes(cache):
    bay = generate_bay()
    best = smallest_compression(bay)
    sizes = {m: sum(compress(bay, m).nbytes().values()) for m in ("bmf", "svd")}
    assert sum(best.nbytes().values()) == min(sizes.values())


def test_stacked_atlas_decodes_every_part_exactly():
    atlas = relief_atlas()
    decoded = atlas.bmf.decompress()
    assert np.array_equal(decoded["depth"], atlas.maps.depth)
    assert np.array_equal(decoded["material"], atlas.maps.material)
    # every texel's free box holds the texel, and nothing in it is higher than the texel (the
    # regions narrower than the widest are padded: their padding columns are never read)
    rows, cols = atlas.maps.shape
    boxes = atlas.bmf.boxes.astype(int)[decoded["boxes"]]
    r, c = np.mgrid[:rows, :cols]
    first, width, height, _ = atlas.window_bay  # the relief bay, the window bay's opening, the grammar openings
    real = ((r < atlas.bay[2]) & (c < atlas.bay[1])) | ((r >= first) & (r < first + height) & (c < width))
    real |= (r >= first + height) & (c < PROFILE[0] + 2)
    inside = (boxes[..., 0] <= c) & (c < boxes[..., 2]) & (boxes[..., 1] <= r) & (r < boxes[..., 3])
    assert np.all(inside[real])
    for y, x in zip(*np.nonzero((atlas.maps.depth > 0) & real)):
        x0, y0, x1, y1 = boxes[y, x]
        assert atlas.maps.depth[y0:y1, x0:x1].min() >= atlas.maps.depth[y, x]


def test_stack_bmf_equals_the_parts():
    bay = generate_bay()
    other = DetailMaps(bay.depth[:20, :30].copy(), bay.material[:20, :30].copy(), bay.texel, bay.depth_unit)
    parts = [compress(bay, "bmf"), compress(other, "bmf")]
    stacked = stack_bmf(parts).decompress()
    for name in ("depth", "material"):
        assert np.array_equal(stacked[name][: bay.shape[0]], parts[0].decompress()[name])
        assert np.array_equal(stacked[name][bay.shape[0] :, :30], parts[1].decompress()[name])
    shift = len(parts[0].boxes)
    assert np.array_equal(stacked["boxes"][bay.shape[0] :, :30], parts[1].decompress()["boxes"] + shift)


@pytest.mark.parametrize("style", ["office", "brick", "fig12"])
def test_openings_line_up_with_the_flat_grammar(style):
    """A window on a face of another size than the probes: the grammar's glass at the profile's
    texel centres over that window is the profile's glass (mirrored, as mesh u runs)."""
    compiled = library_texture()
    number = next(n for n, s in BUILDING_STYLES.items() if s == style)
    openings = style_openings(compiled, style, number)
    face = (17.3, 12.9)
    tiles = tile_array(128)
    uv = (
        np.stack(np.meshgrid(np.arange(0.05, face[0], 0.1), np.arange(0.05, face[1], 0.1)), -1).reshape(-1, 2)
    ).astype(np.float32)
    building = (4, number, 0, face[1])
    result = evaluate(compiled, compiled.address(style), uv, face, seed_vector(5), tiles, building=building)
    checked = 0
    for terminal in np.unique(result.terminal[result.glass]):
        if int(terminal) not in openings.terminals:
            continue
        scope = result.scope[np.flatnonzero(result.glass & (result.terminal == terminal))[0]]
        cols, rows = PROFILE
        x = scope[0] + (np.arange(cols) + 0.5) / cols * scope[2]
        y = scope[1] + (np.arange(rows) + 0.5) / rows * scope[3]
        grid = np.stack(np.meshgrid(x, y), -1).reshape(-1, 2).astype(np.float32)
        here = evaluate(compiled, compiled.address(style), grid, face, seed_vector(5), tiles, building=building)
        glass = (here.glass & (here.terminal == terminal)).reshape(rows, cols)[:, ::-1]
        k = openings.terminals.index(int(terminal))
        region = openings.maps.material[k * (rows + 2) + 1 : (k + 1) * (rows + 2) - 1, 1:-1]
        profile = region == 1
        differ = glass != profile
        # a texel may differ only on the pane's edge in the profile (the tile is sampled at another scale)
        padded = np.pad(profile, 1, mode="edge")
        edge = np.zeros_like(profile)
        for dy, dx in ((0, 1), (2, 1), (1, 0), (1, 2)):
            edge |= padded[dy : dy + rows, dx : dx + cols] != profile
        print(
            f"{style} terminal {terminal}: scope {np.round(scope, 2)}, {int(differ.sum())} of {glass.size} "
            f"texels differ, {int((differ & ~edge).sum())} off the pane's edge"
        )
        assert not np.any(differ & ~edge)
        assert differ.sum() <= 0.03 * glass.size
        checked += 1
    assert checked > 0


def test_cached_arrays_hit_and_damage(cache):
    builds = []

    def build():
        builds.append(1)
        return {"a": np.arange(5), "b": np.ones((2, 2))}

    first = cached_arrays("t", "k", ("a", "b"), build)
    again = cached_arrays("t", "k", ("a", "b"), build)
    assert len(builds) == 1 and np.array_equal(again["a"], first["a"])
    path = next(cache.glob("t-k.npz"))
    path.write_bytes(path.read_bytes()[:40])  # truncated
    assert np.array_equal(cached_arrays("t", "k", ("a", "b"), build)["b"], first["b"]) and len(builds) == 2
    np.savez(path, other=np.zeros(1))  # a sound file of other arrays under the name
    assert set(cached_arrays("t", "k", ("a", "b"), build)) == {"a", "b"} and len(builds) == 3


def test_window_bay_opening_is_the_bay_textures_glass():
    """The window bay's opening (style 0): stretched over the bay's glass rectangle, its glass texels
    are the bay texture's glass texels, one for one, inside a ring of wall at depth 0."""
    atlas = relief_atlas()
    first, cols, rows, repeats = atlas.window_bay
    assert repeats == 0
    material = atlas.maps.material[first : first + rows, :cols]
    depth = atlas.maps.depth[first : first + rows, :cols]
    image, (u0, v0, u1, v1) = assets.facade_texture()
    size = image.shape[0]
    glass = image[round(v0 * size) : round(v1 * size), round(u0 * size) : round(u1 * size), 3] < 128
    assert glass.all() and glass.shape == (rows - 2, cols - 2)
    assert np.array_equal(material[1:-1, 1:-1] == GLASS, glass)
    ring = np.ones(material.shape, bool)
    ring[1:-1, 1:-1] = False
    assert np.all(depth[ring] == 0) and np.all(depth[1:-1, 1:-1] > 0)


def test_every_style_has_openings_and_dusks_are_holes():
    """Every grammar style of the city has window openings in the atlas (styles_with_relief_fraction
    1.0); dusk's are its holes (SkipMasks): each profile is the hole's mask over its scope, open at
    the pane's depth inside the wall, with no frame texels (frames stay on the wall plane)."""
    atlas = relief_atlas()
    compiled = library_texture()
    openings = cached_openings(compiled, "dusk", 6)
    print(
        f"compression per style {atlas.styles}; dusk's holes {openings.holes}, their atlas rows {[atlas.terminals[h] for h in openings.holes]}"
    )
    assert all(atlas.styles.values()) and set(atlas.styles) == set(BUILDING_STYLES.values())
    assert openings.holes and set(openings.holes) == set(openings.terminals)
    rows, cols = openings.region_shape
    for k, hole in enumerate(openings.holes):
        material = openings.maps.material[k * rows : (k + 1) * rows]
        depth = openings.maps.depth[k * rows : (k + 1) * rows]
        inside = np.array(
            [[(c + 0.5) / (cols - 2), (r + 0.5) / (rows - 2)] for r in range(rows - 2) for c in range(cols - 2)]
        )
        cut = hole_cut(compiled, tile_array(128), hole, inside).reshape(rows - 2, cols - 2)[:, ::-1]
        assert np.array_equal(material[1:-1, 1:-1] == GLASS, cut) and cut.sum() > 0.5 * cut.size
        assert np.all(depth[material == GLASS] == OPENING_DEPTH["glass"]) and np.all(depth[material != GLASS] == 0)
        assert np.all(material[material != GLASS] == WALL) and atlas.terminals[hole] >= 0
