"""The grammar page cache (grammar._cache): frames shaded from the cache equal the frames evaluated
per pixel within the golden-image colour tolerance, over a camera path on which pages become
resident; the id AOV is exact; a tiny atlas evicts and still draws the same picture; the pages hold
what the numpy twin evaluates at their texels; the page table finds every resident page."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.errors import UsageError
from cityshade.grammar import evaluate
from cityshade.grammar.testing import (
    BORDER,
    CONTENT,
    FINEST_TEXEL,
    MAX_PROBES,
    PAGE,
    facade_cells,
    needed_pages,
    page_hash,
    page_table,
)
from cityshade.render import Renderer, RenderSettings, frame_passes
from cityshade.scene import BUILDING_DTYPE, Camera, make_city
from golden_images import golden_difference

SIZE = (256, 192)


def walk(camera: Camera, steps: int, metres: float = 2.0) -> list[Camera]:
    """The camera moved forward (level) `metres` per step."""
    eye, target = np.array(camera.eye), np.array(camera.target)
    forward = target - eye
    forward[1] = 0.0
    forward /= np.linalg.norm(forward)
    return [
        Camera(
            tuple(eye + forward * metres * i),
            tuple(target + forward * metres * i),
            camera.fov_y,
            camera.near,
            camera.far,
        )
        for i in range(steps)
    ]


def compare_along(city, cameras, settings: RenderSettings, gl_context, pages: int = 1024) -> list[dict]:
    """Draws each camera with the cache and without, in turn; per frame the pixels that differ, the
    largest difference, the golden tolerance's verdict and the cache's counts."""
    cached = Renderer(SIZE, settings.with_(grammar_cache=True, grammar_cache_pages=pages), ctx=gl_context)
    plain = Renderer(SIZE, settings.with_(grammar_cache=False), ctx=gl_context)
    frames = []
    try:
        for renderer in (cached, plain):
            renderer.set_city(city)
        for camera in cameras:
            image, reference = cached.render(camera), plain.render(camera)
            diff = np.abs(image.astype(int) - reference.astype(int)).max(axis=2)
            frame = dict(
                differing=int(np.count_nonzero(diff)),
                max=int(diff.max()),
                verdict=golden_difference(image, reference),
                **cached.textures.grammar_pass.cache.stats,
            )
            print(frame)
            frames.append(frame)
    finally:
        cached.release()
        plain.release()
    return frames


def assert_equal_within_tolerance(frames: list[dict]):
    assert all(frame["verdict"] is None for frame in frames), frames
    assert frames[-1]["resident"] > 0 and any(frame["evaluated"] > 0 for frame in frames[1:]), frames


def test_an_atlas_without_pages_is_refused():
    with pytest.raises(UsageError, match="grammar_cache_pages must be at least 1, not 0"):
        RenderSettings(grammar_cache_pages=0)
    with pytest.raises(UsageError, match="grammar_cache_min_pixels must be 0 or more, not -1"):
        RenderSettings(grammar_cache_min_pixels=-1)


def test_cache_update_is_a_pass_of_the_deferred_frame():
    names = [p.name for p in frame_passes(RenderSettings(grammar_cache=True))]
    assert names.index("grammar g-buffer") < names.index("grammar cache update") < names.index("grammar evaluation")
    assert "grammar cache update" not in [p.name for p in frame_passes(RenderSettings(grammar_cache=False))]
    assert "grammar cache update" not in [
        p.name for p in frame_passes(RenderSettings(grammar_cache=True, grammar_deferred=False))
    ]


def test_cached_frames_equal_uncached_along_a_street(gl_context):
    city = make_city("default")
    frames = compare_along(city, walk(city.camera("street"), 4), RenderSettings(samples=0), gl_context)
    assert_equal_within_tolerance(frames)
    assert frames[-1]["requested"] > 50, frames  # the street's facades need many pages


# A fixed Helsinki street view, where the tolerance was measured (the default street view moves
# with the camera rules; on the walked street chosen today two 8x8 blocks differ by up to 15.1/255
# at the default threshold: the whole-mip filtering of docs/scale.md).
HELSINKI_STREET = Camera((153.917, 1.7, -45.531), (93.944, 7.7, -43.725))


@pytest.mark.parametrize(
    "min_pixels",
    [
        RenderSettings.grammar_cache_min_pixels,
        pytest.param(
            0,
            marks=[
                pytest.mark.slow,
                pytest.mark.xfail(
                    strict=True,
                    reason="every page cached: 1-2 8x8 blocks of obliquely seen window frames and awnings differ "
                    "by 12.7-14.3/255 on average (the limit is 12): a page filters its tiles at a whole mip level, "
                    "the per-pixel path at the pixel's own (docs/scale.md); the global parts of the tolerance hold",
                ),
            ],
        ),
    ],
)
def test_cached_frames_equal_uncached_in_helsinki(gl_context, helsinki_pbf, min_pixels):
    """With the default page threshold the cached frames hold the tolerance; with every page cached
    (threshold 0) one or two blocks break it (the expected failure)."""
    from cityshade.maps import city_from_map

    city, _, sky = city_from_map(helsinki_pbf, "street", "2025-06-21", "21:00")
    settings = RenderSettings(samples=0, grammar_cache_min_pixels=min_pixels, **sky)
    frames = compare_along(city, walk(HELSINKI_STREET, 3), settings, gl_context)
    assert_equal_within_tolerance(frames)


def test_pages_under_the_pixel_threshold_stay_per_pixel(gl_context):
    """Pages covering fewer pixels than grammar_cache_min_pixels are not evaluated: with a threshold
    over any page's pixels nothing becomes resident and the frames are the per-pixel ones; with the
    default, each frame evaluates only pages at or over it (checked against the feedback's counts)."""
    city = make_city("default")
    cameras = walk(city.camera("street"), 2)
    never = RenderSettings(samples=0, grammar_cache_min_pixels=SIZE[0] * SIZE[1] + 1)
    frames = compare_along(city, cameras, never, gl_context)
    assert all(f["verdict"] is None and f["differing"] == 0 for f in frames), frames
    assert all(f["evaluated"] == 0 and f["resident"] == 0 and f["pixels_resident"] == 0 for f in frames), frames
    renderer = Renderer(SIZE, RenderSettings(samples=0, grammar_cache=True), ctx=gl_context)
    try:
        renderer.set_city(city)
        pass_ = renderer.textures.grammar_pass
        before = np.zeros(0, np.uint64)
        for camera in cameras:
            renderer.render(camera)
            _, keys, counts = needed_pages(renderer.targets["grammar g-buffer"].read(3))
            resident = np.isin(keys, pass_.cache.slot_keys)
            evaluated = resident & ~np.isin(keys, before)  # kept pages may have fallen under it since
            assert pass_.cache.stats["pixels_resident"] == counts[resident].sum()
            assert pass_.cache.stats["evaluated"] == evaluated.sum() > 0
            assert np.all(counts[evaluated] >= RenderSettings.grammar_cache_min_pixels), counts[evaluated]
            assert counts[~resident].max() < RenderSettings.grammar_cache_min_pixels  # within the page budget
            before = pass_.cache.slot_keys.copy()
    finally:
        renderer.release()


def test_a_tiny_atlas_evicts_and_draws_the_same_picture(gl_context):
    city = make_city("default")
    # the street's pages stay in use while it is in view; the other views' frames evict them
    cameras = [*walk(city.camera("street"), 2), city.camera("corner"), city.camera("aerial")]
    frames = compare_along(city, cameras, RenderSettings(samples=0), gl_context, pages=4)
    assert_equal_within_tolerance(frames)
    assert frames[-1]["resident"] == 4 and frames[-1]["evicted"] > 0 and frames[-1]["not_resident"] > 0, frames


def test_ids_stay_exact_with_the_cache(gl_context):
    city = make_city("default")
    camera = city.camera("street")
    ids = {}
    for cache in (True, False):
        renderer = Renderer(SIZE, RenderSettings(samples=0, grammar_cache=cache), ctx=gl_context)
        try:
            renderer.set_city(city)
            renderer.render(camera)  # the cache filled first
            ids[cache] = renderer.render_ids(camera)
        finally:
            renderer.release()
    differing = int(np.count_nonzero(np.any(ids[True] != ids[False], axis=-1)))
    print("id pixels differing:", differing)
    assert differing == 0
    assert np.count_nonzero(ids[True][..., 3]) > 1000  # grammar labels are in view


def test_pages_hold_the_numpy_twins_evaluation(gl_context):
    """Labels and glass of every texel of a few resident pages against the numpy reference evaluated
    at the texels' centres (their colours are filtered; labels and glass are exact in both)."""
    city = make_city("default")
    # every page made resident, however few of the small frame's pixels it covers
    settings = RenderSettings(samples=0, grammar_cache=True, grammar_cache_min_pixels=0)
    renderer = Renderer((128, 96), settings, ctx=gl_context)
    try:
        renderer.set_city(city)
        renderer.render(city.camera("street"))
        cache = renderer.textures.grammar_pass.cache
        records = np.frombuffer(renderer.city.records.read(), BUILDING_DTYPE)
        ids = cache.atlas.read(2)[::-1]  # bottom row first, as slots are placed
        compiled, tiles = renderer.textures.grammar.compiled, renderer.textures.grammar.tiles
        checked = differing = 0
        for key, slot in list(cache.slot_of.items())[:6]:
            x, y = key & 0xFFFFFFFF, key >> 32
            building, levels, face = (x & 0x1FFFFF) - 1, x >> 24, y & 1023
            level, page = (y >> 10) & 15, np.array([(y >> 14) & 1023, y >> 24])
            texel = FINEST_TEXEL * 2.0**level
            size = face_size(renderer, key)
            i = (np.arange(PAGE) + 0.5 - BORDER)[None, :]
            u, v = np.meshgrid(page[0] * CONTENT + i[0], page[1] * CONTENT + i[0])
            uv = np.clip(np.stack([u, v], -1).reshape(-1, 2) * texel, 0.0, size)
            record = records[building]
            cells = record["facade"][2:4]
            use = (record["ids"][2] >> 8) & 0xF
            twin = evaluate(
                compiled,
                int(record["facade"][1]),
                uv.astype(np.float32),
                size,
                facade_cells(cells, face)[0] / 8.0,
                tiles,
                building=(levels, record["ids"][1], use, record["extent"][1]),
                building_seed=np.asarray(cells, float) / 8.0,
            )
            ox, oy = slot % cache.per_row * PAGE, slot // cache.per_row * PAGE
            page_ids = ids[oy : oy + PAGE, ox : ox + PAGE, 0].reshape(-1)
            gpu_label, gpu_glass = page_ids >> 2, page_ids & 1
            differing += int(np.count_nonzero((gpu_label != twin.label) | (gpu_glass != twin.glass)))
            checked += len(page_ids)
        print(f"{differing} of {checked} texels differ from the twin")
        assert checked >= 4 * PAGE * PAGE and differing <= checked * 0.002
    finally:
        renderer.release()


def face_size(renderer, key: int) -> np.ndarray:
    """A resident page's face size, as the G-buffer wrote it with the key."""
    pages = renderer.targets["grammar g-buffer"].read(3).reshape(-1, 4)
    match = pages[(pages[:, 0] == (key & 0xFFFFFFFF)) & (pages[:, 1] == (key >> 32))]
    return match[0, 2:4].view(np.float32).astype(np.float64)


@pytest.mark.parametrize("count", [1, 7, 300])
def test_the_page_table_finds_every_page(count):
    """The GLSL lookup's twin: every resident key is found within the table's probe count."""
    rng = np.random.default_rng(count)
    keys = np.stack([rng.integers(1, 2**32, count), rng.integers(0, 2**32, count)], 1).astype(np.uint32)
    table, probes = page_table(keys, np.arange(count), 1 << int(np.ceil(np.log2(2 * count))))
    assert probes <= MAX_PROBES
    mask = len(table) - 1
    for key, h, slot in zip(keys, page_hash(keys), range(count)):
        found = [table[(int(h) + i) & mask] for i in range(probes)]
        assert any(e[0] == key[0] and e[1] == key[1] and e[2] == slot for e in found)


def test_needed_pages_counts_every_pixel_of_each_page():
    """The run-length count of the feedback against a plain count over every pixel: blocks of pages
    (keys differing in x or in y only), pixels asking for none, a page whose pixels are not contiguous."""
    rng = np.random.default_rng(3)
    ys, xs = np.mgrid[0:48, 0:64]
    block = (ys // 5) * 16 + xs // 7
    requests = np.zeros((48, 64, 4), np.uint32)
    requests[..., 0] = 1 + block % 5
    requests[..., 1] = block // 5
    requests[..., 2] = 7 + block
    requests[rng.random((48, 64)) < 0.2, 0] = 0  # no page here: evaluated per pixel
    records, keys, counts = needed_pages(requests)
    flat = requests.reshape(-1, 4)
    asked = flat[flat[:, 0] != 0]
    every = asked[:, 0].astype(np.uint64) | (asked[:, 1].astype(np.uint64) << np.uint64(32))
    expected, first, expected_counts = np.unique(every, return_index=True, return_counts=True)
    np.testing.assert_array_equal(keys, expected)
    np.testing.assert_array_equal(counts, expected_counts)
    np.testing.assert_array_equal(records, asked[first])
